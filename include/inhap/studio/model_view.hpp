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
// With a bridged device (--device udp) there is no lab truth and no lab object in the studio:
//  - ObservedRecording: the recording is taken from what the servo loop observes (its observer
//    ring, drained by the streamer thread): t, the probe position and the device's sensed force
//    compensated causally (as `inhap serve --record` writes it), no truth.
//  - CompareRenderer in sensed mode: the "object" is the device's own sensed force (compensated,
//    zero force commanded); the model is stepped on the same path and its force commanded when
//    selected.
// Units: mm, N, s.
#pragma once

#include <atomic>
#include <memory>
#include <nlohmann/json.hpp>
#include <unordered_map>
#include <vector>

#include "inhap/contact/compensation.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/haptics/servo_loop.hpp"
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

/// A bridged device's sensed (compensated) force above which the probe counts as in contact for
/// the live coverage map, the recording's contact count and the RMSE, N.
inline constexpr double kSensedContactN = 0.1;

/// A bridged device's recording from the servo loop's observer ring (the streamer thread; the
/// servo step only pushes to the ring). One row per new device sample (a tick that repeats the
/// last device time is not a measurement; one whose time runs backwards, a new device session,
/// is counted in skipped()), up to `seconds` of device time.
class ObservedRecording {
 public:
  void start(const CompensatorConfig& config, double seconds);
  /// Takes the sample when it is new and the recording not full; `point` is then the coverage
  /// map's point (the probe centre and the compensated force, contact above kSensedContactN).
  bool add(const haptics::LoopSample& s, TickPoint& point);
  bool full() const { return full_; }
  double seconds() const { return rec_.size() ? rec_.t.back() - rec_.t.front() : 0.0; }
  std::size_t skipped() const { return skipped_; }
  /// Rows whose compensated force is above kSensedContactN.
  std::size_t contact_rows() const { return contact_; }
  /// The recording (t s, p mm, f N); leaves this one empty.
  Recording take();

 private:
  CompensatorConfig config_;
  CompensatorState state_;
  Recording rec_;
  double seconds_ = 0;
  std::size_t skipped_ = 0, contact_ = 0;
  bool full_ = false;
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
  /// Sensed mode (a bridged device): the object is the device's sensed force, compensated
  /// causally with `config`; "object" commands zero force.
  CompareRenderer(const CompensatorConfig& config, const haptics::DataDrivenModel* model,
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
  const lab::SoftObject* object_ = nullptr;  ///< null: sensed mode
  double radius_ = 0, limit_;
  CompensatorConfig comp_;
  CompensatorState comp_state_;
  std::unique_ptr<haptics::DataDrivenRenderer> model_;
  const lab::SimDevice* device_ = nullptr;
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
