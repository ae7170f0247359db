// inhap: modeling and transfer of inhomogeneous haptic data.
// Units everywhere: mm, N, s, N/mm.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <vector>

#include "command.hpp"
#include "inhap/core/error.hpp"

namespace inhap::cli {

namespace {
struct Entry {
  int order;
  std::string name;
  Register fn;
};
std::vector<Entry>& registry() {
  static std::vector<Entry> r;
  return r;
}
}  // namespace

CommandRegistrar::CommandRegistrar(int order, std::string name, Register fn) {
  registry().push_back({order, std::move(name), std::move(fn)});
}

namespace {
ProgressHook& progress_hook() {
  static ProgressHook h;
  return h;
}
}  // namespace

void set_progress_hook(ProgressHook hook) {
  progress_hook() = std::move(hook);
}

void progress(const std::string& what, double fraction, double eta_s) {
  static thread_local bool in_hook = false;
  if (progress_hook() && !in_hook) {
    in_hook = true;
    progress_hook()(what, fraction, eta_s);
    in_hook = false;
    return;
  }
  static const bool tty = ::isatty(2);
  if (!tty && fraction < 1.0) return;
  fmt::print(stderr, "{}[{}] {:3.0f}%{}{}", tty ? "\r" : "", what, 100.0 * fraction,
             eta_s > 0 && fraction < 1.0 ? fmt::format(" (eta {:.0f} s)", eta_s) : std::string(),
             fraction >= 1.0 ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace inhap::cli

int main(int argc, char** argv) {
  CLI::App app{
      "inhap: modeling and transfer of inhomogeneous haptic data.\n"
      "Units everywhere: positions mm, forces N, time s, stiffness N/mm.\n"
      "Meshes are PLY (ASCII or binary, extra vertex properties kept) or OBJ; recordings are CSV\n"
      "with a header row t,px,py,pz,fx,fy,fz[,...] (t in s, p in mm, f in N)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "inhap 0.1.0");
  auto& reg = inhap::cli::registry();
  std::sort(reg.begin(), reg.end(), [](const auto& a, const auto& b) {
    return a.order < b.order || (a.order == b.order && a.name < b.name);
  });
  for (auto& e : reg) e.fn(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const inhap::Error& e) {
    fmt::print(stderr, "inhap: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "inhap: internal error: {}\n", e.what());
    return 3;
  }
  return 0;
}
