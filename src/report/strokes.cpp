// inhap demo: TCA-MESH vs CBA stroke pairs and their figures. Units: mm, N, s, N/mm.
#include "inhap/report/strokes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "inhap/core/csv.hpp"

namespace inhap::report {
namespace {

// Distance along the stroke, mm.
double along(const StrokeCase& sc, const Vec3& p) {
  const Vec2 d = (sc.to - sc.from).normalized();
  return (Vec2(p.x(), p.y()) - sc.from).dot(d);
}

double distortion(const StrokeCase& sc, const std::vector<rendering::StrokeSample>& s) {
  const double len = (sc.to - sc.from).norm();
  std::vector<double> e;
  for (const auto& x : s) {
    const double u = along(sc, x.hip);
    if (!x.contact || u < 1.0 || u > len - 1.0) continue;
    const double ref = sc.truth ? sc.truth(x.hip.x(), x.hip.y()) : x.ihip.z();
    if (std::isfinite(ref)) e.push_back(x.hip.z() - ref);
  }
  if (e.empty()) return 0;
  double mean = 0, sq = 0;
  for (double v : e) mean += v / double(e.size());
  for (double v : e) sq += (v - mean) * (v - mean);
  return std::sqrt(sq / double(e.size()));
}

nlohmann::json trace(const std::vector<double>& u, const std::vector<double>& z,
                     const std::string& name, const std::string& color, const std::string& dash,
                     double width = 1.8) {
  return {{"type", "scatter"}, {"mode", "lines"},
          {"x", series(u)},    {"y", series(z)},
          {"name", name},      {"line", {{"color", color}, {"dash", dash}, {"width", width}}}};
}

// Blue (low) to red (high) through white, 0 <= v <= 1.
std::array<double, 3> ramp(double v) {
  v = std::clamp(v, 0.0, 1.0);
  if (v < 0.5) return {0.2 + 1.6 * v * 0.5, 0.35 + 1.3 * v * 0.5, 0.85 + 0.3 * v * 0.5};
  const double w = v - 0.5;
  return {1.0 - 0.2 * w, 0.8 - 1.3 * w, 1.0 - 1.7 * w};
}

}  // namespace

void sliding_heights(const std::vector<rendering::StrokeSample>& s, const Vec2& from,
                     const Vec2& dir, double len, int which, std::vector<double>& u,
                     std::vector<double>& z) {
  std::size_t n = 0;
  for (const auto& x : s) n += x.contact;
  const std::size_t stride = std::max<std::size_t>(1, n / 600);
  std::size_t k = 0;
  for (const auto& x : s) {
    if (!x.contact || k++ % stride) continue;
    const double a = (Vec2(x.hip.x(), x.hip.y()) - from).dot(dir);
    if (a < 0.2 || a > len - 0.2) continue;  // the sliding part (not the descent or lift)
    const Vec3& p = which == 0 ? x.hip : which == 1 ? x.ihip : x.cihip;
    u.push_back(a);
    z.push_back(p.z());
  }
}

StrokePair run_stroke_pair(const rendering::Model& model, const StrokeCase& sc,
                           std::uint64_t seed) {
  rendering::StrokeOptions o;
  o.from = sc.from;
  o.to = sc.to;
  o.force_n = sc.force_n;
  o.seed = seed;
  StrokePair p;
  p.tca = rendering::simulate_stroke(model, rendering::Algorithm::kTCA, o);
  p.cba = rendering::simulate_stroke(model, rendering::Algorithm::kCBA, o);
  p.distortion_tca = distortion(sc, p.tca);
  p.distortion_cba = distortion(sc, p.cba);
  return p;
}

Figure stroke_figure(const StrokeCase& sc, const StrokePair& p, const std::string& id,
                     const std::string& title) {
  Figure f{id,
           title,
           fmt::format("Constant-force stroke ({} N, 20 mm/s) across {}: heights of the HIP p "
                       "(what the hand feels), the IHIP q and the CIHIP q' for TCA-MESH and CBA{}. "
                       "Shape distortion RMS: TCA-MESH {:.3f} mm, CBA {:.3f} mm.",
                       sc.force_n, sc.name, sc.truth ? ", and the true surface" : "",
                       p.distortion_tca, p.distortion_cba),
           "plotly",
           {}};
  nlohmann::json data = nlohmann::json::array();
  if (sc.truth) {
    std::vector<double> u, z;
    const double len = (sc.to - sc.from).norm();
    const Vec2 d = (sc.to - sc.from).normalized();
    for (double a = 0; a <= len; a += len / 300) {
      const Vec2 q = sc.from + a * d;
      const double h = sc.truth(q.x(), q.y());
      if (!std::isfinite(h)) continue;
      u.push_back(a);
      z.push_back(h);
    }
    data.push_back(trace(u, z, "true surface", "#000000", "solid", 2.5));
  }
  const char* names[] = {"HIP p", "IHIP q", "CIHIP q'"};
  const char* dashes[] = {"solid", "dot", "dash"};
  for (int w = 0; w < 3; ++w) {
    std::vector<double> u, z;
    sliding_heights(p.tca, sc.from, (sc.to - sc.from).normalized(), (sc.to - sc.from).norm(), w, u,
                    z);
    data.push_back(trace(u, z, fmt::format("TCA-MESH {}", names[w]), "#1f77b4", dashes[w]));
  }
  for (int w = 0; w < 2; ++w) {
    std::vector<double> u, z;
    sliding_heights(p.cba, sc.from, (sc.to - sc.from).normalized(), (sc.to - sc.from).norm(), w, u,
                    z);
    data.push_back(trace(u, z, fmt::format("CBA {}", names[w]), "#ff7f0e", dashes[w]));
  }
  f.spec["data"] = data;
  f.spec["layout"] = {{"xaxis", {{"title", {{"text", "distance along the stroke (mm)"}}}}},
                      {"yaxis", {{"title", {{"text", "height z (mm)"}}}}}};
  return f;
}

void write_stroke_csv(const std::string& path, const StrokePair& p) {
  const std::vector<std::string> units = {
      "units: algorithm 0 = TCA-MESH, 1 = CBA; t s; p HIP, q IHIP, c CIHIP in mm; f N; k N/mm"};
  CsvWriter csv(path,
                {"algorithm", "t", "px", "py", "pz", "qx", "qy", "qz", "cx", "cy", "cz", "fx", "fy",
                 "fz", "k", "contact"},
                units);
  for (int a = 0; a < 2; ++a)
    for (const auto& e : a == 0 ? p.tca : p.cba)
      csv.row({double(a), e.time, e.hip.x(), e.hip.y(), e.hip.z(), e.ihip.x(), e.ihip.y(),
               e.ihip.z(), e.cihip.x(), e.cihip.y(), e.cihip.z(), e.force.x(), e.force.y(),
               e.force.z(), e.k, e.contact ? 1.0 : 0.0});
  csv.commit();
}

nlohmann::json colored_mesh_json(const TriMesh& mesh, const std::vector<double>& values, double lo,
                                 double hi, const Vec3& offset) {
  const double span = std::max(hi - lo, 1e-12);
  nlohmann::json pos = nlohmann::json::array(), col = nlohmann::json::array(),
                 idx = nlohmann::json::array();
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    for (int a = 0; a < 3; ++a) pos.push_back(rnd(mesh.positions[i][a] + offset[a], 2));
    const double v = i < values.size() && std::isfinite(values[i]) ? values[i] : lo;
    for (double c : ramp((v - lo) / span)) col.push_back(rnd(c, 2));
  }
  for (const auto& t : mesh.triangles)
    for (int a = 0; a < 3; ++a) idx.push_back(t[a]);
  return {{"positions", pos}, {"colors", col}, {"indices", idx}};
}

Figure mesh_figure(const TriMesh& mesh, const std::string& property,
                   const std::vector<StrokeLine>& lines, const std::string& id,
                   const std::string& title, const std::string& caption) {
  Figure f{id, title, caption, "three", {}};
  std::vector<double> v;
  if (!property.empty() && mesh.has_property(property)) {
    v = mesh.property(property);
  } else {
    for (const auto& p : mesh.positions) v.push_back(p.z());
  }
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  f.spec["meshes"] = nlohmann::json::array({colored_mesh_json(mesh, v, *lo, *hi)});
  f.spec["lines"] = nlohmann::json::array();
  const Box3 box = mesh.bbox();
  const double radius = 0.006 * (box.max - box.min).norm();  // tube radius, lifted by as much
  f.spec["line_radius"] = rnd(radius, 3);
  for (const auto& l : lines) {
    nlohmann::json pts = nlohmann::json::array();
    std::size_t n = 0;
    for (const auto& s : l.samples) n += s.contact;
    const std::size_t stride = std::max<std::size_t>(1, n / 400);
    std::size_t k = 0;
    Vec3 last = Vec3::Constant(std::numeric_limits<double>::infinity());
    for (const auto& s : l.samples) {
      if (!s.contact || k++ % stride) continue;
      // Repeated points (the settle at the start) would break the tube's curve.
      if ((s.ihip - last).norm() < 0.05) continue;
      last = s.ihip;
      for (int a = 0; a < 3; ++a) pts.push_back(rnd(s.ihip[a] + (a == 2 ? radius : 0), 2));
    }
    f.spec["lines"].push_back({{"points", pts}, {"color", l.color}});
  }
  return f;
}

}  // namespace inhap::report
