// Runs the `inhap` program built alongside the tests and captures its output and exit status.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace inhap::test {

struct CliResult {
  int status = -1;  ///< exit code
  std::string out;  ///< stdout and stderr, interleaved
};

/// `args` is appended to the program path as is (quote paths yourself if they contain spaces);
/// `env` (e.g. "NAME=value") is put before it, for the program's environment.
inline CliResult run_cli(const std::string& args, const std::string& env = {}) {
  CliResult r;
  std::string cmd = (env.empty() ? "" : env + " ") + std::string(INHAP_CLI) + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  int st = ::pclose(pipe);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace inhap::test
