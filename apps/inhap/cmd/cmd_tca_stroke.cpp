// `inhap tca stroke`: a simulated constant-force stroke across a mesh rendered with TCA-MESH or
// CBA (thesis sec. 5.3), written tick by tick to CSV. Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "command.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/rendering/stroke.hpp"

namespace inhap::cli {

namespace {

struct StrokeArgs {
  std::string mesh, algorithm = "tca", from, to, out;
  double force = 1.0, speed = 20.0, tremor = 0.0;
  double a_s = rendering::Params{}.a_s, a_t = rendering::Params{}.a_t;
  double stiffness = rendering::Params{}.default_stiffness;
  bool no_shading = false;
  std::uint64_t seed = 1;
};

Vec2 parse_xy(const std::string& flag, const std::string& text) {
  const auto comma = text.find(',');
  double x = 0, y = 0;
  if (comma == std::string::npos || !parse_double(text.substr(0, comma), x) ||
      !parse_double(text.substr(comma + 1), y) || !std::isfinite(x) || !std::isfinite(y))
    throw Error(
        fmt::format("{}: expected X,Y in mm (e.g. 12.5,-3), got {}", flag, quote_token(text)));
  return {x, y};
}

void run_stroke(const StrokeArgs& a) {
  rendering::Algorithm alg;
  if (a.algorithm == "tca")
    alg = rendering::Algorithm::kTCA;
  else if (a.algorithm == "cba")
    alg = rendering::Algorithm::kCBA;
  else
    throw Error(fmt::format("--algorithm: expected tca or cba, got {}", quote_token(a.algorithm)));
  rendering::StrokeOptions o;
  o.from = parse_xy("--from", a.from);
  o.to = parse_xy("--to", a.to);
  o.force_n = a.force;
  o.speed_mm_s = a.speed;
  o.tremor_n = a.tremor;
  o.seed = a.seed;
  rendering::Params params;
  params.a_s = a.a_s;
  params.a_t = a.a_t;
  params.default_stiffness = a.stiffness;
  params.force_shading = !a.no_shading;
  const rendering::Model model(read_mesh(a.mesh), params);
  const auto samples = rendering::simulate_stroke(model, alg, o);

  const std::vector<std::string> comments = {
      fmt::format(
          "inhap tca stroke --mesh {} --algorithm {} --from {} --to {} --force {} --speed {} "
          "--seed {}",
          a.mesh, a.algorithm, a.from, a.to, a.force, a.speed, a.seed),
      "units: t s; px,py,pz HIP mm; qx,qy,qz IHIP mm; cx,cy,cz CIHIP mm; fx,fy,fz force on the "
      "probe N; k N/mm; s mm; tx,ty,tz mesh compensation t mm; contact 0/1"};
  CsvWriter csv(a.out,
                {"t", "px", "py", "pz", "qx", "qy", "qz", "cx", "cy", "cz", "fx", "fy", "fz", "k",
                 "s", "tx", "ty", "tz", "contact"},
                comments);
  std::size_t contact = 0;
  double fsum = 0;
  for (const auto& e : samples) {
    csv.row({e.time, e.hip.x(), e.hip.y(), e.hip.z(), e.ihip.x(), e.ihip.y(), e.ihip.z(),
             e.cihip.x(), e.cihip.y(), e.cihip.z(), e.force.x(), e.force.y(), e.force.z(), e.k, e.s,
             e.t.x(), e.t.y(), e.t.z(), e.contact ? 1.0 : 0.0});
    contact += e.contact;
    fsum += e.contact ? e.force.norm() : 0.0;
  }
  csv.commit();
  fmt::print("{}: {} ticks ({:.3f} s), {} in contact, mean contact force {:.3f} N\n", a.out,
             samples.size(), samples.empty() ? 0.0 : samples.back().time, contact,
             contact ? fsum / double(contact) : 0.0);
}

CLI::App* tca_group(CLI::App& app) {
  // Another command file may register further `tca` subcommands: share the group.
  auto found = app.get_subcommands([](const CLI::App* s) { return s->get_name() == "tca"; });
  if (!found.empty()) return found.front();
  auto* tca = app.add_subcommand(
      "tca", "TCA-MESH and CBA haptic rendering of meshes with stiffness (thesis ch. 5)");
  tca->require_subcommand(1);
  return tca;
}

void register_stroke(CLI::App& app) {
  auto args = std::make_shared<StrokeArgs>();
  auto* cmd = tca_group(app)->add_subcommand(
      "stroke",
      "Simulate a constant-force stroke across the top of a mesh and write the trajectory.\n"
      "A force-tracking hand starts above (X,Y) at the mesh top + 5 mm, descends at 20 mm/s until\n"
      "it touches, settles at the force N, strokes in a straight line to the end point at\n"
      "--speed while holding the force (force-constancy model), then lifts off. 1 kHz servo.\n"
      "Units: positions mm, forces N, stiffness N/mm (vertex property `stiffness`), time s.\n"
      "Output CSV columns (one row per 1 ms tick, after a '# units' comment line):\n"
      "  t            time, s\n"
      "  px,py,pz     HIP p(n): the probe, mm\n"
      "  qx,qy,qz     IHIP q(n): the god-object on the (translated) mesh, mm (= HIP when free)\n"
      "  cx,cy,cz     CIHIP q'(n) = q(n) + s(n) n(n), mm (= IHIP for CBA)\n"
      "  fx,fy,fz     rendered force on the probe, N\n"
      "  k            stiffness k(n) at the IHIP, N/mm (0 when free)\n"
      "  s            point compensation s(n), mm (TCA only)\n"
      "  tx,ty,tz     mesh compensation t, mm (TCA only)\n"
      "  contact      1 in contact, 0 free");
  cmd->add_option("--mesh", args->mesh,
                  "mesh file (.ply/.obj, mm; optional vertex property stiffness in N/mm)")
      ->required();
  cmd->add_option("--algorithm", args->algorithm,
                  "tca (TCA-MESH) or cba (constraint-based god-object)")
      ->capture_default_str();
  cmd->add_option("--from", args->from, "start X,Y in mm")->required();
  cmd->add_option("--to", args->to, "end X,Y in mm")->required();
  cmd->add_option("--force", args->force, "force the hand holds, N (at most 6.2)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output CSV")->required();
  cmd->add_option("--speed", args->speed, "stroke speed, mm/s")->capture_default_str();
  cmd->add_option("--seed", args->seed, "seed of the hand's force tremor")->capture_default_str();
  cmd->add_option("--tremor", args->tremor, "RMS force tremor of the hand (10 Hz), N")
      ->capture_default_str();
  cmd->add_option("--a-s", args->a_s, "TCA height restoration slope a_s (eq. 5.11)")
      ->capture_default_str();
  cmd->add_option("--a-t", args->a_t, "TCA mesh restoration ratio a_t (eq. 5.15)")
      ->capture_default_str();
  cmd->add_option("--stiffness", args->stiffness, "stiffness for meshes without the property, N/mm")
      ->capture_default_str();
  cmd->add_flag("--no-force-shading", args->no_shading,
                "use face normals instead of interpolated vertex normals");
  cmd->callback([args] { run_stroke(*args); });
}

}  // namespace

INHAP_COMMAND(60, "tca stroke", register_stroke);

}  // namespace inhap::cli
