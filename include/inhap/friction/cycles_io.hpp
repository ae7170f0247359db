// Palpation cycles as CSV, so that a lab with a real device can record cycles with its own code
// and fit the sliding yield surfaces offline (`inhap sys fit`). Units: mm, N, s, rad.
//
// Columns (one row per loading-unloading cycle; '#' comment lines first):
//   point            reference point id (integer >= 0)
//   cx,cy,cz         nominal reference point c (probe centre), mm        [optional: p_c]
//   fn,ft            commanded normal and tangential load f_N, f_T, N
//   t_plateau        plateau duration, s
//   dir              tangential direction index k (integer >= 0)
//   angle            angle of t_k from t_0 around n_c, rad                 [optional]
//   tx,ty,tz         tangential loading direction t_k (unit)
//   pcx,pcy,pcz      contact point p_c, mm
//   ncx,ncy,ncz      outward surface normal n_c (unit)
//   fmx,fmy,fmz      reaction force at t_measurement, N
//   umx,umy,umz      displacement u = p - p_c at t_measurement, mm
//   prx,pry,prz      release point p_r, mm (u^p = p_r - p_c)
//   t_start          device time at the start of the cycle, s                [optional]
//   status           0 ok, 1 no contact, 2 saturated, 3 unsettled, 4 bad input,
//                    5 slip capped (unloaded early after max_slip)      [optional: 0]
#pragma once

#include <span>
#include <string>
#include <vector>

#include "inhap/friction/palpation.hpp"

namespace inhap::friction {

/// Writes cycles atomically (temporary file + rename).
void write_cycles_csv(const std::string& path, std::span<const CycleRecord> cycles);
/// Reads cycles; throws ParseError naming the file and line on a missing column, a non-integer
/// id, a non-finite value or a zero normal/direction.
std::vector<CycleRecord> read_cycles_csv(const std::string& path);

}  // namespace inhap::friction
