// inhap studio: the palpation view (thesis 4.3.2, figs 4.6-4.8). The library's palpation
// protocol (friction::PalpationProtocol, a TickProtocol) runs inside the servo loop as its
// renderer: every tick the loop hands it the device's position and force sensor, and it returns
// the force to command. One protocol per reference point, in turn. Finished cycles leave the
// servo thread through a lock-free ring (no lock, no allocation, no I/O in step()); the
// streamer drains it for the page's live plot (fig. 4.7) and fits the sliding yield surfaces
// when the sweep is done (fig. 4.8).
// Units: mm, N, s.
#pragma once

#include <atomic>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/haptics/servo.hpp"
#include "inhap/haptics/spsc_ring.hpp"
#include "inhap/lab/operators.hpp"

namespace inhap::studio {

/// The lab's hand let go: the protocol alone moves the probe (as `sys palpate` detaches it).
class DetachedOperator final : public lab::HandOperator {
 public:
  explicit DetachedOperator(const Vec3& start) : start_(start) {}
  std::string name() const override { return "none"; }
  void begin(lab::SimDevice& device) override;
  void step(lab::SimDevice&) override {}

 private:
  Vec3 start_;
};

class PalpationRenderer final : public haptics::Renderer {
 public:
  using CycleRing = haptics::SpscRing<friction::CycleRecord, 1024>;
  /// `points` (probe centre on `shape`) and `normals` (outward, unit), one protocol each, built
  /// here (this allocates; step() does not). `device`: the device's own description (its true
  /// servo rate and force limit). `shape` must outlive the renderer. Throws inhap::Error on an
  /// invalid configuration or point list.
  PalpationRenderer(const friction::PalpationConfig& config, const DeviceInfo& device,
                    const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                    const friction::MeshSurface& shape);

  haptics::ServoOutput step(const haptics::ServoInput& input) noexcept override;
  /// The protocol cannot restart mid-cycle: a watchdog reset (a long device fault) is ignored
  /// and the protocol goes on from the readings it gets next.
  void reset() noexcept override {}
  const char* name() const noexcept override { return "palpation"; }

  /// Cycles finished since the last call (streamer thread only).
  CycleRing& finished_cycles() { return ring_; }
  /// True once every point is done or one failed (acquire: after it, cycles() may be read).
  bool finished() const { return finished_.load(std::memory_order_acquire); }
  /// The reason a point failed ("" when none); valid once finished(). Formatted here, on the
  /// caller's thread: step() allocates nothing, a failed point included.
  std::string error() const;
  /// Every cycle of every point, in order; only once finished().
  std::vector<friction::CycleRecord> cycles() const;
  /// Fraction of the sweep done (any thread).
  double progress() const { return progress_.load(std::memory_order_relaxed); }
  /// The reference point being palpated (any thread).
  int point() const { return current_.load(std::memory_order_relaxed); }
  /// Cycles the ring had no room for (the streamer fell 1024 cycles behind).
  long dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::vector<std::unique_ptr<friction::PalpationProtocol>> protocols_;
  std::size_t index_ = 0, pushed_ = 0;
  CycleRing ring_;
  std::atomic<bool> finished_{false};
  std::atomic<double> progress_{0};
  std::atomic<int> current_{0};
  std::atomic<long> dropped_{0};
  // A failed point: the protocol's reason, a pointer to its static text (step() copies the
  // pointer, not the text; error() formats it on the reader's side).
  const char* error_ = "";
  int failed_point_ = -1;
};

/// fig. 4.7 data of one cycle for the page: point, f_N, f_T, plateau, direction, angle,
/// ||u^p|| tangential (mm), status.
nlohmann::json cycle_json(const friction::CycleRecord& c);

/// fig. 4.8 for the page: per reference point its position, normal, the tangential directions
/// t_k (world), and per f_N level and direction the elastic limit f_T (N) and the tangential
/// and normal parts of the elastic displacement limit (mm), with the extrapolated / no-sliding
/// flags; creep viscosity and tangential stiffness.
nlohmann::json yield_json(const friction::SysModel& sys);

}  // namespace inhap::studio
