// The virtual lab from the command line. Units: mm, N, s, N/mm.
#include "inhap/eval/lab_files.hpp"

#include <fmt/format.h>

#include <cmath>

#include "inhap/core/error.hpp"

namespace inhap::eval {

lab::Scene pick_scene(const std::string& name, const std::string& file) {
  if (!name.empty() && !file.empty()) throw Error("give either --scene or --scene-file, not both");
  if (!file.empty()) return lab::load_scene(file);
  if (name.empty())
    throw Error("expected --scene NAME or --scene-file FILE.json (see `inhap lab scenes`)");
  return lab::builtin_scene(name);
}

std::string scenes_table() {
  std::string s = fmt::format("{:<21} {:>12}  {}\n", "scene", "k@5N (N/mm)", "description");
  for (const auto& name : lab::builtin_scene_names()) {
    const lab::Scene scene = lab::builtin_scene(name);
    const Vec2 c = scene.region.center;
    const double k = scene.object.stiffness_at(Vec3(c.x(), c.y(), 1e3), 5.0);
    s += fmt::format("{:<21} {:>12.2f}  {}\n", name, k, scene.description);
  }
  return s;
}

void require_finite_recording(const Recording& rec, const std::string& out) {
  for (std::size_t i = 0; i < rec.size(); ++i)
    if (!std::isfinite(rec.t[i]) || !rec.p[i].allFinite() || !rec.f[i].allFinite())
      throw Error(fmt::format(
          "{}: refusing to write row {} (t = {} s): a position or force is not finite (the "
          "scene's sizes or positions are out of range?)",
          out, i + 1, rec.t[i]));
}

}  // namespace inhap::eval
