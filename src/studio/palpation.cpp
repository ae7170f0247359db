// inhap studio: the palpation protocol as the servo loop's renderer (palpation.hpp).
#include "inhap/studio/palpation.hpp"

#include <fmt/format.h>

#include "inhap/core/error.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::studio {

void DetachedOperator::begin(lab::SimDevice& device) {
  device.detach_hand();
  device.place(start_);
}

PalpationRenderer::PalpationRenderer(const friction::PalpationConfig& config,
                                     const DeviceInfo& device, const std::vector<Vec3>& points,
                                     const std::vector<Vec3>& normals,
                                     const friction::MeshSurface& shape) {
  if (points.empty() || points.size() != normals.size())
    throw Error("palpation: expected at least one reference point, each with a normal");
  protocols_.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    protocols_.push_back(std::make_unique<friction::PalpationProtocol>(
        config, device, static_cast<int>(i), points[i], normals[i], &shape));
}

haptics::ServoOutput PalpationRenderer::step(const haptics::ServoInput& in) noexcept {
  haptics::ServoOutput out;
  out.hip_mm = out.ihip_mm = out.cihip_mm = in.p_mm;
  if (finished_.load(std::memory_order_relaxed)) return out;
  friction::PalpationProtocol& p = *protocols_[index_];
  out.force_n = p.step(in.t_s, in.p_mm, in.sensor_force_n);
  out.contact = in.sensor_force_n.norm() > 0.1;  // for the page only
  const auto& done = p.cycles();
  while (pushed_ < done.size())
    if (!ring_.push(done[pushed_++])) dropped_.fetch_add(1, std::memory_order_relaxed);
  const double n = static_cast<double>(protocols_.size());
  progress_.store((static_cast<double>(index_) + p.progress()) / n, std::memory_order_relaxed);
  if (!p.done()) return out;
  if (p.failed()) {
    error_ = p.error();
    failed_point_ = static_cast<int>(index_);
    finished_.store(true, std::memory_order_release);
    return out;
  }
  if (++index_ == protocols_.size()) {
    progress_.store(1.0, std::memory_order_relaxed);
    finished_.store(true, std::memory_order_release);
    return out;
  }
  pushed_ = 0;
  current_.store(static_cast<int>(index_), std::memory_order_relaxed);
  return out;
}

std::string PalpationRenderer::error() const {
  if (!finished() || failed_point_ < 0) return {};
  return fmt::format("palpation of reference point {} failed: {}", failed_point_, error_);
}

std::vector<friction::CycleRecord> PalpationRenderer::cycles() const {
  std::vector<friction::CycleRecord> all;
  if (!finished()) return all;
  for (const auto& p : protocols_) all.insert(all.end(), p->cycles().begin(), p->cycles().end());
  return all;
}

namespace {
nlohmann::json vec(const Vec3& p) {
  return nlohmann::json::array({p.x(), p.y(), p.z()});
}
}  // namespace

nlohmann::json cycle_json(const friction::CycleRecord& c) {
  return {{"point", c.point},        {"fn", c.f_normal},
          {"ft", c.f_tangential},    {"plateau", c.t_plateau},
          {"dir", c.direction},      {"angle", c.angle},
          {"up", c.up_tangential()}, {"status", friction::to_string(c.status)}};
}

nlohmann::json yield_json(const friction::SysModel& sys) {
  nlohmann::json pts = nlohmann::json::array();
  const std::size_t levels = sys.f_normal_levels.size(), dirs = sys.angles.size();
  for (std::size_t i = 0; i < sys.points.size(); ++i) {
    const friction::SysPoint& p = sys.points[i];
    nlohmann::json tdirs = nlohmann::json::array(), limits = nlohmann::json::array();
    for (std::size_t k = 0; k < dirs; ++k)
      tdirs.push_back(
          vec(friction::tangent_direction(p.normal, sys.tangent_reference, sys.angles[k])));
    for (std::size_t j = 0; j < levels; ++j) {
      nlohmann::json row = nlohmann::json::array();
      for (std::size_t k = 0; k < dirs; ++k) {
        const friction::BorderResult& r = sys.border(i, j, k).result;
        row.push_back({{"f", r.f_limit},
                       {"r", r.radius},
                       {"d", r.depth},
                       {"e", r.extrapolated},
                       {"ns", r.no_sliding}});
      }
      limits.push_back(row);
    }
    pts.push_back({{"id", p.id},
                   {"position", vec(p.position)},
                   {"normal", vec(p.normal)},
                   {"tdirs", tdirs},
                   {"limits", limits},
                   {"creep_viscosity", p.creep_viscosity},
                   {"tangential_stiffness", p.tangential_stiffness}});
  }
  return {
      {"type", "yield"}, {"levels", sys.f_normal_levels}, {"angles", sys.angles}, {"points", pts}};
}

}  // namespace inhap::studio
