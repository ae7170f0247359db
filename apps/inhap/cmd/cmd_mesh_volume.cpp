// inhap mesh from-volume: the CT head of thesis fig. 5.3c — skin isosurface of a NRRD volume
// with stiffness 0.4-1.0 N/mm inversely proportional to the skin-to-bone distance, scaled into a
// cube. Units: mm, N/mm.
#include <fmt/format.h>

#include <memory>

#include "command.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/mesh_report.hpp"
#include "inhap/geometry/volume.hpp"

namespace inhap::cli {
namespace {

struct FromVolumeOptions {
  std::string header, out;
  double iso = 500, bone_iso = 1150;
  std::vector<double> k_range{0.4, 1.0};
  double fit_mm = 100;
  double far_quantile = 0.98;
  bool ascii = false;
};

void run_from_volume(const FromVolumeOptions& o) {
  if (o.k_range.size() != 2 || !(o.k_range[0] > 0) || !(o.k_range[1] >= o.k_range[0]))
    throw Error(
        fmt::format("--k-range: expected two stiffness values 0 < min <= max in N/mm, got {}",
                    fmt::join(o.k_range, " ")));
  if (!(o.fit_mm >= 0))
    throw Error(fmt::format("--fit-mm: expected a size >= 0 mm (0 keeps the scanner's mm), got {}",
                            o.fit_mm));
  const Volume vol = read_nrrd(o.header);
  HeadModelOptions ho;
  ho.skin_iso = o.iso;
  ho.bone_iso = o.bone_iso;
  ho.k_min = o.k_range[0];
  ho.k_max = o.k_range[1];
  ho.far_quantile = o.far_quantile;
  // Every error names the volume: an absurd spacing, or no isosurface at the level asked for.
  const auto named = [&](auto&& fn) {
    try {
      return fn();
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", o.header, e.what()));
    }
  };
  if (!(vol.spacing.minCoeff() > 0) || !(vol.spacing.maxCoeff() <= 1e6))
    throw Error(fmt::format("{}: expected spacings in (0, 1e6] mm, got {} x {} x {}", o.header,
                            vol.spacing.x(), vol.spacing.y(), vol.spacing.z()));
  HeadModel head = named([&] { return head_from_volume(vol, ho); });
  const double scale = named([&] { return fit_head(head, o.fit_mm); });
  fmt::print("volume      {} x {} x {} samples, spacing {} x {} x {} mm\n", vol.nx, vol.ny, vol.nz,
             vol.spacing.x(), vol.spacing.y(), vol.spacing.z());
  const TriMesh& m = head.mesh;
  fmt::print("{}", head_summary_text(head, ho, scale));
  MeshWriteOptions wo;
  wo.ascii = o.ascii;
  fmt::print(stderr, "{}", dropped_properties_text(o.out, write_mesh(o.out, m, wo)));
  fmt::print("wrote       {}\n", o.out);
}

void register_from_volume(CLI::App& app) {
  auto opt = std::make_shared<FromVolumeOptions>();
  auto* cmd =
      subcommand_group(
          app, "mesh",
          "Mesh files: inspect, convert, build from height maps and volumes (units: mm, N/mm)")
          ->add_subcommand("from-volume",
                           "CT volume (NRRD header, raw slices) -> skin isosurface mesh "
                           "with a `stiffness` vertex property\n"
                           "(N/mm) inversely proportional to the distance from the skin "
                           "to the bone isosurface (thesis fig. 5.3c),\n"
                           "plus `bone_distance` (mm of the written mesh). Marching "
                           "tetrahedra, largest component, outward normals,\n"
                           "scaled into a --fit-mm cube. Units: mm, N/mm.");
  cmd->add_option("header", opt->header, "NRRD header (.nhdr or .nrrd)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--iso", opt->iso, "Skin iso value (CT number)")->capture_default_str();
  cmd->add_option("--bone-iso", opt->bone_iso, "Bone iso value (CT number)")->capture_default_str();
  cmd->add_option("--k-range", opt->k_range, "Stiffness range MIN MAX, N/mm")
      ->expected(2)
      ->capture_default_str();
  cmd->add_option("--fit-mm", opt->fit_mm,
                  "Scale so the largest side is this many mm (0: keep scanner mm)")
      ->capture_default_str();
  cmd->add_option("--far-quantile", opt->far_quantile,
                  "Distance quantile that gets the minimum stiffness")
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Output mesh (.ply keeps the properties; .obj drops them)")
      ->required();
  cmd->add_flag("--ascii", opt->ascii, "Write ASCII PLY instead of binary");
  cmd->callback([opt] { run_from_volume(*opt); });
}

}  // namespace

// After the lead's `mesh` group (order 10) so the group exists; created here otherwise.
INHAP_COMMAND(20, "mesh from-volume", register_from_volume);

}  // namespace inhap::cli
