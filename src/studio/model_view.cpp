// inhap studio: the Model view's device, renderer and coverage (see model_view.hpp).
#include "inhap/studio/model_view.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/lab/soft_contact.hpp"

namespace inhap::studio {

RecordingDevice::RecordingDevice(const lab::Scene& scene, std::uint64_t seed, double seconds,
                                 double speed, std::unique_ptr<lab::HandOperator> op) {
  if (!(seconds > 0 && seconds <= 600)) throw Error("record: expected 0 < seconds <= 600");
  spec_.operator_name = "explore";
  spec_.seconds = seconds;
  spec_.seed = seed;
  spec_.explore.coverage = true;  // the training run of `lab record --coverage` / eval forces
  setup_ = lab::make_record_setup(scene, spec_);
  if (op) setup_.op = std::move(op);
  device_ = setup_.device.get();
  max_ticks_ = static_cast<std::size_t>(std::lround(seconds * device_->info().servo_rate_hz));
  log_ = std::make_unique<lab::TickLogger>(*device_, max_ticks_);
  setup_.op->begin(*device_);  // as lab::record: logger first, then the hand takes over
  info_ = device_->info();
  info_.servo_rate_hz *= std::clamp(speed, 0.1, 20.0);
  scene_ = scene;
}

void RecordingDevice::tick() {
  if (ticks_ < max_ticks_) {
    log_->sample();  // reserved: no allocation
    const lab::ContactState& cs = device_->contact();
    TickPoint p;
    p.t = device_->time();
    p.contact = cs.in_contact;
    if (cs.in_contact) p.q = cs.proxy, p.f = cs.force;
    ring_.push(p);  // a full ring drops the point for the live map only, never for the log
    ++ticks_;
    logged_s_.store(p.t, std::memory_order_relaxed);
    if (ticks_ == max_ticks_) full_.store(true, std::memory_order_release);
  }
  setup_.op->step(*device_);
  device_->tick();
}

lab::LabRecording RecordingDevice::take_log() {
  lab::LabRecording r = log_->take();
  r.comments = lab::record_comments(scene_, spec_, setup_);
  r.comments.push_back("recorded in inhap studio (Model view), operator " + setup_.op->name());
  return r;
}

void ObservedRecording::start(const CompensatorConfig& config, double seconds) {
  config_ = config;
  state_ = {};
  rec_ = {};
  seconds_ = seconds;
  skipped_ = contact_ = 0;
  full_ = false;
}

bool ObservedRecording::add(const haptics::LoopSample& s, TickPoint& point) {
  if (full_) return false;
  if (rec_.size() && !(s.t_s > rec_.t.back())) {
    if (!(s.t_s == rec_.t.back())) ++skipped_;
    return false;
  }
  if (!s.p_mm.allFinite() || !s.sensor_force_n.allFinite() || !std::isfinite(s.t_s)) {
    ++skipped_;
    return false;
  }
  const Vec3 f = compensate_step(config_, state_, s.p_mm, s.sensor_force_n);
  rec_.t.push_back(s.t_s);
  rec_.p.push_back(s.p_mm);
  rec_.f.push_back(f);
  point.t = s.t_s;
  point.contact = f.norm() > kSensedContactN;
  point.q = s.p_mm;
  point.f = f;
  contact_ += point.contact;
  if (s.t_s - rec_.t.front() >= seconds_ - 1e-6) full_ = true;
  return true;
}

Recording ObservedRecording::take() {
  Recording r = std::move(rec_);
  rec_ = {};
  return r;
}

CompareRenderer::CompareRenderer(const lab::SoftObject& object, double probe_radius,
                                 const haptics::DataDrivenModel* model,
                                 const lab::SimDevice* device, double force_limit_n)
    : object_(&object), radius_(probe_radius), limit_(force_limit_n), device_(device) {
  if (model) model_ = std::make_unique<haptics::DataDrivenRenderer>(*model);
}

CompareRenderer::CompareRenderer(const CompensatorConfig& config,
                                 const haptics::DataDrivenModel* model, double force_limit_n)
    : limit_(force_limit_n), comp_(config) {
  if (model) model_ = std::make_unique<haptics::DataDrivenRenderer>(*model);
}

haptics::ServoOutput CompareRenderer::step(const haptics::ServoInput& in) noexcept {
  haptics::ServoOutput out;
  out.hip_mm = out.ihip_mm = out.cihip_mm = in.p_mm;
  if (!in.p_mm.allFinite() || !std::isfinite(in.t_s)) {
    reset();
    return out;
  }
  const double dt = last_t_ >= 0 && in.t_s > last_t_ ? in.t_s - last_t_ : 1e-3;
  last_t_ = in.t_s;
  const Vec3 v = device_ ? device_->truth().velocity : Vec3::Zero();
  ComparePoint c;
  c.t = in.t_s;
  if (object_) {
    c.object = lab::contact_step(*object_, radius_, contact_, in.p_mm, v, in.t_s, dt);
    if (!c.object.allFinite()) c.object.setZero(), contact_.reset();
    c.object_contact = contact_.in_contact;
  } else {  // sensed mode: what the device feels (zero commanded unless the model is)
    c.object = in.has_sensor ? compensate_step(comp_, comp_state_, in.p_mm, in.sensor_force_n)
                             : Vec3(Vec3::Zero());
    if (!c.object.allFinite()) c.object.setZero();
    c.object_contact = c.object.norm() > kSensedContactN;
  }
  haptics::ServoOutput m;
  if (model_) {
    m = model_->step(in);
    c.model = m.force_n;
    c.model_contact = m.contact;
  }
  ring_.push(c);
  if (use_model_.load(std::memory_order_acquire) && model_) {
    out = m;
  } else if (object_) {
    out.force_n = c.object;
    out.contact = c.object_contact;
    if (c.object_contact) out.ihip_mm = out.cihip_mm = contact_.proxy;
  } else {
    out.contact = c.object_contact;  // the device's own object: nothing commanded
  }
  const double n = out.force_n.norm();
  if (!(n <= limit_))
    out.force_n = n > 0 && std::isfinite(n) ? Vec3(out.force_n * (limit_ / n)) : Vec3(Vec3::Zero());
  return out;
}

void CompareRenderer::reset() noexcept {
  contact_.reset();
  comp_state_.reset();
  last_t_ = -1;
  if (model_) model_->reset();
}

namespace {
constexpr double kCellMm = datadriven::CoverageParams{}.cell_mm;
std::uint64_t xy_key(double x, double y) {
  const auto ix = static_cast<std::int32_t>(std::floor(std::clamp(x / kCellMm, -1e9, 1e9)));
  const auto iy = static_cast<std::int32_t>(std::floor(std::clamp(y / kCellMm, -1e9, 1e9)));
  return (std::uint64_t(std::uint32_t(ix)) << 32) | std::uint32_t(iy);
}
}  // namespace

void CoverageTracker::add(const TickPoint& p) {
  if (!p.contact || !p.q.allFinite() || !p.f.allFinite()) {
    last_t_ = -1;
    return;
  }
  q_.push_back(p.q);
  f_.push_back(p.f);
  if (last_t_ >= 0 && p.t > last_t_) {  // sliding: the proxy moved at > 1 mm/s in the plane
    const Vec3 d = p.q - last_q_;
    const double speed = std::hypot(d.x(), d.y()) / (p.t - last_t_);
    if (speed > 1.0) {
      const double a = std::atan2(d.y(), d.x());
      const int sector = static_cast<int>(std::lround(a / (std::numbers::pi / 4))) & 7;
      const std::uint64_t k = xy_key(p.q.x(), p.q.y());
      dirs_[k] |= 1u << sector;
    }
  }
  last_q_ = p.q;
  last_t_ = p.t;
}

void CoverageTracker::clear() {
  q_.clear(), f_.clear(), dirs_.clear();
  last_t_ = -1;
}

nlohmann::json CoverageTracker::json() const {
  nlohmann::json cells = nlohmann::json::array(), gaps = nlohmann::json::array();
  if (!q_.empty()) {
    const datadriven::CoverageMap map(q_, f_);
    // The map's cells are cubes; the page shows the object from above: per xy column the
    // largest force and the samples.
    struct Column {
      double f = 0;
      std::size_t n = 0;
      int ix = 0, iy = 0;
    };
    std::unordered_map<std::uint64_t, Column> cols;
    for (const datadriven::CoverageCell& c : map.cells()) {
      const double x = (c.index[0] + 0.5) * kCellMm, y = (c.index[1] + 0.5) * kCellMm;
      const std::uint64_t k = xy_key(x, y);
      Column& col = cols.try_emplace(k, Column{0, 0, c.index[0], c.index[1]}).first->second;
      col.f = std::max(col.f, c.f_max);
      col.n += c.samples;
    }
    for (const auto& [k, c] : cols) {
      const auto d = dirs_.find(k);
      const unsigned mask = d == dirs_.end() ? 0u : d->second;
      const auto r = [](double v) { return std::round(v * 1000) / 1000; };
      cells.push_back({r((c.ix + 0.5) * kCellMm), r((c.iy + 0.5) * kCellMm), r(c.f), mask, c.n});
    }
    for (const datadriven::CoverageGap& g : datadriven::coverage_gaps(map))
      gaps.push_back({g.x_mm, g.y_mm, g.cells});
  }
  return {{"type", "coverage"},
          {"cell_mm", kCellMm},
          {"samples", q_.size()},
          {"cells", cells},
          {"gaps", gaps}};
}

}  // namespace inhap::studio
