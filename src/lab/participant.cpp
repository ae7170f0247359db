// Virtual participant: a person's exploration program and perception on a simulated
// impedance-type device. Units: mm, mm/s, N, N/mm, kg, s (accelerations mm/s^2: a = 1000 F / m).
#include "inhap/lab/participant.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"

namespace inhap::lab {

using rendering::Label;
using rendering::SceneInfo;
using rendering::ShapeClass;
using rendering::StiffnessClass;
using rendering::Task;

ParticipantProfile sample_participant(std::uint64_t seed) {
  Rng rng(seed ^ 0x7a5c0ffee1234567ull);
  ParticipantProfile p;
  p.seed = seed;
  p.force_n = rng.uniform(0.8, 2.0);
  p.speed_mm_s = rng.uniform(20.0, 60.0);
  double sum = 0;
  for (int i = 0; i < 4; ++i) {
    p.fluctuation_hz[i] = rng.uniform(0.05, 0.25);
    p.fluctuation_weight[i] = rng.uniform(0.2, 1.0);
    p.fluctuation_phase[i] = rng.uniform(0.0, 2 * std::numbers::pi);
    sum += p.fluctuation_weight[i];
  }
  for (auto& w : p.fluctuation_weight) w /= sum;
  return p;
}

namespace {

enum class Kind { kTransit, kPress, kStroke, kTap, kLabel };

struct Action {
  Kind kind = Kind::kTransit;
  int cell = -1;
  Vec2 target = Vec2::Zero();  // transit goal, stroke end or tap site (xy, mm)
  Vec2 dir = Vec2::UnitX();    // stroke direction
  bool centre_site = true;     // tap at the centre (else the surround)
};

// Running sums of a least-squares line F = a + b z.
struct LineFit {
  double n = 0, sz = 0, sf = 0, szz = 0, szf = 0;
  void add(double z, double f) {
    n += 1;
    sz += z;
    sf += f;
    szz += z * z;
    szf += z * f;
  }
  double slope() const {
    const double d = n * szz - sz * sz;
    return d > 0 ? (n * szf - sz * sf) / d : 0.0;
  }
};

}  // namespace

struct VirtualParticipant::Impl {
  ParticipantProfile prof;
  HandDeviceParams hand;
  DeviceInfo dinfo;
  Rng rng;
  // Device physics.
  Vec3 x = Vec3(0, 0, 20), v = Vec3::Zero(), force = Vec3::Zero();
  long ticks = 0;
  bool placed = false;
  // The hand's set point (where the arm's impedance pulls the device).
  Vec2 xy_set = Vec2::Zero(), vxy_set = Vec2::Zero();
  double z_set = 20, vz_set = 0;
  // Exploration program.
  SceneInfo scene;
  std::vector<Action> program;
  std::size_t pc = 0;
  long action_start = 0;
  bool contact = false, rising = false;
  int settled = 0;
  double tap_force = 0;
  LineFit tap_fit;
  double win_sum[3] = {0, 0, 0};
  long win_n[3] = {0, 0, 0};
  std::vector<CellEvidence> evidence;
  std::optional<Label> pending;

  Impl(const ParticipantProfile& p, const HandDeviceParams& h) : prof(p), hand(h), rng(p.seed) {
    if (!(h.max_force_n > 0) || h.max_force_n > kForceCeilingN)
      throw Error(fmt::format("virtual participant: expected max_force_n in (0, {}] N, got {}",
                              kForceCeilingN, h.max_force_n));
    if (!(h.mass_kg > 0) || h.substeps < 1 || !(h.servo_rate_hz > 0))
      throw Error("virtual participant: mass, substeps and servo rate must be positive");
    if (!(p.force_n > 0) || !(p.speed_mm_s > 0) || p.strokes_per_model < 1 || p.taps_per_site < 1)
      throw Error("virtual participant: force, speed, strokes and taps must be positive");
    dinfo.name = "virtual participant on a simulated impedance device";
    dinfo.servo_rate_hz = h.servo_rate_hz;
    dinfo.max_force_n = h.max_force_n;
    dinfo.gravity_mm_s2 = Vec3::Zero();
  }

  double dt() const { return 1.0 / hand.servo_rate_hz; }
  double now() const { return double(ticks) * dt(); }
  double sensed() const { return force.norm(); }
  double elapsed() const { return double(ticks - action_start) * dt(); }

  // Force the person means to apply now: the level with a slow bounded fluctuation.
  double target_force() const {
    double phi = 0;
    for (int i = 0; i < 4; ++i)
      phi += prof.fluctuation_weight[i] *
             std::sin(2 * std::numbers::pi * prof.fluctuation_hz[i] * now() +
                      prof.fluctuation_phase[i]);
    return prof.force_n * (1 + prof.fluctuation * phi);
  }

  // The person's force loop: move the arm's set point down while the felt force is too small.
  void force_loop(double target) {
    vz_set = std::clamp(-hand.force_loop_gain * (target - sensed()), -hand.max_setpoint_speed,
                        hand.max_setpoint_speed);
    z_set += vz_set * dt();
  }

  bool move_xy_towards(const Vec2& goal, double speed) {
    const Vec2 d = goal - xy_set;
    const double dist = d.norm(), step = speed * dt();
    if (dist <= step) {
      xy_set = goal;
      vxy_set.setZero();
      return true;
    }
    vxy_set = d / dist * speed;
    xy_set += d / dist * step;
    return false;
  }

  void build_program(const SceneInfo& s);
  void start_action();
  bool run_action(const Action& a);  // true when the action is finished
  bool transit(const Action& a);
  bool press();
  bool stroke(const Action& a);
  bool tap(const Action& a);
  void judge(int cell);
  void physics();
};

void VirtualParticipant::Impl::build_program(const SceneInfo& s) {
  scene = s;
  program.clear();
  pc = 0;
  evidence.assign(s.cell_centres.size(), CellEvidence{});
  // Visit the circles row by row, alternating direction (a person sweeps the screen).
  std::vector<int> order(s.cell_centres.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = static_cast<int>(c);
  const double row_h = std::max(1e-9, s.cell_mm);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto ra = std::lround(s.cell_centres[a].y() / row_h),
               rb = std::lround(s.cell_centres[b].y() / row_h);
    if (ra != rb) return ra < rb;
    const bool reverse = ra % 2 != 0;
    return reverse ? s.cell_centres[a].x() > s.cell_centres[b].x()
                   : s.cell_centres[a].x() < s.cell_centres[b].x();
  });
  for (int c : order) {
    const Vec2 centre = s.cell_centres[c];
    if (s.task == Task::kShape) {
      const double phi0 = rng.uniform(0.0, std::numbers::pi);
      for (int k = 0; k < prof.strokes_per_model; ++k) {
        const double phi = phi0 + std::numbers::pi * k / prof.strokes_per_model;
        Vec2 dir(std::cos(phi), std::sin(phi));
        if (k % 2 == 1) dir = -dir;
        const Vec2 off = rng.normal(0.0, prof.aim_sd_mm) * Vec2(-dir.y(), dir.x());
        program.push_back(
            {Kind::kTransit, c, centre - prof.stroke_half_length_mm * dir + off, dir, true});
        program.push_back(
            {Kind::kPress, c, centre - prof.stroke_half_length_mm * dir + off, dir, true});
        program.push_back(
            {Kind::kStroke, c, centre + prof.stroke_half_length_mm * dir + off, dir, true});
      }
    } else {
      const double psi = rng.uniform(0.0, 2 * std::numbers::pi);
      const Vec2 surround =
          centre + prof.surround_tap_radius_mm * Vec2(std::cos(psi), std::sin(psi));
      for (int k = 0; k < 2 * prof.taps_per_site; ++k) {
        const bool at_centre = k % 2 == 0;
        const Vec2 site = (at_centre ? centre : surround) +
                          Vec2(rng.normal(0.0, prof.aim_sd_mm), rng.normal(0.0, prof.aim_sd_mm));
        program.push_back({Kind::kTransit, c, site, Vec2::UnitX(), at_centre});
        program.push_back({Kind::kTap, c, site, Vec2::UnitX(), at_centre});
      }
    }
    program.push_back({Kind::kTransit, c, centre, Vec2::UnitX(), true});
    program.push_back({Kind::kLabel, c, centre, Vec2::UnitX(), true});
  }
  start_action();
}

void VirtualParticipant::Impl::start_action() {
  action_start = ticks;
  contact = rising = false;
  settled = 0;
  tap_fit = LineFit{};
  tap_force = target_force();
  for (int w = 0; w < 3; ++w) {
    win_sum[w] = 0;
    win_n[w] = 0;
  }
}

// Lift to the hover height, then move above the target in the air.
bool VirtualParticipant::Impl::transit(const Action& a) {
  if (elapsed() > 5.0) return true;
  if (z_set < scene.hover_z_mm) {  // lift first
    vz_set = hand.lift_speed;
    z_set = std::min(scene.hover_z_mm, z_set + hand.lift_speed * dt());
    vxy_set.setZero();
    return false;
  }
  vz_set = 0;
  if (sensed() > hand.contact_force_n || x.z() < scene.hover_z_mm - 3) return false;  // not clear
  const bool there = move_xy_towards(a.target, hand.transit_speed);
  return there && (x.head<2>() - a.target).norm() < 0.3 && v.norm() < 10;
}

// Descend until contact, then hold until the force is within 5 % of the target for 150 ms.
bool VirtualParticipant::Impl::press() {
  vxy_set.setZero();
  if (elapsed() > 3.0) return true;
  if (!contact) {
    vz_set = -hand.approach_speed;
    z_set += vz_set * dt();
    contact = sensed() > hand.contact_force_n;
    return false;
  }
  const double target = target_force();
  force_loop(target);
  settled = std::abs(sensed() - target) < 0.05 * target ? settled + 1 : 0;
  return settled >= 150;
}

// Slide to the stroke's end under force control, summing HIP heights in the windows.
bool VirtualParticipant::Impl::stroke(const Action& a) {
  force_loop(target_force());
  if (sensed() > hand.contact_force_n) {
    const double u = (x.head<2>() - scene.cell_centres[a.cell]).dot(a.dir), au = std::abs(u);
    const auto& w = prof.shape;
    int bin = -1;
    if (au <= w.centre_half_mm)
      bin = 0;
    else if (au >= w.surround_inner_mm && au <= w.surround_outer_mm)
      bin = u < 0 ? 1 : 2;
    if (bin >= 0) {
      win_sum[bin] += x.z();
      ++win_n[bin];
    }
  }
  const double limit = 2 * prof.stroke_half_length_mm / prof.speed_mm_s + 2.0;
  if (!move_xy_towards(a.target, prof.speed_mm_s) && elapsed() < limit) return false;
  if (win_n[0] > 0 && win_n[1] > 0 && win_n[2] > 0)
    evidence[a.cell].stroke_contrast_mm.push_back(
        win_sum[0] / win_n[0] - 0.5 * (win_sum[1] / win_n[1] + win_sum[2] / win_n[2]));
  return true;
}

// Press down until the force reaches the tap force, then rise until contact is lost; the
// stiffness is the slope of force against HIP height while loading.
bool VirtualParticipant::Impl::tap(const Action& a) {
  vxy_set.setZero();
  if (!rising) {
    vz_set = -prof.tap_speed_mm_s;
    z_set += vz_set * dt();
    const double f = sensed();
    if (f > 0.15 * tap_force && f < 0.9 * tap_force) tap_fit.add(x.z(), f);
    rising = f >= tap_force || elapsed() > 3.0;
    return false;
  }
  vz_set = prof.tap_speed_mm_s;
  z_set += vz_set * dt();
  if (sensed() > hand.contact_force_n && elapsed() < 6.0) return false;
  const double k = -tap_fit.slope();
  if (tap_fit.n >= 5 && k > 0 && std::isfinite(k))
    (a.centre_site ? evidence[a.cell].k_centre : evidence[a.cell].k_surround).push_back(k);
  return true;
}

bool VirtualParticipant::Impl::run_action(const Action& a) {
  switch (a.kind) {
    case Kind::kTransit:
      return transit(a);
    case Kind::kPress:
      return press();
    case Kind::kStroke:
      return stroke(a);
    case Kind::kTap:
      return tap(a);
    case Kind::kLabel:
      judge(a.cell);
      return true;
  }
  return true;
}

void VirtualParticipant::Impl::judge(int cell) {
  CellEvidence& e = evidence[cell];
  int value;
  const bool lapse = rng.uniform() < prof.lapse_rate;
  if (scene.task == Task::kShape) {
    if (e.stroke_contrast_mm.empty() || lapse) {
      value = static_cast<int>(rng.below(3));
    } else {
      double mean = 0;
      for (double c : e.stroke_contrast_mm) mean += c;
      mean /= double(e.stroke_contrast_mm.size());
      value = static_cast<int>(rendering::classify_height_contrast(mean, prof.shape.threshold_mm));
    }
  } else {
    if (e.k_centre.empty() || e.k_surround.empty() || lapse) {
      value = static_cast<int>(rng.below(3));
    } else {
      // Each tap's stiffness is perceived with log-normal noise whose SD makes two single
      // taps differing by the Weber fraction 75 % discriminable (2AFC):
      // sigma = ln(1 + W) / (0.6745 sqrt 2).
      const double band = std::log(1 + prof.weber_fraction);
      const double sigma = band / (0.6745 * std::sqrt(2.0));
      auto perceived = [&](const std::vector<double>& ks) {
        double s = 0;
        for (double k : ks) s += std::log(k) + rng.normal(0.0, sigma);
        return s / double(ks.size());
      };
      const double r = perceived(e.k_centre) - perceived(e.k_surround);
      value = static_cast<int>(r > band    ? StiffnessClass::kHarder
                               : r < -band ? StiffnessClass::kSofter
                                           : StiffnessClass::kSame);
    }
  }
  e.label = value;
  pending = Label{scene.task, value};
}

void VirtualParticipant::Impl::physics() {
  const double h = dt() / hand.substeps;
  const double k_to_acc = 1000.0 / hand.mass_kg;  // N -> mm/s^2
  for (int s = 0; s < hand.substeps; ++s) {
    Vec3 f_hand;
    f_hand.head<2>() = hand.lateral_stiffness * (xy_set - x.head<2>()) +
                       hand.lateral_damping * (vxy_set - v.head<2>());
    f_hand.z() = hand.arm_stiffness * (z_set - x.z()) + hand.arm_damping * (vz_set - v.z());
    const Vec3 a = k_to_acc * (f_hand + force - hand.device_damping * v);
    v += a * h;
    x += v * h;
  }
}

// ---------------------------------------------------------------------------------------------
VirtualParticipant::VirtualParticipant(const ParticipantProfile& profile,
                                       const HandDeviceParams& hand)
    : impl_(std::make_unique<Impl>(profile, hand)) {}
VirtualParticipant::~VirtualParticipant() = default;

const DeviceInfo& VirtualParticipant::info() const {
  return impl_->dinfo;
}
double VirtualParticipant::time() const {
  return impl_->now();
}
Vec3 VirtualParticipant::position() const {
  return impl_->x;
}
Vec3 VirtualParticipant::force_sensor() const {
  return impl_->force;
}

void VirtualParticipant::command_force(const Vec3& force) {
  Impl& m = *impl_;
  if (!force.allFinite()) {
    m.force.setZero();
    return;
  }
  const double n = force.norm();
  m.force = n > m.hand.max_force_n ? Vec3(force * (m.hand.max_force_n / n)) : force;
}

void VirtualParticipant::tick() {
  Impl& m = *impl_;
  if (m.pc < m.program.size() && m.run_action(m.program[m.pc])) {
    ++m.pc;
    m.start_action();
  }
  m.physics();
  ++m.ticks;
}

void VirtualParticipant::begin_trial(const SceneInfo& scene) {
  Impl& m = *impl_;
  if (!m.placed && !scene.cell_centres.empty()) {
    const Vec2 c = scene.cell_centres.front();
    place(Vec3(c.x(), c.y(), scene.hover_z_mm));
  }
  m.pending.reset();
  m.build_program(scene);
}

std::optional<Label> VirtualParticipant::poll() {
  std::optional<Label> l;
  std::swap(l, impl_->pending);
  return l;
}

bool VirtualParticipant::quit() const {
  return impl_->pc >= impl_->program.size() && !impl_->pending;
}

const ParticipantProfile& VirtualParticipant::profile() const {
  return impl_->prof;
}
const std::vector<CellEvidence>& VirtualParticipant::evidence() const {
  return impl_->evidence;
}

void VirtualParticipant::place(const Vec3& p) {
  Impl& m = *impl_;
  m.x = p;
  m.v.setZero();
  m.xy_set = p.head<2>();
  m.vxy_set.setZero();
  m.z_set = p.z();
  m.vz_set = 0;
  m.placed = true;
}

}  // namespace inhap::lab
