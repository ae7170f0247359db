// Virtual lab: simulated operators (people holding the stylus) and the recording driver.
// Units: mm, N, s.
//
// An operator holds the stylus through a simulated hand (an impedance, see sim_device.hpp) and
// decides, every tick, where the hand wants the probe to be. Like a person it perceives the
// contact force with a reaction delay (80-120 ms), plans with an imperfect idea of where the
// surface is, trembles slightly (8-12 Hz physiological tremor plus slow drift) and varies
// speeds, forces and durations from gesture to gesture. Everything random comes from its seed.
//
//   tap      thesis ch. 3 shape modeling: taps every surface point a stylus reaches on the
//            object resting on its table (tops, sides, reachable overhangs, not the base;
//            reach.hpp), approached along the local normal, spots spread evenly (progressive
//            Poisson-disk choice, nearest unvisited spot next): approach 30-200 mm/s
//            (log-uniform), press to a peak of 1-4 N, dwell, retract, move on (>= 1 tap/s).
//            TapOptions::whole_object = false: the earlier top-cap protocol, random points of
//            the scene's region seen from above (normal within 50 deg of +z), 20-200 mm/s.
//   explore  free exploration for force modeling (thesis 4.4.1): pushes up to 5 N, deep pushes,
//            strokes, rubbing circles, then a sliding-only passage (the last third) that never
//            leaves the surface; the normal force is regulated like a person would (delayed
//            feedback on a feed-forward guess). ExploreOptions::coverage gives a training mode
//            that visits the region systematically (grid of spots, each pressed to every depth,
//            slides between them).
//   air      moves the probe in free air above the object with tapping-like accelerations
//            (for compensation tests: the contact force is zero throughout).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "inhap/core/progress.hpp"
#include "inhap/lab/physics.hpp"
#include "inhap/lab/reach.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::lab {

class HandOperator {
 public:
  virtual ~HandOperator() = default;
  virtual std::string name() const = 0;
  /// Called once before the first tick: attaches the hand and places the probe.
  virtual void begin(SimDevice& device) = 0;
  /// Called every tick before the device advances: sets the hand target for the tick's end.
  virtual void step(SimDevice& device) = 0;
};

struct TapOptions {
  double min_speed = 20.0, max_speed = 200.0;  ///< approach speed range, mm/s (log-uniform)
  double min_force = 1.0, max_force = 4.0;     ///< planned peak force range, N
  double max_tilt_deg = 50.0;                  ///< accepted surface-normal angle from +z
  /// Whole-object mode, the default (thesis ch. 3: the user tapped each object all over what
  /// the stylus reaches): spots from the reachable surface (reach.hpp) instead of the region's
  /// disk, seen from above. Each next spot is the one nearest the hand among the reachable
  /// candidates at least `spacing` from every earlier tap on the same side (normals within 90 deg);
  /// when none is left the spacing shrinks by 0.8 (it starts at a fifth of the object's size), so
  /// the taps cover the object evenly at any moment and no spot is tapped twice. The approach is
  /// the normal tilted up to 12 deg (the normal when the tilted stylus would not be clear).
  /// Pauses, dwell and retraction are those of a person going round an object (>= 1 tap/s);
  /// approaches no slower than 30 mm/s; a move between spots backs out along the approach line
  /// only as far as clears the way (10, 20, 35 mm, the stylus length), else goes over.
  /// The default. false: the earlier top-cap protocol (random points of the scene's region
  /// seen from above, normals within max_tilt_deg of +z; `--region top`).
  bool whole_object = true;
  ReachOptions reach;
  std::size_t candidates = 30000;  ///< whole-object mode: surface samples the spots come from
};

struct ExploreOptions {
  double max_force = 5.0;             ///< N
  double sliding_fraction = 1.0 / 3;  ///< final share of the duration that only slides
  /// Coverage-driven training mode (thesis 4.4.1: the operator explores the whole object): for
  /// the first coverage_share of the duration a hexagonal grid of spots over the region, spaced
  /// so that one pass fills that time, is visited row by row (serpentine; rim included); at each
  /// spot the operator loads to a deep push (0.8-0.95 max_force) and back, so every spot gets
  /// every depth; between spots it slides at coverage_force_min..max or (every fourth spot, and
  /// at the start) lifts and approaches from the air; after a spot, now and then a long random
  /// stroke at those forces. After that the ordinary random exploration follows (its
  /// sliding-only passage included).
  bool coverage = false;
  double coverage_share = 0.65;     ///< coverage mode: share of the duration spent on the grid
  double seconds_per_spot = 1.5;    ///< coverage mode: planned time per spot (sets the spacing), s
  double stroke_probability = 0.3;  ///< coverage mode: chance of a long stroke after a spot
  /// Coverage mode: force range of the slides between spots and of the strokes, N (default: the
  /// random exploration's strokes and circles, 0.5-3 N).
  double coverage_force_min = 0.5, coverage_force_max = 3.0;
};

/// The operator names make_operator() accepts: tap, explore, air.
std::vector<std::string> operator_names();
std::unique_ptr<HandOperator> make_tap_operator(const Scene& scene, std::uint64_t seed,
                                                TapOptions options = {});
std::unique_ptr<HandOperator> make_explore_operator(const Scene& scene, std::uint64_t seed,
                                                    double seconds, ExploreOptions options = {});
std::unique_ptr<HandOperator> make_air_operator(const Scene& scene, std::uint64_t seed);
/// By name; throws Error listing the names when unknown.
std::unique_ptr<HandOperator> make_operator(std::string_view name, const Scene& scene,
                                            std::uint64_t seed, double seconds);

/// Runs `op` on the device for `seconds` (round(seconds * rate) ticks, one row each).
/// `progress("recording", fraction, 0)` is called about every simulated second.
LabRecording record(SimDevice& device, HandOperator& op, double seconds,
                    const Progress& progress = {});

/// Everything `inhap lab record` needs.
struct RecordSpec {
  std::string operator_name = "explore";
  double seconds = 60.0;
  std::uint64_t seed = 1;
  ProbeSpec probe;
  bool noise = true, gravity = true, inertia = true;
  Physics physics = Physics::kBuiltin;  ///< contact physics of the device (physics.hpp)
  TapOptions tap;                       ///< operator "tap" only
  ExploreOptions explore;               ///< operator "explore" only
};

/// The device and operator of a recording: the device's noise seed and the operator's seed are
/// derived from spec.seed. record_scene runs them; a bridge client (eval/lab_device.hpp) runs the
/// same pair tick by tick, so both give the same samples.
struct RecordSetup {
  std::unique_ptr<SimDevice> device;
  std::unique_ptr<HandOperator> op;
  DeviceParams params;
};
RecordSetup make_record_setup(const Scene& scene, const RecordSpec& spec);
/// The provenance comments record_scene writes.
std::vector<std::string> record_comments(const Scene& scene, const RecordSpec& spec,
                                         const RecordSetup& setup);

/// Builds the device (noise seed and operator seed derived from spec.seed), runs the operator
/// and returns the recording with provenance comments.
LabRecording record_scene(const Scene& scene, const RecordSpec& spec,
                          const Progress& progress = {});

}  // namespace inhap::lab
