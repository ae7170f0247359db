// A simulated stroke (stroke.hpp) as a CSV file, tick by tick, and in one line.
// Units: t s; HIP, IHIP, CIHIP, s and t mm; force N; k N/mm.
#pragma once

#include <string>
#include <vector>

#include "inhap/rendering/stroke.hpp"

namespace inhap::rendering {

/// Columns t, px,py,pz (HIP), qx,qy,qz (IHIP), cx,cy,cz (CIHIP), fx,fy,fz, k, s, tx,ty,tz (mesh
/// compensation), contact (0/1); `command` is the first comment line, the units the second.
void write_stroke_csv(const std::string& path, const std::vector<StrokeSample>& samples,
                      const std::string& command);

/// "N ticks (T s), n in contact, mean contact force F N".
std::string stroke_summary(const std::vector<StrokeSample>& samples);

}  // namespace inhap::rendering
