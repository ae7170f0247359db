// Automatic palpation of one reference point (thesis 4.3.2, fig. 4.6): a TickProtocol driven
// through the Device interface, so the same code runs the virtual lab's simulated device and a
// real device loop. Units: positions and displacements mm, forces N, times s, gains N/mm,
// N s/mm and N/(mm s).
//
// One loading-unloading cycle:
//   1. lift along the reference normal to the hover height, travel above the reference point
//      (PID position control on a smooth trajectory), hold and tare the force sensor;
//   2. approach along -n_c until the tared sensor force along n_c exceeds contact_force;
//   3. drop the command force (hold only the tool weight), let the probe settle and record the
//      contact point p_c;
//   4. apply the loading profile: load = -f_N(t) n_c + f_T(t) t_k (the force the probe exerts on
//      the object: into the surface and along the tangential direction t_k); record the reaction
//      force f and the displacement u = p - p_c at t_measurement;
//   5. unload, wait for equilibrium (filtered speed below settle_speed for settle_window) and
//      record the release point p_r: the plastic displacement is u^p = p_r - p_c (eq. 4.24).
// The sweep runs f_N over normal_forces, the K tangential directions t_k (angle 2 pi k / K from
// t_0, the projection of tangent_reference onto the tangent plane) and rising f_T steps; each
// step is loaded once per plateau duration. A direction stops early after stop_after_sliding
// consecutive steps whose plateau growth ||u^p_600|| - ||u^p_100|| exceeds slide_threshold.
//
// step() does not allocate: the cycle records are reserved up front.
#pragma once

#include <string>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/core/types.hpp"
#include "inhap/friction/loading_profile.hpp"

namespace inhap::friction {

/// Orthonormal tangent basis at the unit normal n: t0 is `reference` projected onto the tangent
/// plane (falls back to the next world axis when reference is nearly parallel to n), t1 = n x t0.
void tangent_basis(const Vec3& n, const Vec3& reference, Vec3& t0, Vec3& t1);
/// Tangential unit direction at `angle` (rad) from t0 around n.
Vec3 tangent_direction(const Vec3& n, const Vec3& reference, double angle);

enum class CycleStatus : int {
  ok = 0,
  no_contact = 1,  ///< the approach found no surface
  saturated = 2,   ///< the commanded load exceeded the device's force limit
  unsettled = 3,   ///< the probe had not come to rest when the release point was taken
  bad_input = 4,   ///< non-finite readings
};
const char* to_string(CycleStatus s);

/// One loading-unloading cycle (one row of the cycles CSV).
struct CycleRecord {
  int point = 0;                  ///< reference point id
  Vec3 reference = Vec3::Zero();  ///< nominal reference point c (probe centre), mm
  double f_normal = 0;            ///< commanded f_N, N
  double f_tangential = 0;        ///< commanded f_T, N
  double t_plateau = 0;           ///< s
  int direction = 0;              ///< index k of t_k
  double angle = 0;               ///< angle of t_k from t_0 around n_c, rad
  Vec3 tdir = Vec3::UnitX();      ///< t_k (unit)
  Vec3 pc = Vec3::Zero();         ///< contact point p_c, mm
  Vec3 nc = Vec3::UnitZ();        ///< surface normal n_c (unit, outward)
  Vec3 f_meas = Vec3::Zero();     ///< reaction force at t_measurement (tared sensor), N
  Vec3 u_meas = Vec3::Zero();     ///< displacement p - p_c at t_measurement, mm
  Vec3 pr = Vec3::Zero();         ///< release point p_r, mm
  double t_start = 0;             ///< device time at the start of the cycle, s
  CycleStatus status = CycleStatus::ok;

  Vec3 up() const { return pr - pc; }  ///< plastic displacement u^p, eq. 4.24
  /// Norm of the tangential part of u^p (component in the tangent plane of n_c), mm.
  double up_tangential() const;
};

struct PalpationConfig {
  std::vector<double> normal_forces{1.0, 3.0, 5.0};  ///< f_N levels, N
  int directions = 8;                                ///< K tangential directions
  std::vector<double> plateaus{0.1, 0.6};            ///< t_plateau values, s (short first)
  /// f_T steps as fractions of f_N: step i loads f_T = f_N * tangential_ratios[i].
  std::vector<double> tangential_ratios{0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2};
  double tangential_force_max = 4.0;  ///< absolute f_T cap, N
  /// Total load |f_l| cap as a fraction of the device's max force.
  double load_fraction_max = 0.97;
  int stop_after_sliding = 3;     ///< early stop: consecutive clearly sliding steps (0: never)
  double slide_threshold = 0.05;  ///< mm of plateau growth that counts as clearly sliding
  ProfileRates rates;
  Vec3 tangent_reference = Vec3::UnitX();

  // Motion (PID position control with the tool weight fed forward).
  double hover = 2.0;            ///< mm above the reference point before each approach
  double travel_speed = 60.0;    ///< mm/s
  double approach_speed = 15.0;  ///< mm/s
  double approach_extra = 6.0;   ///< mm searched below the reference point before giving up
  double contact_force = 0.06;   ///< N along n_c (tared) that detects contact
  int contact_ticks = 2;         ///< consecutive ticks above contact_force
  double tare_time = 0.03;       ///< s held at the hover point; the sensor is averaged over it
  double kp = 0.4, ki = 4.0, kd = 0.008;  ///< PID gains, N/mm, N/(mm s), N s/mm
  double integral_limit = 1.5;            ///< |ki * integral| cap, N
  double velocity_cutoff = 40.0;          ///< low-pass cutoff of the velocity estimate, Hz
  /// Damping while the command force is dropped or the profile is applied, N s/mm (stands in
  /// for the device's internal friction; bounds the slip speed; no effect at rest).
  double load_damping = 0.004;
  double drop_time = 0.04;  ///< s of zero load after contact before p_c is taken

  // Equilibrium after unloading.
  double settle_speed = 0.5;    ///< mm/s
  double settle_window = 0.03;  ///< s below settle_speed
  double settle_min = 0.05;     ///< s
  double settle_max = 0.6;      ///< s (status unsettled beyond)
};

/// Palpation of one reference point: the whole sweep of cycles.
class PalpationProtocol final : public TickProtocol {
 public:
  /// `reference` is the probe-centre position of the reference point on the undeformed surface
  /// and `normal` the outward surface normal there (from the shape mesh). Throws inhap::Error on
  /// an invalid configuration.
  PalpationProtocol(const PalpationConfig& config, const DeviceInfo& device, int point_id,
                    const Vec3& reference, const Vec3& normal);

  Vec3 step(double time, const Vec3& position, const Vec3& sensor_force) override;
  bool done() const override { return phase_ == Phase::done; }

  const std::vector<CycleRecord>& cycles() const { return cycles_; }
  /// True when the sweep stopped on an error (no contact, bad input); see error().
  bool failed() const { return failed_; }
  const char* error() const { return error_; }
  /// Upper bound of cycles in the sweep (no early stop).
  std::size_t max_cycles() const { return max_cycles_; }
  /// Conservative estimate of the simulated time the sweep takes, s (for progress bars).
  double estimated_duration() const;

 private:
  enum class Phase { start, lift, travel, tare, approach, drop, load, release, done };
  struct Steps {  // position of the sweep
    std::size_t fn = 0, dir = 0, step = 0, plateau = 0;
    int sliding_run = 0;
  };
  double now_fn() const { return cfg_.normal_forces[seq_.fn]; }
  double step_force(std::size_t fn, std::size_t step) const;
  bool advance();  // moves seq_ to the next cycle; false when the sweep is complete
  void begin_cycle(double time, const Vec3& position);
  void begin_lift(double time, const Vec3& position);
  void begin_move(double time, const Vec3& from, const Vec3& to, double speed);
  Vec3 pid(double time, const Vec3& position, const Vec3& target, const Vec3& target_velocity,
           double dt);
  Vec3 hold_zero_load() const;
  Vec3 finish_cycle(double time, const Vec3& position);
  Vec3 fail(const char* why, CycleStatus status, const Vec3& position);
  Vec3 clamp_force(const Vec3& f) const;

  PalpationConfig cfg_;
  DeviceInfo info_;
  int point_;
  Vec3 c_, n_, t0_, t1_, weight_;
  std::vector<CycleRecord> cycles_;
  std::size_t max_cycles_ = 0;
  Steps seq_;
  bool finishing_ = false, failed_ = false;
  const char* error_ = "";

  Phase phase_ = Phase::start;
  double phase_t0_ = 0, last_time_ = 0;
  Vec3 last_p_ = Vec3::Zero(), vel_ = Vec3::Zero(), integral_ = Vec3::Zero();
  bool have_last_ = false;
  // Trajectory (lift then travel): piecewise straight with smooth time scaling.
  Vec3 move_from_ = Vec3::Zero(), move_to_ = Vec3::Zero(), travel_to_ = Vec3::Zero();
  double move_dur_ = 0;
  // Tare.
  Vec3 bias_sum_ = Vec3::Zero(), bias_ = Vec3::Zero();
  int bias_n_ = 0;
  int contact_run_ = 0;
  double settle_run_ = 0;
  LoadingProfile profile_;
  CycleRecord cur_;
  bool measured_ = false, saturated_ = false;
};

}  // namespace inhap::friction
