// `inhap eval sys`: sliding yield surfaces on the virtual lab (thesis 4.3, 4.5): palpate the
// planar object (9 reference points) and the dome (18), compare every elastic limit with the
// lab's true mu * f_N, then estimate the proxy of a free-exploration recording and compare it
// with the lab's true tangential anchor. Units: mm, N, s.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/sys_files.hpp"

namespace inhap::cli {
namespace {

using namespace inhap::eval;

using nlohmann::json;

struct EvalSysOptions {
  SysLabOptions lab;  // seconds, seed, quick, physics (flags)
  std::string json;
  std::string scenes = "planar,dome";
};

json eval_scene(const std::string& name, const EvalSysOptions& o) {
  SysLabOptions so = o.lab;
  so.scene = name;
  so.progress = cli::progress;
  return sys_lab_json(name, evaluate_sys_on_lab(so));
}

void run_eval_sys(const EvalSysOptions& o) {
  json objects = json::array();
  std::stringstream list(o.scenes);
  for (std::string name; std::getline(list, name, ',');)
    if (!name.empty()) objects.push_back(eval_scene(name, o));
  fmt::print("{}", sys_lab_table(objects));
  if (!o.json.empty()) write_file_atomic(o.json, json{{"objects", objects}}.dump(2) + "\n");
}

void register_eval_sys(CLI::App& app) {
  auto o = std::make_shared<EvalSysOptions>();
  auto* cmd = eval_group(app)->add_subcommand(
      "sys",
      "Sliding yield surfaces on the virtual lab (thesis 4.3): palpate `planar` (9 reference\n"
      "points) and `dome` (18), compare each elastic limit f_T with the lab's true mu * f_N, then\n"
      "estimate the proxy of a free-exploration recording and compare it with the lab's true\n"
      "tangential anchor. Units: mm, N, s.");
  cmd->add_option("--json", o->json, "write the results as JSON to this file");
  cmd->add_option("--scenes", o->scenes, "comma-separated built-in scenes")->capture_default_str();
  cmd->add_option("--seconds", o->lab.seconds, "length of the exploration recording, s")
      ->capture_default_str();
  cli::add_physics_option(*cmd, o->lab.physics, "lab contact physics: builtin | mujoco");
  cmd->add_option("--seed", o->lab.seed, "seed of the device noise and the operator")
      ->capture_default_str();
  cmd->add_flag("--quick", o->lab.quick,
                "4 (3) reference points, f_N 1 and 3 N, 4 directions, 10 s (tests)");
  cmd->callback([o] { run_eval_sys(*o); });
}

}  // namespace

INHAP_COMMAND(60, "eval sys", register_eval_sys);

}  // namespace inhap::cli
