// A simulated constant-force stroke across a rendered mesh (thesis ch. 5.3): a simple
// force-tracking hand descends onto the surface, holds the wanted force, strokes in a straight
// line at constant speed while regulating the force (force-constancy model), then lifts off.
// Used by `inhap tca stroke` and by tests; the fuller virtual participant lives elsewhere.
//
// Units: positions mm, forces N, time s, speeds mm/s, stiffness N/mm.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/rendering/renderer.hpp"

namespace inhap::rendering {

/// "tca" (TCA-MESH) or "cba" (the god-object); nothing for any other word.
std::optional<Algorithm> parse_algorithm(std::string_view s);

struct StrokeOptions {
  Vec2 from = Vec2::Zero();           ///< start (x, y) of the stroke, mm
  Vec2 to = Vec2::Zero();             ///< end (x, y), mm
  double force_n = 1.0;               ///< force the hand holds, N
  double speed_mm_s = 20.0;           ///< lateral stroke speed, mm/s
  double approach_speed_mm_s = 20.0;  ///< descent (and lift-off) speed in free space, mm/s
  /// Time constant of the hand's force regulation, s: the hand moves along z by
  /// (|f| - F) / (k tau) per second, k the stiffness it feels (N/mm).
  double force_time_constant_s = 0.03;
  double max_vertical_speed_mm_s = 100.0;  ///< cap of the hand's vertical speed, mm/s
  double settle_s = 0.2;                   ///< hold time at the start once the force is reached, s
  double tremor_n = 0.0;      ///< RMS of the hand's force error (10 Hz low-passed noise), N
  std::uint64_t seed = 1;     ///< seed of the tremor noise
  double rate_hz = 1000.0;    ///< servo rate, Hz
  double clearance_mm = 5.0;  ///< the probe starts this far above the mesh's top, mm
  double timeout_s = 600.0;   ///< give up (Error) after this much simulated time, s
};

/// One servo tick of a stroke (thesis notation: p HIP, q IHIP, q' CIHIP).
struct StrokeSample {
  double time = 0;            ///< s
  Vec3 hip = Vec3::Zero();    ///< p(n), mm
  Vec3 ihip = Vec3::Zero();   ///< q(n), mm (equals p in free space)
  Vec3 cihip = Vec3::Zero();  ///< q'(n), mm (equals p in free space)
  Vec3 force = Vec3::Zero();  ///< rendered force on the probe, N
  double k = 0;               ///< k(n), N/mm (0 in free space)
  double s = 0;               ///< s(n), mm
  Vec3 t = Vec3::Zero();      ///< mesh compensation vector after the tick, mm
  bool contact = false;
};

/// Runs the stroke with a fresh State. Throws Error on bad options, when no surface is found
/// below `from`, or on timeout.
std::vector<StrokeSample> simulate_stroke(const Model& model, Algorithm algorithm,
                                          const StrokeOptions& options);

}  // namespace inhap::rendering
