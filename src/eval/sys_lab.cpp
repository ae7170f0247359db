// Palpation of a virtual-lab scene (thesis 4.2-4.3) for `inhap sys palpate`, `inhap eval sys`,
// `inhap eval forces` and the demo: the probe-centre shape height field, the reference points,
// the palpation through the device interface and the fitted sliding yield surfaces.
// Units: mm, N, s.
#include "inhap/eval/sys_lab.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <numbers>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/proxy_track.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::eval {

std::vector<Vec2> reference_xy(const lab::Scene& scene, const std::string& spec_in) {
  const std::string spec =
      !spec_in.empty() ? spec_in : (scene.name == "dome" ? "rings:1,6,11" : "grid:3x3");
  const Vec2 c = scene.region.center;
  auto bad = [&] {
    return Error(
        fmt::format("--points: expected grid:RxC[:half_extent_mm], "
                    "rings:N0,N1,...[:radius_mm] or file:xy.csv, got '{}'",
                    spec));
  };
  std::vector<Vec2> out;
  if (spec.rfind("grid:", 0) == 0) {
    int rows = 0, cols = 0;
    double half = scene.region.radius;
    const int n = std::sscanf(spec.c_str() + 5, "%dx%d:%lf", &rows, &cols, &half);
    if (n < 2 || rows < 1 || cols < 1 || rows * cols > 400 || !(half > 0)) throw bad();
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j)
        out.emplace_back(c.x() + (cols > 1 ? -half + 2 * half * j / (cols - 1) : 0.0),
                         c.y() + (rows > 1 ? -half + 2 * half * i / (rows - 1) : 0.0));
  } else if (spec.rfind("rings:", 0) == 0) {
    std::string body = spec.substr(6);
    double radius = scene.region.radius;
    if (const auto colon = body.find(':'); colon != std::string::npos) {
      if (std::sscanf(body.c_str() + colon + 1, "%lf", &radius) != 1 || !(radius > 0)) throw bad();
      body.resize(colon);
    }
    std::vector<int> counts;
    for (std::size_t pos = 0; pos <= body.size();) {
      const std::size_t comma = std::min(body.find(',', pos), body.size());
      int k = 0;
      if (std::sscanf(body.substr(pos, comma - pos).c_str(), "%d", &k) != 1 || k < 1) throw bad();
      counts.push_back(k);
      pos = comma + 1;
    }
    if (counts.empty()) throw bad();
    for (std::size_t r = 0; r < counts.size(); ++r) {
      const double rr = counts.size() > 1 ? radius * r / (counts.size() - 1) : 0.0;
      for (int k = 0; k < counts[r]; ++k) {
        const double a = 2.0 * std::numbers::pi * k / counts[r];
        out.emplace_back(c.x() + rr * std::cos(a), c.y() + rr * std::sin(a));
      }
    }
  } else if (spec.rfind("file:", 0) == 0) {
    const std::string_view req[] = {"x", "y"};
    const CsvTable t = read_csv(spec.substr(5), req);
    for (std::size_t i = 0; i < t.rows(); ++i) out.emplace_back(t.column("x")[i], t.column("y")[i]);
    if (out.empty()) throw Error(fmt::format("{}: expected at least one point", spec.substr(5)));
  } else {
    throw bad();
  }
  return out;
}

TriMesh shape_height_field(const lab::Scene& sc, double probe_radius, double half) {
  const double sp = 1.0;
  const int w = static_cast<int>(std::ceil(2 * half / sp)) + 1;
  Grid g(w, w);
  const Vec2 c = sc.region.center;
  for (int i = 0; i < w; ++i)
    for (int j = 0; j < w; ++j) {
      const auto d =
          sc.object.shape().drop(c.x() - half + j * sp, c.y() - half + i * sp, probe_radius);
      g.at(j, i) = d ? d->z() : probe_radius;
    }
  TriMesh m = grid_to_mesh(g, sp);
  m.transform(1.0, Vec3(half - c.x(), half - c.y(), 0.0));
  m.compute_normals();
  return m;
}

std::vector<LimitError> limit_errors(const ScenePalpation& p) {
  std::vector<LimitError> out;
  const friction::SysModel& m = p.sys;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const double mu = p.scene.object.mu_at(m.points[i].position);
    for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j)
      for (std::size_t k = 0; k < m.angles.size(); ++k) {
        const friction::BorderResult& b = m.border(i, j, k).result;
        LimitError e;
        e.point = i, e.level = j, e.direction = k;
        e.f_limit = b.f_limit;
        e.truth = mu * m.f_normal_levels[j];
        e.rel = std::abs(b.f_limit - e.truth) / e.truth;
        e.extrapolated = b.extrapolated;
        e.measured = !b.extrapolated && !b.no_sliding;
        out.push_back(e);
      }
  }
  return out;
}

ProxyErrors proxy_errors(const ScenePalpation& r, const lab::LabRecording& lab, bool creep) {
  friction::ProxyModel model{&r.sys, r.shape.get()};
  model.creep = creep;
  const friction::ProxyColumns c = friction::proxy_track(model, lab.rec);
  ProxyErrors e;
  for (std::size_t i = 0; i < lab.rec.size(); ++i) {
    if (!lab.truth.contact[i] || !lab.truth.anchor[i].allFinite()) continue;
    e.err.push_back((c.q[i] - lab.truth.anchor[i]).norm());
    e.missed += !c.contact[i];
  }
  return e;
}

SysLabResult evaluate_sys_on_lab(const SysLabOptions& o) {
  const std::string& name = o.scene;
  ScenePalpationOptions po;
  po.scene = name;
  po.seed = o.seed;
  po.quick = o.quick;
  po.physics = o.physics;
  if (o.quick) po.points = name == "dome" ? "rings:1,3:20" : "grid:2x2:25";
  po.progress_label = "eval sys: palpate " + name;
  po.progress = o.progress;
  SysLabResult res;
  res.palpation = palpate_scene(po);
  const ScenePalpation& r = res.palpation;
  for (const LimitError& e : limit_errors(r)) {  // against the lab's mu at each reference point
    res.limit_rel.push_back(e.rel);
    if (e.measured) res.limit_rel_measured.push_back(e.rel);
  }
  // Free exploration with ground truth.
  lab::RecordSpec spec;
  spec.operator_name = "explore";
  spec.seconds = o.quick ? std::min(o.seconds, 10.0) : o.seconds;
  spec.seed = o.seed;
  spec.physics = lab::physics_from_string(o.physics);
  res.exploration_s = spec.seconds;
  const auto t0 = std::chrono::steady_clock::now();
  const lab::LabRecording lab =
      lab::record_scene(r.scene, spec, [&](const std::string&, double f, double) {
        if (!o.progress) return;
        const double el =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        o.progress("eval sys: explore " + name, f, f > 0 ? el * (1 - f) / f : 0);
      });
  res.proxy = proxy_errors(r, lab, true);
  res.proxy_rate_independent = proxy_errors(r, lab, false);
  return res;
}

friction::PalpationConfig palpation_config(bool quick) {
  friction::PalpationConfig cfg;
  if (quick) {
    cfg.normal_forces = {1.0, 3.0};
    cfg.directions = 4;
  }
  return cfg;
}

DevicePalpation palpate_points(Device& dev, const friction::MeshSurface& shape,
                               const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                               const friction::PalpationConfig& cfg, const Progress& progress,
                               const std::string& label) {
  using namespace inhap::friction;
  if (points.size() != normals.size() || points.empty())
    throw Error("palpation: expected as many normals as reference points, and at least one");
  DevicePalpation r;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  for (std::size_t i = 0; i < points.size(); ++i) {
    PalpationProtocol proto(cfg, dev.info(), static_cast<int>(i), points[i], normals[i], &shape);
    for (long n = 0; !proto.done() && n < 36'000'000; ++n) {  // 10 simulated hours
      // A device without a fresh state this tick (a late bridge datagram) gets zero force and
      // the protocol does not advance: it only ever sees real samples.
      const Vec3 f =
          dev.faulted() ? Vec3::Zero() : proto.step(dev.time(), dev.position(), dev.force_sensor());
      if (!dev.faulted()) ++r.ticks;
      dev.command_force(f);
      dev.tick();
      if (progress && n % 5000 == 0) {
        const double frac = (i + proto.progress()) / points.size();
        const double el =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        progress(label, frac, frac > 0 ? el * (1 - frac) / frac : 0);
      }
    }
    if (proto.failed() || !proto.done())
      throw Error(
          fmt::format("palpation of reference point {} at ({:.2f}, {:.2f}, {:.2f}) mm failed: {}",
                      i, points[i].x(), points[i].y(), points[i].z(),
                      proto.failed() ? proto.error() : "did not finish"));
    r.cycles.insert(r.cycles.end(), proto.cycles().begin(), proto.cycles().end());
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  if (progress) progress(label, 1.0, 0);
  return r;
}

friction::SysModel fit_palpation(const std::vector<friction::CycleRecord>& cycles,
                                 const friction::MeshSurface& shape,
                                 const friction::PalpationConfig& cfg) {
  friction::FitOptions fo;
  fo.shape = &shape;
  fo.load_damping = cfg.load_damping;
  fo.tangent_reference = cfg.tangent_reference;
  return friction::fit_sys(cycles, fo);
}

ScenePalpation palpate_scene(const ScenePalpationOptions& o) {
  using namespace inhap::friction;
  ScenePalpation r;
  if (!o.scene.empty() && !o.scene_file.empty())
    throw Error("give either --scene or --scene-file, not both");
  r.scene = !o.scene_file.empty() ? lab::load_scene(o.scene_file)
                                  : lab::builtin_scene(o.scene.empty() ? "planar" : o.scene);
  lab::DeviceParams dp;
  dp.seed = o.seed;
  dp.physics = lab::physics_from_string(o.physics);
  lab::SimDevice dev(r.scene.object, dp);
  dev.detach_hand();
  const double radius = dev.probe_radius();
  const std::vector<Vec2> xy = reference_xy(r.scene, o.points);
  double half = r.scene.region.radius + 15.0;
  for (const Vec2& p : xy)
    half = std::max(half, (p - r.scene.region.center).cwiseAbs().maxCoeff() + 15.0);
  r.shape_mesh = shape_height_field(r.scene, radius, half);
  r.shape = std::make_unique<MeshSurface>(r.shape_mesh, 0.0);
  for (const Vec2& p : xy) {
    const auto d = r.scene.object.shape().drop(p.x(), p.y(), radius);
    if (!d)
      throw Error(fmt::format("reference point ({:g}, {:g}) misses the object", p.x(), p.y()));
    Vec3 c, n;
    if (!r.shape->closest(*d, c, n)) throw Error("shape mesh: no closest point");
    r.points.push_back(c);
    r.normals.push_back(n);
  }
  const PalpationConfig cfg = palpation_config(o.quick);
  dev.place(r.points.front() + (cfg.hover + 3.0) * r.normals.front());
  DevicePalpation d =
      palpate_points(dev, *r.shape, r.points, r.normals, cfg, o.progress, o.progress_label);
  r.cycles = std::move(d.cycles);
  r.ticks = d.ticks;
  r.wall_s = d.wall_s;
  r.cpu_s = d.cpu_s;
  r.sys = fit_palpation(r.cycles, *r.shape, cfg);
  return r;
}

}  // namespace inhap::eval
