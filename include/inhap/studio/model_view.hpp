// inhap studio: the Model view (thesis ch. 4 in one sitting): record a free exploration of the
// lab's object, train the data-driven force model on it (eval::train_from_file, the code of
// `inhap model train`), then feel the model against the object.
//  - RecordingDevice: the lab device on the scene's object, held by the lab's explore operator
//    (the coverage-driven training run of `inhap lab record --operator explore --coverage`) or
//    by the mouse; every tick is logged with its ground truth (lab::TickLogger, reserved up
//    front: no allocation in the servo thread) and the true proxy leaves through a lock-free
//    ring for the live coverage map.
//  - CompareRenderer: the object (the lab's contact law, lab::contact_step, at the probe's
//    position) and the trained model (haptics::DataDrivenRenderer) both stepped every tick on
//    the same probe path; the active one's force is commanded, both leave through a ring for the
//    page's plot and the running RMSE.
// Units: mm, N, s.
#pragma once

#include <atomic>
#include <memory>
#include <nlohmann/json.hpp>
#include <unordered_map>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/haptics/spsc_ring.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::studio {

/// One tick of a recording for the coverage map: the true proxy (anchor) and contact force.
struct TickPoint {
  double t = 0;
  Vec3 q = Vec3::Zero();  ///< true proxy, mm (valid when contact)
  Vec3 f = Vec3::Zero();  ///< noise-free contact force, N
  bool contact = false;
};

class RecordingDevice final : public Device {
 public:
  using Ring = haptics::SpscRing<TickPoint, 16384>;
  /// `op` null: the explore operator of `inhap lab record --operator explore --coverage` for
  /// `seconds` (seed derived as there). Logs at most `seconds` simulated seconds.
  RecordingDevice(const lab::Scene& scene, std::uint64_t seed, double seconds, double speed,
                  std::unique_ptr<lab::HandOperator> op);
  const DeviceInfo& info() const override { return info_; }
  double time() const override { return device_->time(); }
  Vec3 position() const override { return device_->position(); }
  Vec3 force_sensor() const override { return device_->force_sensor(); }
  void command_force(const Vec3& force) override { device_->command_force(force); }
  void tick() override;

  Ring& ring() { return ring_; }
  /// True once `seconds` are logged (acquire: take_log() may follow once the loop stopped).
  bool full() const { return full_.load(std::memory_order_acquire); }
  /// Simulated seconds logged so far (any thread).
  double logged_s() const { return logged_s_.load(std::memory_order_relaxed); }
  /// The recording and its truth (call after the servo loop stopped).
  lab::LabRecording take_log();
  const lab::SimDevice& device() const { return *device_; }

 private:
  lab::RecordSpec spec_;
  lab::RecordSetup setup_;
  lab::SimDevice* device_ = nullptr;
  std::unique_ptr<lab::HandOperator> op_;
  std::unique_ptr<lab::TickLogger> log_;
  DeviceInfo info_;
  std::size_t max_ticks_ = 0, ticks_ = 0;
  lab::Scene scene_;
  Ring ring_;
  std::atomic<bool> full_{false};
  std::atomic<double> logged_s_{0};
};

/// The A/B pair stepped on one probe path.
struct ComparePoint {
  double t = 0;
  Vec3 object = Vec3::Zero(), model = Vec3::Zero();  ///< N
  bool object_contact = false, model_contact = false;
};

class CompareRenderer final : public haptics::Renderer {
 public:
  using Ring = haptics::SpscRing<ComparePoint, 8192>;
  /// `object`: the lab's soft object (outlives the renderer); `model`: the trained model, or
  /// null (then only the object is felt). `device`: the lab device, for the probe's velocity.
  CompareRenderer(const lab::SoftObject& object, double probe_radius,
                  const haptics::DataDrivenModel* model, const lab::SimDevice* device,
                  double force_limit_n);
  haptics::ServoOutput step(const haptics::ServoInput& input) noexcept override;
  void reset() noexcept override;
  const char* name() const noexcept override { return "compare"; }
  /// true: command the model's force; false: the object's (any thread).
  void use_model(bool m) { use_model_.store(m && model_, std::memory_order_release); }
  bool using_model() const { return use_model_.load(std::memory_order_acquire); }
  bool has_model() const { return model_ != nullptr; }
  Ring& ring() { return ring_; }

 private:
  const lab::SoftObject& object_;
  double radius_, limit_;
  std::unique_ptr<haptics::DataDrivenRenderer> model_;
  const lab::SimDevice* device_;
  lab::ContactState contact_;
  double last_t_ = -1;
  std::atomic<bool> use_model_{false};
  Ring ring_;
};

/// Live coverage of the exploration so far (streamer thread): the library's CoverageMap over the
/// in-contact true proxies and forces, plus per xy cell the directions the proxy slid in (8
/// sectors of 45 deg, a bit mask).
class CoverageTracker {
 public:
  void add(const TickPoint& p);
  std::size_t samples() const { return q_.size(); }
  /// {"type":"coverage", cell_mm, samples, cells: [[x, y, f_max N, direction mask, samples]],
  /// gaps: [[x, y, cells]]} (the largest unvisited gaps: coverage_gaps, "explore here").
  nlohmann::json json() const;
  void clear();

 private:
  std::vector<Vec3> q_, f_;
  std::unordered_map<std::uint64_t, unsigned> dirs_;  // xy cell key -> direction mask
  Vec3 last_q_ = Vec3::Zero();
  double last_t_ = -1;
};

/// Running RMSE per axis of model - object over the ticks where either is in contact.
struct RunningRmse {
  Vec3 sum = Vec3::Zero();
  std::size_t n = 0;
  void add(const ComparePoint& p) {
    if (!p.object_contact && !p.model_contact) return;
    sum += (p.model - p.object).cwiseAbs2();
    ++n;
  }
  Vec3 rmse() const { return n ? Vec3((sum / double(n)).cwiseSqrt()) : Vec3::Zero(); }
};

}  // namespace inhap::studio
