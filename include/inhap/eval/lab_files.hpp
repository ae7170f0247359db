// The virtual lab from the command line (`inhap lab scenes|record`): choosing a scene, the scene
// table, and the check a recording passes before it is written. Units: mm, N, s, N/mm.
#pragma once

#include <string>

#include "inhap/core/csv.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {

/// The built-in scene `name` or the scene file `file` (exactly one of them; Error otherwise).
lab::Scene pick_scene(const std::string& name, const std::string& file);

/// One line per built-in scene: name, stiffness at 5 N in the region's centre (N/mm), description.
std::string scenes_table();

/// Error naming `out` and the row when a time, position or force of `rec` is not finite (inhap
/// could not read it back: the scene or the operator drove the simulation out of range).
void require_finite_recording(const Recording& rec, const std::string& out);

}  // namespace inhap::eval
