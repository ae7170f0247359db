// Palpation cycles as CSV, so that a lab with a real device can record cycles with its own code
// and fit the sliding yield surfaces offline (`inhap sys fit`). Units: mm, N, s, rad.
//
// Columns (one row per loading-unloading cycle; '#' comment lines first):
//   point            reference point id (integer >= 0)
//   cx,cy,cz         nominal reference point c (probe centre), mm        [optional: p_c]
//   fn,ft            commanded normal and tangential load f_N, f_T, N
//   t_plateau        plateau duration, s
//   dir              tangential direction index k (integer >= 0)
//   angle            angle of t_k from t_0 around n_c, rad  [optional unless tx,ty,tz are absent]
//   tx,ty,tz         tangential loading direction t_k (unit)  [optional with angle and a normal]
//   pcx,pcy,pcz      contact point p_c, mm
//   ncx,ncy,ncz      outward surface normal n_c (unit)        [optional with a shape]
//   fmx,fmy,fmz      reaction force at t_measurement, N
//   umx,umy,umz      displacement u = p - p_c at t_measurement, mm
//   prx,pry,prz      release point p_r, mm (u^p = p_r - p_c)
//   t_measurement    when fm and um were taken, s after the plateau start, <= t_plateau
//                    (negative: during the loading ramps)        [optional: 0.09]
//   t_start          device time at the start of the cycle, s                [optional]
//   status           0 ok, 1 no contact, 2 saturated, 3 unsettled, 4 bad input,
//                    5 slip capped (unloaded early after max_slip)      [optional: 0]
//
// A rig that does not log the frame: without ncx,ncy,ncz the normal is the shape's outward
// normal at the point closest to p_c; without tx,ty,tz the direction is
// t_k = cos(angle) t_0 + sin(angle) t_1, with t_0 the tangent reference projected onto the
// tangent plane of n_c (tangent_basis), as the palpation protocol builds it.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/shape_query.hpp"

namespace inhap::friction {

/// What the reader uses to complete rows without normal or tangent columns.
struct CycleGeometry {
  /// The probe-centre surface (e.g. a MeshSurface of the shape mesh): n_c when ncx,ncy,ncz are
  /// absent. nullptr: those columns are required.
  const ShapeQuery* shape = nullptr;
  /// t_0 is this world direction projected onto the tangent plane (sys fit --tangent-reference).
  Vec3 tangent_reference = Vec3::UnitX();
  /// p_c farther than this from the shape is an error, mm.
  double max_distance_mm = 5.0;
};

/// Writes cycles atomically (temporary file + rename).
void write_cycles_csv(const std::string& path, std::span<const CycleRecord> cycles);
/// Reads cycles; throws ParseError naming the file and line on a missing column, a non-integer
/// id, a non-finite value, a zero normal/direction or a measurement after the plateau.
std::vector<CycleRecord> read_cycles_csv(const std::string& path,
                                         const CycleGeometry& geometry = {});

}  // namespace inhap::friction
