// `inhap tca stroke`: a simulated constant-force stroke across a mesh rendered with TCA-MESH or
// CBA (thesis sec. 5.3), written tick by tick to CSV. Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/rendering/stroke.hpp"
#include "inhap/rendering/stroke_csv.hpp"

namespace inhap::cli {

namespace {

struct StrokeArgs {
  std::string mesh, algorithm = "tca", from, to, out;
  rendering::StrokeOptions o;  // force_n, speed_mm_s, tremor_n, seed (flags)
  rendering::Params params;    // a_s, a_t, default_stiffness (flags)
  bool no_shading = false;
};

Vec2 parse_xy(const std::string& flag, const std::string& text) {
  Vec2 v;
  if (!parse_number_list(text, 2, v.data()) || !v.allFinite())
    throw Error(
        fmt::format("{}: expected X,Y in mm (e.g. 12.5,-3), got {}", flag, quote_token(text)));
  return v;
}

void run_stroke(const StrokeArgs& a) {
  const std::optional<rendering::Algorithm> alg = rendering::parse_algorithm(a.algorithm);
  if (!alg)
    throw Error(fmt::format("--algorithm: expected tca or cba, got {}", quote_token(a.algorithm)));
  rendering::StrokeOptions o = a.o;
  o.from = parse_xy("--from", a.from);
  o.to = parse_xy("--to", a.to);
  rendering::Params params = a.params;
  params.force_shading = !a.no_shading;
  if (!(params.default_stiffness > 0 && params.default_stiffness <= rendering::kMaxStiffnessNmm))
    throw Error(fmt::format("--stiffness: expected a stiffness in (0, {}] N/mm, got {}",
                            rendering::kMaxStiffnessNmm, params.default_stiffness));
  TriMesh mesh = read_mesh(a.mesh);
  std::optional<rendering::Model> built;
  try {
    built.emplace(std::move(mesh), params);
  } catch (const Error& e) {  // the model's checks (the stiffness map): name the file
    throw Error(fmt::format("{}: {}", a.mesh, e.what()));
  }
  const rendering::Model& model = *built;
  const auto samples = rendering::simulate_stroke(model, *alg, o);

  rendering::write_stroke_csv(
      a.out, samples,
      fmt::format(
          "inhap tca stroke --mesh {} --algorithm {} --from {} --to {} --force {} --speed {} "
          "--seed {}",
          a.mesh, a.algorithm, a.from, a.to, o.force_n, o.speed_mm_s, o.seed));
  fmt::print("{}: {}\n", a.out, rendering::stroke_summary(samples));
}

void register_stroke(CLI::App& app) {
  auto args = std::make_shared<StrokeArgs>();
  auto* cmd =
      subcommand_group(app, "tca",
                       "TCA-MESH and CBA haptic rendering of meshes with stiffness (thesis ch. 5)")
          ->add_subcommand(
              "stroke",
              "Simulate a constant-force stroke across the top of a mesh and write the "
              "trajectory.\n"
              "A force-tracking hand starts above (X,Y) at the mesh top + 5 mm, descends at 20 "
              "mm/s until\n"
              "it touches, settles at the force N, strokes in a straight line to the end point at\n"
              "--speed while holding the force (force-constancy model), then lifts off. 1 kHz "
              "servo.\n"
              "Units: positions mm, forces N, stiffness N/mm (vertex property `stiffness`), time "
              "s.\n"
              "Output CSV columns (one row per 1 ms tick, after a '# units' comment line):\n"
              "  t            time, s\n"
              "  px,py,pz     HIP p(n): the probe, mm\n"
              "  qx,qy,qz     IHIP q(n): the god-object on the (translated) mesh, mm (= HIP when "
              "free)\n"
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
  cmd->add_option("--force", args->o.force_n, "force the hand holds, N (at most 6.2)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output CSV")->required();
  cmd->add_option("--speed", args->o.speed_mm_s, "stroke speed, mm/s")->capture_default_str();
  cmd->add_option("--seed", args->o.seed, "seed of the hand's force tremor")->capture_default_str();
  cmd->add_option("--tremor", args->o.tremor_n, "RMS force tremor of the hand (10 Hz), N")
      ->capture_default_str();
  cmd->add_option("--a-s", args->params.a_s, "TCA height restoration slope a_s (eq. 5.11)")
      ->capture_default_str();
  cmd->add_option("--a-t", args->params.a_t, "TCA mesh restoration ratio a_t (eq. 5.15)")
      ->capture_default_str();
  cmd->add_option("--stiffness", args->params.default_stiffness,
                  "stiffness for meshes without the property, N/mm (at most 100; a mesh's "
                  "stiffness property likewise)")
      ->capture_default_str();
  cmd->add_flag("--no-force-shading", args->no_shading,
                "use face normals instead of interpolated vertex normals");
  cmd->callback([args] { run_stroke(*args); });
}

}  // namespace

INHAP_COMMAND(60, "tca stroke", register_stroke);

}  // namespace inhap::cli
