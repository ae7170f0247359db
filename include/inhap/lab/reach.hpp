// Virtual lab: where a person holding a stylus can tap an object resting on a table. Units: mm.
//
// The table is the plane z = (bottom of the object's bounds). A surface point x with outward
// normal n is *reachable* when
//   - it is not the base: x lies at least `base_margin_mm` above the table;
//   - the stylus can come straight in along the normal: the segment x + s n, s in
//     [start_mm, stylus_length_mm], keeps the probe clear of the object (every point farther
//     than the probe radius + `clearance_mm` from the surface) and stays `table_clearance_mm`
//     above the table;
//   - the hand can get there from above: the vertical segment from x + stylus_length_mm n up to
//     above the object is clear as well.
// The tapping operator (whole-object mode, its default) taps only such points and `inhap eval
// shape` measures its coverage over the same set.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/lab/soft_object.hpp"

namespace inhap::lab {

struct ReachOptions {
  double stylus_length_mm = 50.0;   ///< straight approach segment that must be clear
  double start_mm = 1.0;            ///< the segment starts this far out along the normal
  double clearance_mm = 0.2;        ///< the probe must pass farther than this from the surface
  double table_clearance_mm = 1.0;  ///< the segment stays this far above the table
  double base_margin_mm = 2.0;      ///< points lower than this above the table are the base
};

struct SurfaceSample {
  Vec3 point;   ///< on the undeformed surface, mm
  Vec3 normal;  ///< outward unit normal
};

/// Height of the table the object rests on (bottom of its bounds), mm.
double table_height(const SoftObject& object);

/// True when a probe of radius r moves straight from a to b without coming within
/// r + clearance_mm of the object (sphere tracing on the exact distance).
bool segment_clear(const SoftObject& object, double r, const Vec3& a, const Vec3& b,
                   double clearance_mm = 0.2);

/// The reachability rule above for surface point x with outward normal n; `approach` is the
/// stylus direction (the normal, or the normal tilted as a hand holds it).
bool reachable(const SoftObject& object, double probe_radius, const Vec3& x, const Vec3& approach,
               const ReachOptions& options = {});

/// About `count` points spread uniformly by area over the whole surface (mesh shapes: seeded
/// area-weighted triangle sampling; analytic shapes: seeded points of a 0.3 mm shell around
/// the surface projected onto it). `area_mm2` receives the surface area (estimated for analytic
/// shapes) when not null.
std::vector<SurfaceSample> sample_object_surface(const SoftObject& object, std::size_t count,
                                                 std::uint64_t seed, double* area_mm2 = nullptr);

/// The reachable ones (approach along the normal) among sample_object_surface(count, seed).
std::vector<SurfaceSample> reachable_samples(const SoftObject& object, double probe_radius,
                                             std::size_t count, std::uint64_t seed,
                                             const ReachOptions& options = {});

}  // namespace inhap::lab
