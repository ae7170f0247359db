// Servo-rate rendering of a data-driven force model (thesis sec. 4.4-4.5).
//
// Units: positions mm, velocities mm/s, forces N, time s (one step = one servo period,
// model.foaw.dt_s, 1 ms at 1 kHz).
//
// Model/state split: the ForceModel is immutable and shared; ServoState holds the FOAW buffer
// and the contact/proxy bookkeeping of one device. servo_step() is the servo call: no heap
// allocation, no exceptions, no I/O, bounded time.
//
// The proxy q comes from outside (the sliding-yield-surface proxy estimator of the friction
// module, a recording's qx,qy,qz columns, or the lab's ground truth), together with the
// contact flag; EntryProxyState gives the pre-thesis baseline q = p at contact onset.
#pragma once

#include <cstdint>

#include "inhap/core/types.hpp"
#include "inhap/datadriven/foaw.hpp"
#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {

struct ServoState {
  FoawState foaw;                ///< velocity filter buffer
  bool contact = false;          ///< contact at the last step
  Vec3 velocity = Vec3::Zero();  ///< last FOAW estimate, mm/s
  Vec3 force = Vec3::Zero();     ///< last output, N
  Vec3 q = Vec3::Zero();         ///< proxy at the last step in contact, mm
  double slip = 0;           ///< proxy speed since the tick before, mm/s (0: held, kSlidingStepMm)
  int bin = -1;              ///< bin used at the last step (-1 out of contact)
  std::uint32_t resets = 0;  ///< how many times bad input forced a reset

  void reset() {
    const std::uint32_t r = resets + 1;
    *this = ServoState{};
    resets = r;
  }
};

/// Positions farther than this from the origin are treated as absurd input, mm.
inline constexpr double kAbsurdPositionMm = 1e5;

/// A probe step of at least this length in one tick is a tracking glitch (20 mm/tick = 20 m/s
/// at 1 kHz, as the mesh renderer's max_jump_mm): zero force and a state reset, mm.
inline constexpr double kMaxJumpMm = 20.0;

/// One servo tick: probe centre p (mm), proxy q (mm) and contact flag in, force (N) out. The
/// proxy slides when it moved by more than kSlidingStepMm since the last tick, both in contact;
/// its speed is that step over the filter's dt_s (ForceModel::sliding_mu).
/// Zero force out of contact; the FOAW filter is updated every tick. Non-finite or absurd p or
/// q gives zero force and a state reset, as does a jump of p by kMaxJumpMm or more in one tick
/// (the tick after it renders as from a fresh state). The force is always finite and clamped
/// to model.force_limit_n, itself capped by the device's limit (kDeviceForceLimitN).
Vec3 servo_step(const ForceModel& model, ServoState& state, const Vec3& p, const Vec3& q,
                bool contact);
/// The same with the outward surface normal at q (the proxy estimator's frame; needed by
/// FeatureSet::kLocalFrame models, ignored by the others). A non-finite normal gives +z.
Vec3 servo_step(const ForceModel& model, ServoState& state, const Vec3& p, const Vec3& q,
                const Vec3& normal, bool contact);
/// The same with the velocity filter `foaw` in place of model.foaw: the model's filter at the
/// rate the samples come in (FoawParams::at_period), when it differs from the training's.
Vec3 servo_step(const ForceModel& model, const FoawParams& foaw, ServoState& state, const Vec3& p,
                const Vec3& q, const Vec3& normal, bool contact);

/// Baseline proxy without the sliding yield surface: q = p_c, the probe centre at contact
/// onset, held while contact lasts (the "u = p - p_c" of earlier data-driven methods).
struct EntryProxyState {
  bool contact = false;
  Vec3 entry = Vec3::Zero();
};
inline Vec3 entry_proxy(EntryProxyState& s, const Vec3& p, bool contact) {
  if (contact && !s.contact) s.entry = p;
  s.contact = contact;
  return contact ? s.entry : p;
}

}  // namespace inhap::datadriven
