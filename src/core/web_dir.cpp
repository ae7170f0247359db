#include "inhap/core/web_dir.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <vector>

#include "inhap/core/error.hpp"

namespace inhap {

namespace fs = std::filesystem;

std::vector<fs::path> beside_program(const std::string& name) {
  std::vector<fs::path> candidates;
  std::array<char, 4096> buf{};
  const ssize_t n = ::readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n > 0) {
    fs::path d = fs::path(std::string(buf.data(), std::size_t(n))).parent_path();
    for (int up = 0; up < 5 && !d.empty(); ++up, d = d.parent_path()) {
      candidates.push_back(d / name);
      candidates.push_back(d / "share/inhap" / name);
    }
  }
  candidates.push_back(fs::current_path() / name);
  return candidates;
}

std::string find_web_dir(const std::string& given, const std::function<bool(const fs::path&)>& has,
                         const std::string& what) {
  std::vector<fs::path> candidates;
  if (!given.empty()) {
    candidates.push_back(given);
  } else if (const char* env = std::getenv("INHAP_WEB_DIR"); env && *env) {
    candidates.push_back(env);
  } else {
    candidates = beside_program("web");
  }
  for (const fs::path& c : candidates)
    if (has(c)) return c.string();
  throw Error(fmt::format(
      "cannot find {} (looked in {}{}): give --web-dir DIR or set INHAP_WEB_DIR, and run ./run "
      "setup",
      what, candidates.empty() ? std::string("nothing") : candidates.front().string(),
      candidates.size() > 1 ? fmt::format(" and {} more", candidates.size() - 1) : ""));
}

}  // namespace inhap
