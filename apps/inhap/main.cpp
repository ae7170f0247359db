// inhap: modeling and transfer of inhomogeneous haptic data.
// Units everywhere: mm, N, s, N/mm.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/text.hpp"

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

void progress(const std::string& what, double fraction, double eta_s) {
  static const bool tty = ::isatty(2);
  if (!tty && fraction < 1.0) return;
  fmt::print(stderr, "{}", text::progress_line(what, fraction, eta_s, tty));
  std::fflush(stderr);
}

namespace {

std::string did_you_mean(const CLI::App& app, const std::vector<std::string>& args) {
  const CLI::App* at = &app;
  std::string path = "inhap";
  for (const auto& a : args) {
    if (a.empty() || a[0] == '-') continue;
    const auto subs = at->get_subcommands([](const CLI::App*) { return true; });
    if (subs.empty()) return {};
    const CLI::App* next = nullptr;
    for (const auto* s : subs)
      if (s->check_name(a)) next = s;
    if (next) {
      at = next;
      path += " " + next->get_name();
      continue;
    }
    // `a` stands where a subcommand of `at` is expected: the closest name, if close enough.
    std::vector<std::string> names;
    for (const auto* s : subs) names.push_back(s->get_name());
    const std::string best = text::closest(a, names);
    if (best.empty())
      return fmt::format(" ('{}' is not a subcommand of {}; see {} --help)", a.substr(0, 60), path,
                         path);
    return fmt::format(" (did you mean '{} {}'?)", path, best);
  }
  return {};
}

int parse_error_exit(const CLI::App& app, const CLI::ParseError& e,
                     const std::vector<std::string>& args) {
  fmt::print(stderr, "inhap: error: {}{}\n", text::one_line(e.what(), 300),
             did_you_mean(app, args));
  return 2;
}

}  // namespace

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
  inhap::fault::from_environment();  // tests of all-or-nothing outputs only
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --help-all, --version: exit 0
  } catch (const CLI::ParseError& e) {
    // Bad flags or arguments: one line with the inhap prefix, exit 2 (CLI11's own codes vary).
    return inhap::cli::parse_error_exit(app, e, std::vector<std::string>(argv + 1, argv + argc));
  } catch (const inhap::Error& e) {
    fmt::print(stderr, "inhap: error: {}\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr,
               "inhap: error: out of memory (an input asks for more than this machine has)\n");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "inhap: internal error: {}\n", e.what());
    return 3;
  }
  return 0;
}
