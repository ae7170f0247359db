// `inhap lab ...`: the virtual lab (simulated device, soft objects, operators).
// Units: mm, N, s, N/mm.
#include <fmt/format.h>

#include <chrono>
#include <memory>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/lab_files.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace {

using namespace inhap;
using namespace inhap::lab;

struct RecordArgs {
  eval::LabRecordRequest req;
  std::string scene, scene_file, out;
};

constexpr double kMaxRecordingS = 3600.0;
using eval::kBytesPerTick;

void run_scenes() {
  fmt::print("{}", eval::scenes_table());
}

void run_record(const RecordArgs& a) {
  const Scene scene = eval::pick_scene(a.scene, a.scene_file);
  const RecordSpec spec = eval::lab_record_spec(a.req);
  // Both outputs are checked before the simulation (which may take minutes) and written
  // all-or-nothing after it.
  check_output_path(a.out);
  check_output_path(truth_path_for(a.out));
  fmt::print(stderr, "{}", eval::long_recording_note(a.req.seconds));
  const auto t0 = std::chrono::steady_clock::now();
  const std::string what = fmt::format("lab record {}", scene.name);
  const LabRecording lab = eval::downsample_recording(
      record_scene(
          scene, spec,
          [&](const std::string&, double f, double) {
            const double el =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            cli::progress(what, f, f > 0 ? el * (1 - f) / f : 0);
          }),
      a.req.rate_hz, a.req.seed);
  eval::require_finite_recording(lab.rec, a.out);
  OutputTransaction tx;
  write_lab_recording(a.out, lab);
  tx.commit();
  fmt::print(stderr, "wrote {} rows to {} and {}\n", lab.rec.size(), a.out, truth_path_for(a.out));
}

void register_lab(CLI::App& app) {
  auto* lab = app.add_subcommand(
      "lab",
      "Virtual lab: simulated haptic device, soft objects with ground truth, operators.\n"
      "Units: mm, N, s, N/mm.");
  lab->require_subcommand(1);

  auto* scenes =
      lab->add_subcommand("scenes", "List the built-in scenes (stiffness at 5 N, N/mm).");
  scenes->callback(run_scenes);

  auto scene_args = std::make_shared<std::pair<std::string, std::string>>();
  auto* dump = lab->add_subcommand("scene", "Write a built-in scene as an editable JSON file.");
  dump->add_option("name", scene_args->first, "built-in scene name")->required();
  dump->add_option("--out,-o", scene_args->second, "output JSON file")->required();
  dump->callback([scene_args] {
    save_scene(scene_args->second, builtin_scene(scene_args->first));
    fmt::print(stderr, "wrote {}\n", scene_args->second);
  });

  auto a = std::make_shared<RecordArgs>();
  auto* rec = lab->add_subcommand("record",
                                  "Simulate an operator on a scene and write a recording (1 kHz, "
                                  "or --rate) (t s, p mm, f N, raw rf N)\n"
                                  "plus its ground truth beside it (OUT.truth.csv).");
  rec->add_option("--scene", a->scene, "built-in scene (see `inhap lab scenes`)");
  rec->add_option("--scene-file", a->scene_file, "scene JSON file");
  rec->add_option("--operator", a->req.op, "tap | explore | air")
      ->capture_default_str()
      ->check(CLI::IsMember({"tap", "explore", "air"}));
  rec->add_option("--seconds", a->req.seconds,
                  fmt::format("length of the recording, s (at most {:g}: about {:.0f} MB per "
                              "minute of CSV)",
                              kMaxRecordingS, 60e3 * kBytesPerTick / 1e6))
      ->capture_default_str()
      ->check(CLI::Range(0.001, kMaxRecordingS));
  rec->add_option("--seed", a->req.seed, "random seed (same seed, same bytes)")
      ->capture_default_str();
  rec->add_option("--out,-o", a->out, "output CSV (truth goes to OUT.truth.csv)")->required();
  rec->add_option("--probe", a->req.probe, "sphere (8 mm radius) | tip")
      ->capture_default_str()
      ->check(CLI::IsMember({"sphere", "tip"}));
  cli::add_physics_option(
      *rec, a->req.physics,
      "contact physics: builtin (inhap's Hunt-Crossley / anchor / Coulomb law) | "
      "mujoco (MuJoCo 2.2 soft contact, elliptic friction cone; planar, dome, "
      "hemisphere, sphere and box shapes; docs/lab-mujoco.md)");
  rec->add_option("--rate", a->req.rate_hz,
                  "logging rate, Hz (servo and physics stay at 1 kHz; below 1000 the file keeps "
                  "the tick\nnearest each instant of a logger at this rate, jittered by +-20 % of "
                  "its period, truth alike)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  rec->add_flag("--no-noise", a->req.no_noise, "no force-sensor noise in the raw reading");
  rec->add_option(
         "--region", a->req.region,
         "tap operator: reachable = every surface a stylus reaches on the object as it\n"
         "rests (tops, sides, reachable overhangs; not the base it rests on), spread evenly\n"
         "(blue noise), >= 1 tap/s (the thesis' protocol) | top = random points of the\n"
         "scene's region seen from above (the earlier top-cap protocol)")
      ->capture_default_str()
      ->check(CLI::IsMember({"reachable", "top"}));
  rec->add_flag("--whole-object", a->req.whole_object,
                "tap operator: the same as --region reachable, the default (kept for old command\n"
                "lines; an error with --region top)");
  rec->add_flag("--coverage", a->req.coverage,
                "explore operator: a training exploration that covers the object (a grid of\n"
                "spots over the region, every depth at each, slides between them; then the random\n"
                "exploration), as eval forces records its training run; see docs/force-model.md");
  rec->add_flag("--no-gravity", a->req.no_gravity, "no tool weight in the raw reading");
  rec->add_flag("--no-inertia", a->req.no_inertia, "no tool inertia in the raw reading");
  rec->callback([a] { run_record(*a); });
}

}  // namespace

INHAP_COMMAND(60, "lab", register_lab);
