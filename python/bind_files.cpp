// What the program does with files besides recordings: `mesh info | convert | from-volume`, point
// set and height / stiffness map writers, and `eval strokes` on the real data sets.
// Units: mm, N, N/mm; step times in microseconds.
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "common.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/strokes.hpp"
#include "inhap/geometry/grid_io.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/mesh_report.hpp"
#include "inhap/geometry/volume.hpp"
#include "inhap/rendering/real_data.hpp"
#include "inhap/surface/point_io.hpp"

namespace inhap::py {

namespace {

// A float64 (H, W) C-order array, else TypeError naming `name` (never copied here).
pyb::array checked_grid(const pyb::object& obj, const char* name) {
  if (!pyb::isinstance<pyb::array>(obj))
    throw pyb::type_error(std::string(name) + ": expected a 2-D numpy array of float64");
  const auto a = pyb::reinterpret_borrow<pyb::array>(obj);
  if (!a.dtype().is(pyb::dtype::of<double>()) || a.ndim() != 2 ||
      !(a.flags() & pyb::array::c_style))
    throw pyb::type_error(std::string(name) +
                          ": expected a C-contiguous float64 array of shape (H, W)");
  return a;
}

// A mesh argument: a file path (read) or an inhap.Mesh (copied).
TriMesh mesh_arg(const pyb::object& obj, std::string& name) {
  if (pyb::isinstance<pyb::str>(obj)) {
    name = obj.cast<std::string>();
    return read_mesh(name);
  }
  if (!pyb::isinstance<TriMesh>(obj))
    throw pyb::type_error("mesh: expected a mesh file path (str) or an inhap.Mesh");
  return obj.cast<const TriMesh&>();
}

void bind_mesh_files(pyb::module_& m) {
  m.def(
      "mesh_info",
      [](const pyb::object& mesh, const std::string& file) {
        std::string name = file;
        const TriMesh t = mesh_arg(mesh, name);
        pyb::object d = json_to_python(mesh_info_json(name, t));
        d["text"] = mesh_info_text(name, t);
        return d;
      },
      pyb::arg("mesh"), pyb::arg("file") = "mesh (in memory)",
      "`inhap mesh info` of a mesh (path or inhap.Mesh): vertices, faces, edges, bbox_mm, "
      "properties (min/max), manifold, watertight, oriented, boundary loops/edges, components; "
      "its --json dict plus 'text' (what it prints).");
  m.def(
      "convert_mesh",
      [](const pyb::object& mesh, const std::string& out, double scale_to, bool center,
         const std::string& stiffness_from, const std::vector<double>& k_range, bool ascii) {
        std::string name = "mesh (in memory)";
        TriMesh t = mesh_arg(mesh, name);
        stiffness_from_property(t, stiffness_from, k_range);
        scale_and_center(t, scale_to, center, name);
        std::vector<std::string> dropped;
        if (!out.empty()) dropped = write_mesh(out, t, MeshWriteOptions{.ascii = ascii});
        return pyb::make_tuple(std::move(t), dropped);
      },
      pyb::arg("mesh"), pyb::kw_only(), pyb::arg("out") = "", pyb::arg("scale_to") = 0.0,
      pyb::arg("center") = false, pyb::arg("stiffness_from") = "",
      pyb::arg("k_range") = std::vector<double>{}, pyb::arg("ascii") = false,
      "`inhap mesh convert`: scale uniformly so the largest bounding-box side is scale_to mm "
      "(0: keep), centre the box at the origin, map a vertex property (stiffness_from) linearly "
      "onto 'stiffness' in k_range (KMIN, KMAX) N/mm. Returns (new Mesh, properties the format "
      "of out could not store); out=PATH (.ply / .obj) writes it.");
  m.def(
      "mesh_from_volume",
      [](const std::string& header, double iso, double bone_iso, std::vector<double> k_range,
         double fit_mm, double far_quantile, const std::string& out, bool ascii) {
        if (k_range.size() != 2 || !(k_range[0] > 0) || !(k_range[1] >= k_range[0]))
          throw Error("k_range: expected two stiffness values 0 < min <= max in N/mm");
        HeadModelOptions ho;
        ho.skin_iso = iso;
        ho.bone_iso = bone_iso;
        ho.k_min = k_range[0];
        ho.k_max = k_range[1];
        ho.far_quantile = far_quantile;
        std::string summary;
        HeadModel head = with_progress(pyb::none(), [&](const Progress&) {
          const Volume vol = read_nrrd(header);
          HeadModel h = head_from_volume(vol, ho);
          summary = head_summary_text(h, ho, fit_head(h, fit_mm));
          if (!out.empty()) write_mesh(out, h.mesh, MeshWriteOptions{.ascii = ascii});
          return h;
        });
        return pyb::make_tuple(std::move(head.mesh), summary);
      },
      pyb::arg("header"), pyb::kw_only(), pyb::arg("iso") = 500.0, pyb::arg("bone_iso") = 1150.0,
      pyb::arg("k_range") = std::vector<double>{0.4, 1.0}, pyb::arg("fit_mm") = 100.0,
      pyb::arg("far_quantile") = 0.98, pyb::arg("out") = "", pyb::arg("ascii") = false,
      "`inhap mesh from-volume` (thesis fig. 5.3c): the skin isosurface of a CT volume (NRRD "
      "header) with 'stiffness' (N/mm, k_range) inversely proportional to the skin-to-bone "
      "distance and 'bone_distance' (mm), scaled into a fit_mm cube (0: scanner mm). Returns "
      "(Mesh, the summary it prints); out=PATH writes the mesh.");
}

void bind_writers(pyb::module_& m) {
  m.def(
      "write_points",
      [](const std::string& path, const pyb::object& points, const pyb::object& directions,
         bool ascii) {
        PointSet s;
        s.points = to_vec3(points, "points");
        if (!directions.is_none()) {
          s.directions = to_vec3(directions, "directions");
          if (s.directions.size() != s.points.size())
            throw pyb::type_error("directions: expected as many rows as points");
        }
        write_points(path, s, ascii);
      },
      pyb::arg("path"), pyb::arg("points"), pyb::arg("directions") = pyb::none(),
      pyb::arg("ascii") = false,
      "Writes a point set (float64 (N, 3), mm) and optional unit directions ((N, 3), stored as "
      "nx,ny,nz) as a PLY (binary, or ASCII) or OBJ (points only) that read_points reads back.");
  m.def(
      "write_grid",
      [](const std::string& path, const pyb::object& values) {
        const pyb::array a = checked_grid(values, "values");
        Grid g(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
        std::copy_n(as_doubles(a), g.values.size(), g.values.begin());
        write_grid(path, g);
      },
      pyb::arg("path"), pyb::arg("values"),
      "Writes a height (mm) or stiffness (N/mm) map, float64 (H, W) row y column x, as .csv "
      "(exact: read_grid gives the same values) or .pgm (16-bit; integer levels 0..65535).");
}

void bind_strokes(pyb::module_& m) {
  m.def(
      "eval_strokes",
      [](const std::string& data, const std::vector<double>& speeds, double force,
         std::uint64_t seed, bool quick, pyb::object progress) {
        const eval::StrokesConfig cfg = eval::strokes_config(speeds, force, seed, quick);
        std::string text = eval::strokes_table_header();
        const std::string json = with_progress(std::move(progress), [&](const Progress& cb) {
          const std::vector<rendering::RealDataset> sets = rendering::load_real_datasets(data);
          std::vector<eval::DatasetResult> results;
          for (const auto& ds : sets) {
            if (cb)
              cb("eval strokes: " + ds.name,
                 static_cast<double>(results.size()) / static_cast<double>(sets.size()), 0);
            const rendering::Model model(ds.mesh, cfg.params);
            results.push_back(eval::run_dataset(model, ds, cfg));
            text += eval::strokes_table_row(results.back());
          }
          return eval::to_json(results).dump();
        });
        pyb::object d = json_to_python(json);
        d["text"] = text;
        return d;
      },
      pyb::arg("data"), pyb::arg("speeds") = eval::StrokesConfig{}.speeds_mm_s,
      pyb::arg("force") = 1.0, pyb::arg("seed") = 1, pyb::arg("quick") = false,
      pyb::arg("progress") = true,
      "`inhap eval strokes` (thesis 5.3, fig. 5.7) on the real data sets in the folder `data` "
      "(afm-topography/, bunny/, headsq/): constant-force strokes (force N, speeds mm/s, the "
      "hand's tremor from seed) with TCA-MESH and CBA; per data set the shape distortion (RMS, "
      "mm), the largest height jump (mm) and the servo step p50/p99 (us). Its --json dict plus "
      "'text' (the table it prints).");
}

}  // namespace

void register_files(pyb::module_& m) {
  bind_mesh_files(m);
  bind_writers(m);
  bind_strokes(m);
}

}  // namespace inhap::py
