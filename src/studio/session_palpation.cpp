// inhap studio session: the palpation view (thesis 4.3.2; session.hpp, palpation.hpp).
// The page picks reference points on the probe-centre shape; `palpate` runs the library's
// protocol on the device inside the servo loop (settings of `sys palpate`, quick or full); each
// finished cycle is broadcast (fig. 4.7); when the sweep ends the streamer fits the sliding yield
// surfaces with the code of `sys palpate` (eval::fit_palpation) and broadcasts them (fig. 4.8);
// `save_sys` writes sys.json and the cycles CSV into the workspace with the writers of
// `sys palpate` and reads sys.json back.
#include <fmt/format.h>

#include <algorithm>

#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/studio/display.hpp"
#include "inhap/studio/session.hpp"

namespace inhap::studio {

// Called with the rig stopped. The lab's shape is built once; a real device's is the latest
// reconstruction.
void Session::ensure_palpation_shape() {
  if (!palp_mesh_ || !lab_) {
    if (lab_) {
      // The probe-centre height field of the scene (1 mm grid), as `sys palpate` builds it.
      const double radius = lab::DeviceParams{}.probe.radius_mm;
      palp_mesh_ = std::make_unique<TriMesh>(
          eval::shape_height_field(scene_, radius, scene_.region.radius + 15.0));
    } else {
      if (!reconstruction_)
        throw ProtocolError(
            "palpation: reconstruct the shape in the sampling view first (a real device needs a "
            "shape to palpate)");
      palp_mesh_ = std::make_unique<TriMesh>(*reconstruction_);
      palp_mesh_->compute_normals();
    }
    palp_shape_ = std::make_unique<friction::MeshSurface>(*palp_mesh_, 0.0);
  }
  broadcast_(mesh_json(top_view_mesh(*palp_mesh_, ""), "palpation", ""));
}

std::string Session::do_palpate(const Message& m) {
  const auto& pts = m.body.find("points");
  if (pts == m.body.end() || !pts->is_array() || pts->empty() || pts->size() > 50)
    throw ProtocolError("palpate: expected \"points\": a list of 1-50 [x, y, z] (mm)");
  const bool quick = get_bool_or(m, "quick", true);
  const double speed = get_number_or(m, "speed", 0.1, 20, options_.speed);
  if (!palp_shape_) throw ProtocolError("palpate: open the palpation view first");
  std::vector<Vec3> points, normals;
  for (const auto& p : *pts) {
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
        !p[2].is_number())
      throw ProtocolError("palpate: expected each point as [x, y, z] (mm)");
    const Vec3 q(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    Vec3 c, n;
    if (!q.allFinite() || !palp_shape_->closest(q, c, n) || (c - q).norm() > 5.0)
      throw ProtocolError(
          fmt::format("palpate: point ({:.1f}, {:.1f}, {:.1f}) is not on the shape (within 5 mm)",
                      q.x(), q.y(), q.z()));
    points.push_back(c);
    normals.push_back(n);
  }
  stop_rig();
  palp_config_ = eval::palpation_config(quick);
  palp_points_ = points;
  palp_normals_ = normals;
  palp_speed_ = speed;
  {
    std::lock_guard lock(data_mu_);
    palp_cycles_.clear();
    sys_.reset();
    palp_error_.clear();
  }
  try {
    start_rig("palpating");
  } catch (...) {
    start_rig("palpation");  // back to the idle palpation rig
    throw;
  }
  nlohmann::json ref = nlohmann::json::array();
  for (std::size_t i = 0; i < points.size(); ++i)
    ref.push_back({{"position", {points[i].x(), points[i].y(), points[i].z()}},
                   {"normal", {normals[i].x(), normals[i].y(), normals[i].z()}}});
  return nlohmann::json{{"type", "palpation"},
                        {"status", "running"},
                        {"points", ref},
                        {"quick", quick},
                        {"speed", speed},
                        {"levels", palp_config_.normal_forces},
                        {"directions", palp_config_.directions},
                        {"plateaus", palp_config_.plateaus}}
      .dump();
}

// Streamer thread: the cycles finished since the last poll, then (once) the fit.
void Session::stream_palpation(PalpationRenderer& r, bool& fitted) {
  friction::CycleRecord c;
  while (r.finished_cycles().pop(c)) {
    nlohmann::json j = cycle_json(c);
    j["type"] = "cycle";
    {
      std::lock_guard lock(data_mu_);
      palp_cycles_.push_back(c);
      j["cycles"] = palp_cycles_.size();
    }
    broadcast_(j.dump());
  }
  if (fitted || !r.finished()) return;
  fitted = true;
  fit_palpation_now(r);
}

void Session::fit_palpation_now(PalpationRenderer& r) {
  std::string error = r.error();
  nlohmann::json j{{"type", "palpation"}, {"status", "failed"}};
  if (error.empty()) {
    try {
      const auto cycles = r.cycles();
      friction::SysModel sys = eval::fit_palpation(cycles, *palp_shape_, palp_config_);
      j = yield_json(sys);
      j["cycles"] = cycles.size();
      std::lock_guard lock(data_mu_);
      palp_cycles_ = cycles;  // all of them, also any the ring dropped
      sys_ = std::move(sys);
    } catch (const std::exception& e) {
      error = std::string("fit: ") + e.what();
    }
  }
  if (!error.empty()) {
    j["message"] = error;
    std::lock_guard lock(data_mu_);
    palp_error_ = error;
  }
  fmt::print(stderr, "studio: palpation {}\n", error.empty() ? "fitted" : error);
  broadcast_(j.dump());
}

std::string Session::do_save_sys(const Message& m) {
  const std::string rel = get_string(m, "path");
  if (rel.size() < 6 || rel.substr(rel.size() - 5) != ".json")
    throw ProtocolError("save_sys: expected a path ending in .json");
  const std::string cycles_rel = rel.substr(0, rel.size() - 5) + ".cycles.csv";
  const WorkspacePath sys_out = workspace_.output(rel), cycles_out = workspace_.output(cycles_rel);
  std::optional<friction::SysModel> sys;
  std::vector<friction::CycleRecord> cycles;
  {
    std::lock_guard lock(data_mu_);
    if (!sys_) throw ProtocolError("save_sys: no fitted palpation yet (run one first)");
    sys = sys_;
    cycles = palp_cycles_;
  }
  with_names({&sys_out, &cycles_out}, [&] {
    OutputTransaction tx;  // both files or neither, as `sys palpate`
    friction::write_cycles_csv(cycles_out.path(), cycles);
    friction::write_sys_json(sys_out.path(), *sys);
    tx.commit();
  });
  const WorkspacePath in = workspace_.input(rel);
  const friction::SysModel back =  // the library's reader
      with_names({&in}, [&] { return friction::read_sys_json(in.path()); });
  return nlohmann::json{{"type", "ok"},
                        {"request", "save_sys"},
                        {"path", rel},
                        {"points", back.points.size()},
                        {"levels", back.f_normal_levels.size()},
                        {"directions", back.angles.size()},
                        {"cycles", cycles.size()}}
      .dump();
}

}  // namespace inhap::studio
