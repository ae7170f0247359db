// inhap mesh info | convert | heightmap (the work: inhap/geometry/mesh_report.hpp, heightmap.hpp).
// Units: mm, N/mm.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/mesh_report.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap::cli {
namespace {

void print_warnings(const std::string& path, const std::vector<std::string>& dropped) {
  fmt::print(stderr, "{}", dropped_properties_text(path, dropped));
}

// ------------------------------------------------------------------------------------ info
struct InfoOptions {
  std::string file, json;
};

void run_info(const InfoOptions& o) {
  const TriMesh m = read_mesh(o.file);
  fmt::print("{}", mesh_info_text(o.file, m));
  if (!o.json.empty()) write_file_atomic(o.json, mesh_info_json(o.file, m));
}

// --------------------------------------------------------------------------------- convert
struct ConvertOptions {
  std::string in, out;
  double scale_to = 0;
  bool center = false, ascii = false;
  std::string stiffness_from;
  std::vector<double> k_range;
};

void run_convert(const ConvertOptions& o) {
  TriMesh m = read_mesh(o.in);
  stiffness_from_property(m, o.stiffness_from, o.k_range);
  scale_and_center(m, o.scale_to, o.center, o.in);
  print_warnings(o.out, write_mesh(o.out, m, MeshWriteOptions{.ascii = o.ascii}));
  fmt::print("{}", mesh_written_text(o.out, m));
}

// ------------------------------------------------------------------------------- heightmap
struct HeightmapOptions {
  HeightmapMeshOptions map;
  std::string out;
  bool ascii = false;
};

void run_heightmap(const HeightmapOptions& o) {
  const HeightmapMesh h = heightmap_mesh(o.map);
  print_warnings(o.out, write_mesh(o.out, h.mesh, MeshWriteOptions{.ascii = o.ascii}));
  fmt::print("{}", heightmap_written_text(o.out, h));
}

void register_mesh(CLI::App& app) {
  auto* mesh = app.add_subcommand(
      "mesh", "Mesh files: inspect, convert, build from height maps (units: mm, N/mm)");
  mesh->require_subcommand(1);

  auto info = std::make_shared<InfoOptions>();
  auto* ci = mesh->add_subcommand(
      "info",
      "Vertex/face counts, bounding box (mm), vertex properties with min/max,\n"
      "manifold / watertight / boundary loops / orientation / components.");
  ci->add_option("FILE", info->file, "Mesh file (.ply or .obj)")->required();
  ci->add_option("--json", info->json, "Also write the report as JSON to this file");
  ci->callback([info] { run_info(*info); });

  auto conv = std::make_shared<ConvertOptions>();
  auto* cc = mesh->add_subcommand(
      "convert",
      "Convert between PLY and OBJ (by extension), optionally scale, centre and map a\n"
      "vertex property linearly onto a `stiffness` property in N/mm.");
  cc->add_option("IN", conv->in, "Input mesh (.ply or .obj)")->required();
  cc->add_option("OUT", conv->out,
                 "Output mesh (.ply keeps every vertex property; .obj keeps geometry only)")
      ->required();
  cc->add_option("--scale-to", conv->scale_to,
                 "Scale uniformly so the largest bounding-box side is MM millimetres")
      ->check(CLI::PositiveNumber);
  cc->add_flag("--center", conv->center, "Move the bounding-box centre to the origin");
  cc->add_option("--stiffness-from", conv->stiffness_from,
                 "Vertex property mapped onto `stiffness` (e.g. confidence)");
  cc->add_option("--k-range", conv->k_range,
                 "KMIN KMAX: stiffness in N/mm for the property's min and max")
      ->expected(2);
  cc->add_flag("--ascii", conv->ascii, "Write ASCII PLY instead of binary little-endian");
  cc->callback([conv] { run_convert(*conv); });

  auto hm = std::make_shared<HeightmapOptions>();
  auto* ch = mesh->add_subcommand(
      "heightmap",
      "Height map (+ optional stiffness map of the same size) -> triangle mesh.\n"
      "A WxH grid gives 2(W-1)(H-1) triangles; vertex (x*spacing, y*spacing, height).\n"
      "Grids: CSV of numbers (one row per line) or PGM (P2/P5, 8/16-bit).");
  ch->add_option("HEIGHT", hm->map.height, "Height map file; values in mm (times --height-scale)")
      ->required();
  ch->add_option("--stiffness", hm->map.stiffness,
                 "Stiffness map file, N/mm (or raw levels mapped by --k-range)");
  ch->add_option("--k-range", hm->map.k_range,
                 "KMIN KMAX: map the stiffness map's min..max linearly to N/mm")
      ->expected(2);
  ch->add_option("--stiffness-from-height", hm->map.k_from_height,
                 "KMIN KMAX: stiffness linear in height (lowest..highest), N/mm")
      ->expected(2);
  ch->add_option("--spacing", hm->map.spacing_mm, "Pixel spacing, mm")
      ->required()
      ->check(CLI::PositiveNumber);
  ch->add_option("--height-scale", hm->map.height_scale,
                 "Multiply height values by this to get mm (default 1)");
  ch->add_flag("--level", hm->map.level, "Remove the best-fitting plane (level the tilt)");
  ch->add_option("--downsample", hm->map.downsample,
                 "K: average KxK pixel blocks (spacing becomes K*spacing), e.g. 2 turns a\n"
                 "512x512 AFM scan (522,242 triangles) into 256x256 (130,050)")
      ->check(CLI::Range(1, 4096));
  ch->add_option("--out", hm->out, "Output mesh (.ply recommended: keeps `stiffness`)")->required();
  ch->add_flag("--ascii", hm->ascii, "Write ASCII PLY");
  ch->callback([hm] { run_heightmap(*hm); });
}

}  // namespace

INHAP_COMMAND(10, "mesh", register_mesh);

}  // namespace inhap::cli
