// The virtual lab from the command line (`inhap lab scenes|record`): choosing a scene, the scene
// table, and the check a recording passes before it is written. Units: mm, N, s, N/mm.
#pragma once

#include <cstdint>
#include <string>

#include "inhap/core/csv.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {

/// The built-in scene `name` or the scene file `file` (exactly one of them; Error otherwise).
lab::Scene pick_scene(const std::string& name, const std::string& file);

/// One line per built-in scene: name, stiffness at 5 N in the region's centre (N/mm), description.
std::string scenes_table();

/// Error naming `out` and the row when a time, position or force of `rec` is not finite (inhap
/// could not read it back: the scene or the operator drove the simulation out of range).
void require_finite_recording(const Recording& rec, const std::string& out);

/// The flags of `lab record` that shape the simulation.
struct LabRecordRequest {
  std::string op = "explore";    ///< tap | explore | air
  std::string probe = "sphere";  ///< sphere | tip
  std::string physics = "builtin";
  double seconds = 60;
  std::uint64_t seed = 1;
  /// Tap operator: "reachable" (every surface a stylus reaches on the object as it rests, the
  /// thesis' protocol) or "top" (the scene's region seen from above, the top-cap protocol).
  std::string region = "reachable";
  /// `--whole-object`: accepted for old command lines; the reachable region is the default.
  /// Error together with region "top".
  bool whole_object = false;
  bool no_noise = false, no_gravity = false, no_inertia = false, coverage = false;
  /// Logging rate, Hz: the servo and physics run at 1 kHz, the file keeps the tick nearest each
  /// jittered logging instant (as a real rig's logger at a lower rate does). 1000 = every tick.
  double rate_hz = 1000;
};

/// The ticks a logger at `rate_hz` keeps: the one nearest each instant k / rate_hz +- 20 % of
/// its period (uniform jitter, seeded), every tick at >= 1000 Hz. Rows of the recording and of
/// its truth alike; a comment line says so.
lab::LabRecording downsample_recording(const lab::LabRecording& lab, double rate_hz,
                                       std::uint64_t seed);
/// The lab's RecordSpec for them. Error naming the flag for an unknown probe or region,
/// --whole-object with --region top, or --coverage with an operator other than explore.
lab::RecordSpec lab_record_spec(const LabRecordRequest& r);

/// Recordings longer than this (s) get a note on their size.
inline constexpr double kLongRecordingS = 600.0;
/// Bytes of CSV per 1 kHz tick: a recording row plus its truth row, roughly.
inline constexpr double kBytesPerTick = 400.0;
/// The note on the size of a long recording (empty up to kLongRecordingS).
std::string long_recording_note(double seconds);

}  // namespace inhap::eval
