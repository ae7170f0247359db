// Shared harness of the libFuzzer targets (one per reader, tests/fuzz/fuzz_<reader>.cpp).
// Every target feeds the input to a reader; an inhap::Error is the expected answer to bad
// input, anything else (a crash, a sanitizer report, another exception, a hang, more memory
// than -rss_limit_mb) is a finding. Readers that take a path get the bytes in a temporary file.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "inhap/core/error.hpp"

namespace inhap::fuzz {

/// A per-process temporary file named `*.ext` (the readers dispatch on the extension).
inline const std::string& temp_path(const char* ext) {
  static const std::string path = [ext] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/inhap-fuzz-" + std::to_string(::getpid()) +
           "." + ext;
  }();
  return path;
}

inline void write_temp(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
}

/// Runs `fn` and swallows inhap::Error (a clean rejection). Other exceptions escape: libFuzzer
/// reports them as crashes.
template <class Fn>
int run(Fn&& fn) {
  try {
    fn();
  } catch (const inhap::Error&) {
  }
  return 0;
}

}  // namespace inhap::fuzz

/// Defines LLVMFuzzerTestOneInput for a reader of a file with extension EXT: READ(path).
#define INHAP_FUZZ_FILE_READER(EXT, READ)                                             \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    const std::string& path = ::inhap::fuzz::temp_path(EXT);                          \
    ::inhap::fuzz::write_temp(path, data, size);                                      \
    return ::inhap::fuzz::run([&] { (void)READ(path); });                             \
  }
