// Data in and out: recordings, meshes, point sets, height and stiffness maps. Arrays handed out
// are views of the library's own storage (no copy), kept alive by the Python object.
// Units: t s, positions mm, forces N, stiffness N/mm.
#include <pybind11/stl.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "common.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/surface/point_io.hpp"

namespace inhap::py {

namespace {

const char* const kAxes[3] = {"x", "y", "z"};

// Column `name` of a recording as a view (t, px..fz, or an extra column).
pyb::array recording_column(Recording& r, const std::string& name, pyb::handle self) {
  if (name == "t") return view(r.t, self);
  for (int c = 0; c < 3; ++c) {
    if (name == std::string("p") + kAxes[c]) return column_view(r.p, c, self);
    if (name == std::string("f") + kAxes[c]) return column_view(r.f, c, self);
  }
  for (std::size_t i = 0; i < r.extra_names.size(); ++i)
    if (r.extra_names[i] == name) return view(r.extra[i], self);
  throw pyb::key_error("no column '" + name + "' in the recording");
}

std::vector<std::string> recording_names(const Recording& r) {
  std::vector<std::string> n{"t", "px", "py", "pz", "fx", "fy", "fz"};
  n.insert(n.end(), r.extra_names.begin(), r.extra_names.end());
  return n;
}

Recording make_recording(const pyb::object& t, const pyb::object& p, const pyb::object& f,
                         const pyb::dict& extra) {
  Recording r;
  r.t = to_doubles(t, "t");
  r.p = to_vec3(p, "p");
  r.f = to_vec3(f, "f");
  if (r.p.size() != r.t.size() || r.f.size() != r.t.size())
    throw pyb::type_error("t, p, f: expected the same number of rows");
  for (auto [k, v] : extra) {
    const std::string name = pyb::str(k);
    std::vector<double> col = to_doubles(v, name.c_str());
    if (col.size() != r.t.size())
      throw pyb::type_error(name + ": expected " + std::to_string(r.t.size()) + " rows");
    r.set_extra(name, std::move(col));
  }
  return r;
}

void bind_recording(pyb::module_& m) {
  pyb::class_<Recording>(m, "Recording", R"doc(
A haptic recording at device rate: t (s, shape (N,)), p probe position (mm, (N, 3)), f force on
the probe (N, (N, 3)) and extra columns by name (raw sensor rfx.. in N, proxy qx.. in mm,
normals nx.., contact flag ...). The arrays are views of the recording's own storage: writing
into them changes the recording (no copy).)doc")
      .def(pyb::init(&make_recording), pyb::arg("t"), pyb::arg("p"), pyb::arg("f"),
           pyb::arg("extra") = pyb::dict(),
           "Builds a recording from float64 arrays t (N,) s, p (N, 3) mm, f (N, 3) N and extra "
           "(name -> (N,) array); the values are copied into the recording.")
      .def_property_readonly(
          "t", [](pyb::object self) { return view(self.cast<Recording&>().t, self); },
          "Time stamps, s, (N,) view")
      .def_property_readonly(
          "p", [](pyb::object self) { return view(self.cast<Recording&>().p, self); },
          "Probe positions, mm, (N, 3) view")
      .def_property_readonly(
          "f", [](pyb::object self) { return view(self.cast<Recording&>().f, self); },
          "Forces on the probe, N, (N, 3) view")
      .def_property_readonly("columns", &recording_names, "Column names in file order")
      .def("__len__", &Recording::size)
      .def("__contains__",
           [](const Recording& r, const std::string& n) {
             const auto names = recording_names(r);
             return std::find(names.begin(), names.end(), n) != names.end();
           })
      .def(
          "__getitem__",
          [](pyb::object self, const std::string& name) {
            return recording_column(self.cast<Recording&>(), name, self);
          },
          "Column by name as a (N,) view (px is a strided view of p)")
      .def(
          "__setitem__",
          [](Recording& r, const std::string& name, const pyb::object& values) {
            std::vector<double> v = to_doubles(values, name.c_str());
            if (v.size() != r.size())
              throw pyb::type_error(name + ": expected " + std::to_string(r.size()) + " rows");
            if (name == "t") {
              r.t = std::move(v);
              return;
            }
            for (int c = 0; c < 3; ++c) {
              if (name == std::string("p") + kAxes[c]) {
                for (std::size_t i = 0; i < v.size(); ++i) r.p[i][c] = v[i];
                return;
              }
              if (name == std::string("f") + kAxes[c]) {
                for (std::size_t i = 0; i < v.size(); ++i) r.f[i][c] = v[i];
                return;
              }
            }
            r.set_extra(name, std::move(v));
          },
          "Sets or adds a column (float64 (N,), copied)")
      .def(
          "write", [](const Recording& r, const std::string& path) { write_recording(path, r); },
          pyb::arg("path"), "Writes the recording CSV atomically (t s, p mm, f N, extra columns)")
      .def("__repr__", [](const Recording& r) {
        return "<inhap.Recording " + std::to_string(r.size()) + " rows, " +
               std::to_string(7 + r.extra.size()) + " columns>";
      });
  m.def("read_recording", &read_recording, pyb::arg("path"),
        "Reads a recording CSV (header t,px,py,pz,fx,fy,fz[,...]; t s, p mm, f N). Raises "
        "inhap.Error naming the file and line on bad input.");
  m.def("write_recording", &write_recording, pyb::arg("path"), pyb::arg("recording"),
        "Writes a recording CSV atomically, with a units comment line.");
}

TriMesh make_mesh(const pyb::object& vertices, const pyb::object& faces,
                  const pyb::dict& properties) {
  TriMesh mesh;
  mesh.positions = to_vec3(vertices, "vertices");
  if (!faces.is_none()) {
    if (!pyb::isinstance<pyb::array>(faces) ||
        !pyb::reinterpret_borrow<pyb::array>(faces).dtype().is(pyb::dtype::of<std::int32_t>()))
      throw pyb::type_error("faces: expected a numpy array of int32, shape (M, 3)");
    const auto a = pyb::reinterpret_borrow<pyb::array>(faces);
    if (a.ndim() != 2 || a.shape(1) != 3 || !(a.flags() & pyb::array::c_style))
      throw pyb::type_error("faces: expected a C-contiguous int32 array of shape (M, 3)");
    const auto* tri = static_cast<const Tri*>(a.data());
    mesh.triangles.assign(tri, tri + a.shape(0));
  }
  for (auto [k, v] : properties) {
    const std::string name = pyb::str(k);
    mesh.set_property(name, to_doubles(v, name.c_str()));
  }
  mesh.validate("inhap.Mesh");
  mesh.compute_normals();
  return mesh;
}

pyb::dict mesh_properties(pyb::object self) {
  pyb::dict d;
  for (auto& [name, values] : self.cast<TriMesh&>().properties)
    d[name.c_str()] = view(values, self);
  return d;
}

void bind_mesh(pyb::module_& m) {
  pyb::class_<TriMesh>(m, "Mesh", R"doc(
A triangle mesh: vertices (mm, float64 (N, 3)), faces (int32 (M, 3), counter-clockwise seen from
outside), unit vertex normals ((N, 3)) and named per-vertex properties ((N,) each; `stiffness` in
N/mm). All arrays are views of the mesh's own storage (no copy).)doc")
      .def(pyb::init(&make_mesh), pyb::arg("vertices"), pyb::arg("faces") = pyb::none(),
           pyb::arg("properties") = pyb::dict(),
           "Builds a mesh from vertices (float64 (N, 3), mm), faces (int32 (M, 3)) and "
           "properties (name -> float64 (N,)); copied, validated, normals computed.")
      .def_property_readonly(
          "vertices", [](pyb::object self) { return view(self.cast<TriMesh&>().positions, self); },
          "Vertex positions, mm, (N, 3) view")
      .def_property_readonly(
          "faces",
          [](pyb::object self) {
            auto& t = self.cast<TriMesh&>().triangles;
            const auto n = static_cast<pyb::ssize_t>(t.size());
            return pyb::array(pyb::dtype::of<std::int32_t>(), {n, pyb::ssize_t{3}},
                              {pyb::ssize_t{sizeof(Tri)}, pyb::ssize_t{sizeof(std::int32_t)}},
                              t.empty() ? nullptr : t.front().data(), self);
          },
          "Triangles as vertex indices, int32 (M, 3) view")
      .def_property_readonly(
          "normals", [](pyb::object self) { return view(self.cast<TriMesh&>().normals, self); },
          "Unit vertex normals (N, 3) view (empty when not computed)")
      .def_property_readonly("properties", &mesh_properties,
                             "Per-vertex properties: name -> (N,) view (stiffness N/mm, ...)")
      .def(
          "set_property",
          [](TriMesh& t, const std::string& name, const pyb::object& values) {
            t.set_property(name, to_doubles(values, name.c_str()));
          },
          pyb::arg("name"), pyb::arg("values"),
          "Adds or replaces a property (float64 (N,), copied)")
      .def("compute_normals", &TriMesh::compute_normals, "Angle-weighted vertex normals")
      .def(
          "bbox",
          [](const TriMesh& t) {
            const Box3 b = t.bbox();
            return pyb::make_tuple(to_numpy(std::vector<Vec3>{b.min}).attr("reshape")(3),
                                   to_numpy(std::vector<Vec3>{b.max}).attr("reshape")(3));
          },
          "Bounding box (min, max), mm")
      .def(
          "write",
          [](const TriMesh& t, const std::string& path, bool ascii) {
            return write_mesh(path, t, MeshWriteOptions{ascii});
          },
          pyb::arg("path"), pyb::arg("ascii") = false,
          "Writes .ply (binary, or ASCII) / .obj; returns the properties the format could not "
          "store")
      .def("__repr__", [](const TriMesh& t) {
        return "<inhap.Mesh " + std::to_string(t.num_vertices()) + " vertices, " +
               std::to_string(t.num_triangles()) + " faces>";
      });
  m.def("read_mesh", &read_mesh, pyb::arg("path"),
        "Reads a .ply (ASCII or binary, every vertex property kept) or .obj mesh, mm.");
  m.def(
      "write_mesh",
      [](const std::string& path, const TriMesh& mesh, bool ascii) {
        return write_mesh(path, mesh, MeshWriteOptions{ascii});
      },
      pyb::arg("path"), pyb::arg("mesh"), pyb::arg("ascii") = false,
      "Writes a .ply (binary, or ASCII) or .obj mesh atomically; returns the names of the "
      "vertex properties the format could not store (every one for OBJ).");
}

pyb::array grid_array(Grid grid) {
  auto* g = new Grid(std::move(grid));
  pyb::capsule owner(g, [](void* p) { delete static_cast<Grid*>(p); });
  return pyb::array(
      pyb::dtype::of<double>(), {pyb::ssize_t{g->height}, pyb::ssize_t{g->width}},
      {static_cast<pyb::ssize_t>(g->width * sizeof(double)), pyb::ssize_t{sizeof(double)}},
      g->values.data(), owner);
}

Grid to_grid(const pyb::object& obj, const char* name) {
  if (!pyb::isinstance<pyb::array>(obj))
    throw pyb::type_error(std::string(name) + ": expected a 2-D numpy array of float64");
  const auto a = pyb::reinterpret_borrow<pyb::array>(obj);
  if (!a.dtype().is(pyb::dtype::of<double>()) || a.ndim() != 2 ||
      !(a.flags() & pyb::array::c_style))
    throw pyb::type_error(std::string(name) +
                          ": expected a C-contiguous float64 array of shape (H, W)");
  Grid g(static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
  std::copy_n(as_doubles(a), g.values.size(), g.values.begin());
  return g;
}

void bind_maps(pyb::module_& m) {
  m.def(
      "read_grid", [](const std::string& path) { return grid_array(read_grid(path)); },
      pyb::arg("path"),
      "Reads a height or stiffness map: CSV of numbers (one grid row per line) or PGM (P2/P5, "
      "raw levels). Returns float64 (H, W), row y, column x.");
  m.def(
      "read_wsxm_top", [](const std::string& path) { return grid_array(read_wsxm_top(path)); },
      pyb::arg("path"), "Reads a WSxM .top topography (heights in the file's units), (H, W).");
  m.def(
      "grid_to_mesh",
      [](const pyb::object& height, double spacing, const pyb::object& stiffness) {
        const Grid h = to_grid(height, "height");
        if (stiffness.is_none()) return grid_to_mesh(h, spacing);
        const Grid k = to_grid(stiffness, "stiffness");
        return grid_to_mesh(h, spacing, &k);
      },
      pyb::arg("height"), pyb::arg("spacing"), pyb::arg("stiffness") = pyb::none(),
      "Height map (mm, float64 (H, W)) -> mesh: vertex (x spacing, y spacing, height), two "
      "triangles per cell; a stiffness map (N/mm, same shape) becomes the 'stiffness' property.");
  pyb::class_<PointSet>(m, "PointSet",
                        "Points (mm, (N, 3) view) and optional unit directions ((N, 3) or empty)")
      .def_property_readonly(
          "points", [](pyb::object self) { return view(self.cast<PointSet&>().points, self); })
      .def_property_readonly("directions", [](pyb::object self) {
        return view(self.cast<PointSet&>().directions, self);
      });
  m.def("read_points", &read_points, pyb::arg("path"),
        "Reads a point PLY/OBJ (faces ignored; nx,ny,nz as directions when present), mm.");
}

}  // namespace

void register_io(pyb::module_& m) {
  bind_recording(m);
  bind_mesh(m);
  bind_maps(m);
}

}  // namespace inhap::py
