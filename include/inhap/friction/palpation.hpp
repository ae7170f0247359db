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
//      the object: into the surface and along the tangential direction t_k; with a shape, n_c
//      and t_k follow the surface under the probe); record the reaction
//      force f and the displacement u = p - p_c at t_measurement;
//   5. unload, wait for equilibrium (filtered speed below settle_speed for settle_window) and
//      record the release point p_r: the plastic displacement is u^p = p_r - p_c (eq. 4.24).
// The sweep runs f_N over normal_forces and the K tangential directions t_k (angle 2 pi k / K
// from t_0, the projection of tangent_reference onto the tangent plane). Along a direction f_T
// rises on the lattice f_T = i * tangential_step * f_N (i = 1, 2, ...); each step is loaded once
// per plateau duration. After stop_after_sliding consecutive sliding steps (plateau growth
// ||u^p_600|| - ||u^p_100|| > slide_threshold) one more step half-way between the last elastic
// and the first sliding step narrows the border, and the direction ends (also at the force
// cap). Adaptive start (SweepSchedule): once a border has been seen, later directions start
// steps_below steps under the mean border ratio f_T / f_N seen so far at that level (else at
// any level), and start again lower if their first step already slides.
//
// step() does not allocate: the cycle records are reserved up front.
#pragma once

#include <string>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/core/types.hpp"
#include "inhap/friction/loading_profile.hpp"
#include "inhap/friction/shape_query.hpp"
#include "inhap/geometry/surface_frame.hpp"

namespace inhap::friction {

/// Tangential unit direction at `angle` (rad) from t0 around n.
Vec3 tangent_direction(const Vec3& n, const Vec3& reference, double angle);

enum class CycleStatus : int {
  kOk = 0,
  kNoContact = 1,   ///< the approach found no surface
  kSaturated = 2,   ///< the commanded load exceeded the device's force limit
  kUnsettled = 3,   ///< the probe had not come to rest when the release point was taken
  kBadInput = 4,    ///< non-finite readings
  kSlipCapped = 5,  ///< slid past max_slip: unloaded early (the plateau growth is a lower bound)
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
  /// When f_meas and u_meas were taken, s after the start of the plateau (negative: during the
  /// loading ramps, e.g. a slip-capped cycle). Default: the protocol's 90 ms.
  double t_measurement_s = 0.09;
  CycleStatus status = CycleStatus::kOk;

  Vec3 up() const { return pr - pc; }  ///< plastic displacement u^p, eq. 4.24
  /// Norm of the tangential part of u^p (component in the tangent plane of n_c), mm.
  double up_tangential() const;
};

struct PalpationConfig {
  std::vector<double> normal_forces{1.0, 3.0, 5.0};  ///< f_N levels, N
  int directions = 8;                                ///< K tangential directions
  std::vector<double> plateaus{0.1, 0.6};            ///< t_plateau values, s (short first)
  double tangential_step = 0.15;                     ///< f_T lattice step as a fraction of f_N
  double max_ratio = 2.0;                            ///< largest f_T / f_N tried
  double tangential_force_max = 6.0;                 ///< absolute f_T cap, N
  /// Total load |f_l| cap as a fraction of the device's max force.
  double load_fraction_max = 0.97;
  int stop_after_sliding = 1;  ///< consecutive sliding steps that end a direction (0: never)
  bool half_step = true;       ///< then one step half-way back into the border bracket
  /// The first direction of each level goes on to this many sliding steps, so that the growth
  /// slope (the creep viscosity) is measured at every level.
  int slope_steps = 2;
  double slide_threshold = 0.05;  ///< mm of plateau growth that counts as sliding
  bool adaptive = true;           ///< start near the border seen so far (else from step 1)
  int steps_below = 2;            ///< adaptive: steps started below the predicted border
  ProfileRates rates{20.0, 10.0, 0.1, 0.09};
  Vec3 tangent_reference = Vec3::UnitX();
  /// Feed the tool weight (DeviceInfo tool mass and gravity) forward in the command. Off for
  /// gravity-balanced devices (PHANToM counterweights, the virtual lab), where only the force
  /// sensor sees the tool's weight (removed by the tare).
  bool gravity_feedforward = false;

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
  /// Tangential slip during the plateau (mm) that ends the loading early (keeps the probe on
  /// small objects; the cycle gets status slip_capped).
  double max_slip = 15.0;
  /// Tangential displacement (mm) that ends the loading early at any time (status slip_capped).
  double max_displacement = 30.0;

  // Equilibrium after unloading.
  double settle_speed = 0.5;    ///< mm/s
  double settle_window = 0.03;  ///< s below settle_speed
  double settle_min = 0.05;     ///< s
  double settle_max = 0.6;      ///< s (status unsettled beyond)
};

/// Order of the cycles of a sweep and the adaptive choice of f_T steps (see the file comment).
/// Allocation-free after construction.
class SweepSchedule {
 public:
  /// `max_force`: the device's force limit, N. Throws inhap::Error on an invalid config.
  SweepSchedule(const PalpationConfig& config, double max_force);
  bool done() const { return done_; }
  std::size_t level() const { return lvl_; }
  int direction() const { return dir_; }
  /// f_T = lattice * tangential_step * f_N (a half-integer for the half step).
  double lattice() const { return 0.5 * h_; }
  std::size_t plateau_index() const { return pl_; }
  double f_normal() const;
  double f_tangential() const { return f_tangential(lvl_, h_); }
  double plateau() const;
  /// Reports the tangential plastic displacement of the cycle just run (mm) and moves to the
  /// next cycle; false when the sweep is complete.
  bool next(double up_tangential);
  /// Fraction of the (level, direction) pairs completed.
  double progress() const;
  /// Upper bound of the number of cycles (for reserving storage).
  std::size_t max_cycles() const;
  /// Border ratio f_T / f_N predicted for the current direction (NaN: none yet).
  double predicted_ratio() const;

 private:
  double f_tangential(std::size_t level, int half_steps) const;
  void begin_direction();
  bool end_direction();
  bool half_step_or_end();

  const PalpationConfig* cfg_;
  double cap_;
  std::vector<int> max_h_;  // per level: largest valid f_T in half steps
  std::vector<double> est_sum_;
  std::vector<int> est_n_;
  std::size_t lvl_ = 0, pl_ = 0;
  // Position in half steps (h = 2 i on the lattice); per direction: first, largest elastic and
  // smallest sliding step (-1: none yet).
  int dir_ = 0, h_ = 2, first_h_ = 2, run_ = 0, elastic_h_ = -1, sliding_h_ = -1;
  bool backtracked_ = false, half_done_ = false, done_ = false;
  double short_up_ = 0;
};

/// Palpation of one reference point: the whole sweep of cycles.
class PalpationProtocol final : public TickProtocol {
 public:
  /// `reference` is the probe-centre position of the reference point on the undeformed surface
  /// and `normal` the outward surface normal there (from the shape mesh). Throws inhap::Error on
  /// an invalid configuration.
  /// `shape` (optional, not owned, must outlive the protocol): with it the load follows the
  /// surface under the probe, f_l = -f_N n(p) + f_T t_k projected on the tangent plane at p,
  /// so that f_N and f_T stay normal and tangential where the contact is even when the probe
  /// has moved on a curved object (else the frame of n_c at the reference point, as the thesis).
  PalpationProtocol(const PalpationConfig& config, const DeviceInfo& device, int point_id,
                    const Vec3& reference, const Vec3& normal, const ShapeQuery* shape = nullptr);
  PalpationProtocol(const PalpationProtocol&) = delete;  // the schedule points at cfg_
  PalpationProtocol& operator=(const PalpationProtocol&) = delete;

  Vec3 step(double time, const Vec3& position, const Vec3& sensor_force) override;
  bool done() const override { return phase_ == Phase::kDone; }

  const std::vector<CycleRecord>& cycles() const { return cycles_; }
  /// True when the sweep stopped on an error (no contact, bad input); see error().
  bool failed() const { return failed_; }
  const char* error() const { return error_; }
  /// Upper bound of cycles in the sweep.
  std::size_t max_cycles() const { return schedule_.max_cycles(); }
  /// Fraction of the sweep done (for progress bars).
  double progress() const { return done() ? 1.0 : schedule_.progress(); }

 private:
  enum class Phase { kStart, kLift, kTravel, kTare, kApproach, kDrop, kLoad, kRelease, kDone };
  void begin_cycle(double time, const Vec3& position);
  void begin_lift(double time, const Vec3& position);
  void begin_move(double time, const Vec3& from, const Vec3& to, double speed);
  struct Tick {            // readings of the current tick
    double time, tau, dt;  // tau: time since the start of the phase
    const Vec3& position;
    const Vec3& sensor;
  };
  Vec3 move_step(const Tick& k);
  Vec3 tare_step(const Tick& k);
  Vec3 approach_step(const Tick& k);
  Vec3 load_step(const Tick& k);
  Vec3 release_step(const Tick& k);
  void measure(const Tick& k);
  Vec3 pid(const Vec3& position, const Vec3& target, const Vec3& target_velocity, double dt);
  Vec3 hold_zero_load() const;
  Vec3 finish_cycle(double time, const Vec3& position);
  Vec3 fail(const char* why, CycleStatus status, const Vec3& position);
  Vec3 clamp_force(const Vec3& f) const;

  PalpationConfig cfg_;
  DeviceInfo info_;
  const ShapeQuery* shape_;
  int point_;
  Vec3 c_, n_, t0_, t1_, weight_;
  SweepSchedule schedule_;
  std::vector<CycleRecord> cycles_;
  bool finishing_ = false, failed_ = false;
  const char* error_ = "";

  Phase phase_ = Phase::kStart;
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
  bool measured_ = false, saturated_ = false, slip_capped_ = false;
  double plateau_ut_ = 0;  // tangential displacement at the start of the plateau
};

}  // namespace inhap::friction
