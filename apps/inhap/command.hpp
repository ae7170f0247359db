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

/// The subcommand group `name` (e.g. "eval", "mesh", "tca"), created with `description` by the
/// first command file that registers into it; later files reuse it (registration order varies).
inline CLI::App* subcommand_group(CLI::App& app, const std::string& name,
                                  const std::string& description) {
  auto found = app.get_subcommands([&](const CLI::App* s) { return s->get_name() == name; });
  if (!found.empty()) return found.front();
  auto* group = app.add_subcommand(name, description);
  group->require_subcommand(1);
  return group;
}

/// The "eval" group: evaluations that reproduce the thesis' figures.
inline CLI::App* eval_group(CLI::App& app) {
  return subcommand_group(app, "eval",
                          "Evaluations that reproduce the thesis' figures (units: mm, N, N/mm, s)");
}

/// `--physics builtin|mujoco`: the lab's contact physics (docs/lab-mujoco.md); `what` is the help.
inline CLI::Option* add_physics_option(CLI::App& cmd, std::string& physics,
                                       const std::string& what) {
  return cmd.add_option("--physics", physics, what)
      ->capture_default_str()
      ->check(CLI::IsMember({"builtin", "mujoco"}));
}

/// A boolean set by a pair of flags --NAME and --no-NAME. The help marks the one that matches
/// the default (CLI11's "--x,!--no-x" shows `{false}`, read as the default, for a default on).
/// `mark_default` false: `what` already says the default.
inline void add_switch(CLI::App& cmd, const std::string& name, bool& value, const std::string& what,
                       bool mark_default = true) {
  const bool on = value;
  cmd.add_flag_callback(
      "--" + name, [&value] { value = true; },
      what + (!mark_default ? ""
              : on          ? " (default)"
                            : " (default: off)"));
  cmd.add_flag_callback(
      "--no-" + name, [&value] { value = false; },
      "Turn --" + name + " off" + (on ? "" : " (the default)"));
}

/// Progress line on stderr for long work: "[what] 42% (eta 3 s)"; on a terminal updated in
/// place, otherwise only the final line (fraction 1). Matches eval::Progress.
void progress(const std::string& what, double fraction, double eta_s);

}  // namespace inhap::cli

#define INHAP_CONCAT2(a, b) a##b
#define INHAP_CONCAT(a, b) INHAP_CONCAT2(a, b)
#define INHAP_COMMAND(order, name, fn) \
  static ::inhap::cli::CommandRegistrar INHAP_CONCAT(inhap_cmd_, __COUNTER__)(order, name, fn)
