// Virtual lab: scenes = one soft object (shape, material, inclusions) plus the region of its
// top that operators work on. Built-in scenes reproduce the thesis' objects; scene files are
// JSON (schema in docs/virtual-lab.md).
//
// Units: mm, N, s; k in N/mm^exponent, k_t in N/mm, damping (Hunt-Crossley c) in s/mm,
// creep (slip viscosity c_v) in N s/mm.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "inhap/lab/soft_object.hpp"

namespace inhap::lab {

/// Disk on the xy plane over which operators tap and explore (they look down from +z).
struct Region {
  Vec2 center = Vec2::Zero();
  double radius = 30.0;  ///< mm
};

struct Scene {
  std::string name;
  std::string description;
  SoftObject object;
  Region region;
  std::string source = "builtin";  ///< file the scene came from
};

/// Names of the built-in scenes: planar, dome, sponge, silicone-hemisphere, foam-ball,
/// ridged-silicone, silicone-block.
std::vector<std::string> builtin_scene_names();
/// A built-in scene; throws Error listing the names when unknown.
Scene builtin_scene(std::string_view name);
/// The five tapping objects of thesis fig. 3.3.
std::vector<std::string> tapping_scene_names();

/// Parses a scene from JSON text; `source` names the file in errors (ParseError).
Scene parse_scene(std::string_view json_text, const std::string& source);
/// Loads a JSON scene file (mesh paths are relative to the file's folder).
Scene load_scene(const std::string& path);
/// Pretty JSON that parse_scene() reads back to the same scene.
std::string scene_to_json(const Scene& scene);
/// Writes scene_to_json atomically.
void save_scene(const std::string& path, const Scene& scene);

/// Default operator region for a shape: centred on its bounds, 35 % of the smaller xy extent.
Region default_region(const Shape& shape);

}  // namespace inhap::lab
