// Subcommand registry of the `inhap` program: each cmd_*.cpp registers its subcommands with
// INHAP_COMMAND(order, function); main() adds them in `order` (then name) order.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace inhap::cli {

using Register = std::function<void(CLI::App&)>;

struct CommandRegistrar {
  CommandRegistrar(int order, std::string name, Register fn);
};

/// Progress line on stderr for long work: "[what] 42% (eta 3 s)"; quiet when stderr is not a
/// terminal unless `force`.
void progress(const std::string& what, double fraction, double eta_s);

}  // namespace inhap::cli

#define INHAP_CONCAT2(a, b) a##b
#define INHAP_CONCAT(a, b) INHAP_CONCAT2(a, b)
#define INHAP_COMMAND(order, name, fn) \
  static ::inhap::cli::CommandRegistrar INHAP_CONCAT(inhap_cmd_, __LINE__)(order, name, fn)
