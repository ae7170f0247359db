// sys.json reader/writer (see docs/sliding-yield-surface.md for the format).
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/json_guard.hpp"
#include "inhap/friction/sys_model.hpp"

namespace inhap::friction {

using nlohmann::json;

namespace {

json vec(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

json border_options(const BorderOptions& o) {
  return {{"weight_up", o.weight_up},
          {"weight_growth", o.weight_growth},
          {"floor_up", o.floor_up},
          {"floor_growth", o.floor_growth},
          {"min_sliding_growth", o.min_sliding_growth},
          {"refine", o.refine},
          {"refine_points", o.refine_points}};
}

// Reader helpers: every failure names the file and the JSON path.
struct Reader {
  static constexpr double kMaxMagnitude = 1e6;
  const std::string& file;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw ParseError(file, 0, fmt::format("{}: expected {}", where, what));
  }
  const json& at(const json& j, const char* key, const std::string& where) const {
    if (!j.is_object() || !j.contains(key)) fail(where, fmt::format("key \"{}\"", key));
    return j.at(key);
  }
  double number(const json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, fmt::format("a number, got {}", j.dump().substr(0, 24)));
    const double v = j.get<double>();
    // Every quantity of the file (N, mm, s, N/mm) is far below 1e6: a larger one is no
    // measurement, and 1e308 would overflow the first sum it enters.
    if (!std::isfinite(v) || std::abs(v) > kMaxMagnitude)
      fail(where, fmt::format("a finite number of magnitude at most {:g}", kMaxMagnitude));
    return v;
  }
  double number(const json& j, const char* key, const std::string& where) const {
    return number(at(j, key, where), where + "." + key);
  }
  int integer(const json& v, const std::string& where) const {
    // is_number_integer() also holds for unsigned values past INT_MAX (4e9 must not wrap).
    if (!v.is_number_integer()) fail(where, "an integer");
    if (v.is_number_unsigned()
            ? v.get<std::uint64_t>() > static_cast<std::uint64_t>(kIntMax)
            : (v.get<std::int64_t>() > kIntMax || v.get<std::int64_t>() < -kIntMax))
      fail(where, fmt::format("an integer of at most {} in magnitude, got {}", kIntMax,
                              v.dump().substr(0, 24)));
    return static_cast<int>(v.get<std::int64_t>());
  }
  int integer(const json& j, const char* key, const std::string& where) const {
    return integer(at(j, key, where), where + "." + key);
  }
  static constexpr std::int64_t kIntMax = 2147483647;
  bool boolean(const json& j, const char* key, const std::string& where, bool dflt) const {
    if (!j.contains(key)) return dflt;
    if (!j.at(key).is_boolean()) fail(where + "." + key, "true or false");
    return j.at(key).get<bool>();
  }
  const json& array(const json& j, const char* key, const std::string& where,
                    std::size_t min = 0) const {
    const json& v = at(j, key, where);
    if (!v.is_array() || v.size() < min)
      fail(where + "." + key, fmt::format("an array of at least {} entries", min));
    return v;
  }
  std::vector<double> numbers(const json& j, const char* key, const std::string& where,
                              std::size_t min) const {
    const json& a = array(j, key, where, min);
    std::vector<double> out;
    for (std::size_t i = 0; i < a.size(); ++i)
      out.push_back(number(a[i], fmt::format("{}.{}[{}]", where, key, i)));
    return out;
  }
  Vec3 vec3(const json& j, const char* key, const std::string& where) const {
    const std::vector<double> v = numbers(j, key, where, 3);
    if (v.size() != 3) fail(where + "." + key, "3 numbers");
    return Vec3(v[0], v[1], v[2]);
  }
};

}  // namespace

void write_sys_json(const std::string& path, const SysModel& m) {
  json j;
  j["format"] = "inhap-sys";
  j["version"] = SysModel::kFormatVersion;
  j["units"] = {{"position", "mm"}, {"force", "N"}, {"time", "s"}, {"angle", "rad"}};
  j["f_normal_levels"] = m.f_normal_levels;
  j["angles"] = m.angles;
  j["plateaus"] = m.plateaus;
  j["tangent_reference"] = vec(m.tangent_reference);
  j["border_options"] = border_options(m.border_options);
  j["force_frame"] = to_string(m.force_frame);
  json pts = json::array();
  for (const SysPoint& p : m.points) {
    json jp;
    jp["id"] = p.id;
    jp["position"] = vec(p.position);
    jp["normal"] = vec(p.normal);
    jp["creep_viscosity"] = p.creep_viscosity;
    jp["tangential_stiffness"] = p.tangential_stiffness;
    json bs = json::array();
    for (const SysBorder& b : p.borders) {
      json steps = json::array();
      for (std::size_t s = 0; s < b.steps.size(); ++s) {
        const BorderStep& st = b.steps[s];
        steps.push_back({st.f_tangential, st.u_short, st.u_long, st.depth, st.radius,
                         s < b.result.labels.size() ? b.result.labels[s] : 0});
      }
      bs.push_back({{"f_normal", b.f_normal},
                    {"direction", b.direction},
                    {"f_limit", b.result.f_limit},
                    {"f_limit_load", b.result.f_limit_load},
                    {"ratio_limit", std::isfinite(b.result.ratio_limit) ? json(b.result.ratio_limit)
                                                                        : json(nullptr)},
                    {"depth", b.result.depth},
                    {"radius", b.result.radius},
                    {"split", b.result.split},
                    {"no_sliding", b.result.no_sliding},
                    {"all_sliding", b.result.all_sliding},
                    {"extrapolated", b.result.extrapolated},
                    {"growth_slope", b.result.growth_slope},
                    {"steps", steps}});
    }
    jp["borders"] = bs;
    pts.push_back(jp);
  }
  j["points"] = pts;
  json tris = json::array();
  for (const Tri& t : m.reference_mesh.triangles()) tris.push_back({t[0], t[1], t[2]});
  j["triangles"] = tris;
  j["columns"] = {{"steps", {"f_tangential", "u_short", "u_long", "depth", "radius", "label"}}};
  require_finite_json(j, path);
  write_file_atomic(path, j.dump(1) + "\n");
}

SysBorder read_border(const Reader& r, const json& jb, const std::string& wb, double level,
                      std::size_t direction) {
  SysBorder sb;
  sb.f_normal = r.number(jb, "f_normal", wb);
  sb.direction = r.integer(jb, "direction", wb);
  if (std::abs(sb.f_normal - level) > 1e-6 || sb.direction != static_cast<int>(direction))
    r.fail(wb, fmt::format("level {} N and direction {} (level-major order)", level, direction));
  sb.result.f_limit = r.number(jb, "f_limit", wb);
  sb.result.f_limit_load =
      jb.contains("f_limit_load") ? r.number(jb, "f_limit_load", wb) : sb.result.f_limit;
  if (jb.contains("ratio_limit") && !jb["ratio_limit"].is_null())
    sb.result.ratio_limit = r.number(jb, "ratio_limit", wb);
  sb.result.depth = r.number(jb, "depth", wb);
  sb.result.radius = r.number(jb, "radius", wb);
  if (sb.result.f_limit < 0 || sb.result.radius < 0) r.fail(wb, "f_limit >= 0 and radius >= 0");
  sb.result.split = static_cast<std::size_t>(std::max(0, r.integer(jb, "split", wb)));
  sb.result.no_sliding = r.boolean(jb, "no_sliding", wb, false);
  sb.result.all_sliding = r.boolean(jb, "all_sliding", wb, false);
  sb.result.extrapolated = r.boolean(jb, "extrapolated", wb, false);
  if (jb.contains("growth_slope")) sb.result.growth_slope = r.number(jb, "growth_slope", wb);
  const json& steps = r.array(jb, "steps", wb);
  for (std::size_t s = 0; s < steps.size(); ++s) {
    const std::string ws = fmt::format("{}.steps[{}]", wb, s);
    if (!steps[s].is_array() || steps[s].size() != 6)
      r.fail(ws, "[f_tangential, u_short, u_long, depth, radius, label]");
    BorderStep st;
    st.f_tangential = r.number(steps[s][0], ws);
    st.u_short = r.number(steps[s][1], ws);
    st.u_long = r.number(steps[s][2], ws);
    st.depth = r.number(steps[s][3], ws);
    st.radius = r.number(steps[s][4], ws);
    sb.result.labels.push_back(r.number(steps[s][5], ws) != 0.0);
    sb.steps.push_back(st);
  }
  return sb;
}

SysPoint read_point(const Reader& r, const json& jp, const std::string& w, const SysModel& m) {
  const std::size_t nl = m.f_normal_levels.size(), nk = m.angles.size();
  SysPoint p;
  p.id = r.integer(jp, "id", w);
  p.position = r.vec3(jp, "position", w);
  p.normal = r.vec3(jp, "normal", w);
  if (std::abs(p.normal.norm() - 1.0) > 1e-3) r.fail(w + ".normal", "a unit vector");
  p.normal.normalize();
  if (jp.contains("creep_viscosity")) {
    p.creep_viscosity = r.number(jp, "creep_viscosity", w);
    p.tangential_stiffness = r.number(jp, "tangential_stiffness", w);
    if (p.creep_viscosity < 0 || p.tangential_stiffness < 0)
      r.fail(w, "creep_viscosity >= 0 and tangential_stiffness >= 0");
  }
  const json& bs = r.array(jp, "borders", w, nl * nk);
  if (bs.size() != nl * nk)
    r.fail(w + ".borders", fmt::format("{} borders (levels x directions)", nl * nk));
  for (std::size_t b = 0; b < bs.size(); ++b)
    p.borders.push_back(read_border(r, bs[b], fmt::format("{}.borders[{}]", w, b),
                                    m.f_normal_levels[b / nk], b % nk));
  return p;
}

SysModel read_sys_json(const std::string& path) {
  const std::string text = read_file(path);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw ParseError(path, 0, fmt::format("expected JSON ({})", e.what()));
  } catch (const json::exception& e) {  // e.g. out_of_range 406: a number such as 1e999
    throw ParseError(path, 0, fmt::format("expected JSON with finite numbers ({})", e.what()));
  }
  Reader r{path};
  const json& fmt_name = r.at(j, "format", "$");
  if (!fmt_name.is_string() || fmt_name.get<std::string>() != "inhap-sys")
    r.fail("$.format", "\"inhap-sys\"");
  if (r.integer(j, "version", "$") != SysModel::kFormatVersion)
    r.fail("$.version", fmt::format("{}", SysModel::kFormatVersion));
  SysModel m;
  m.f_normal_levels = r.numbers(j, "f_normal_levels", "$", 1);
  m.angles = r.numbers(j, "angles", "$", 1);
  m.plateaus = r.numbers(j, "plateaus", "$", 1);
  m.tangent_reference = r.vec3(j, "tangent_reference", "$");
  if (j.contains("border_options")) {
    const json& o = j["border_options"];
    const std::string w = "$.border_options";
    m.border_options.weight_up = r.number(o, "weight_up", w);
    m.border_options.weight_growth = r.number(o, "weight_growth", w);
    m.border_options.floor_up = r.number(o, "floor_up", w);
    m.border_options.floor_growth = r.number(o, "floor_growth", w);
    m.border_options.min_sliding_growth = r.number(o, "min_sliding_growth", w);
    m.border_options.refine = r.boolean(o, "refine", w, true);
    m.border_options.refine_points = r.integer(o, "refine_points", w);
  }
  if (j.contains("force_frame")) {  // optional: files before it were decomposed at the probe
    const json& f = j["force_frame"];
    const std::string v = f.is_string() ? f.get<std::string>() : std::string();
    if (v != "anchor" && v != "probe") r.fail("$.force_frame", "\"anchor\" or \"probe\"");
    m.force_frame = force_frame_from_string(v);
  }
  for (std::size_t i = 1; i < m.f_normal_levels.size(); ++i)
    if (!(m.f_normal_levels[i] > m.f_normal_levels[i - 1]) || !(m.f_normal_levels[0] > 0))
      r.fail("$.f_normal_levels", "increasing levels > 0 N");
  const json& pts = r.array(j, "points", "$", 1);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    m.points.push_back(read_point(r, pts[i], fmt::format("$.points[{}]", i), m));
  }
  std::vector<Tri> tris;
  const json& jt = r.array(j, "triangles", "$");
  for (std::size_t t = 0; t < jt.size(); ++t) {
    const std::string w = fmt::format("$.triangles[{}]", t);
    if (!jt[t].is_array() || jt[t].size() != 3) r.fail(w, "3 vertex indices");
    Tri tri;
    for (int v = 0; v < 3; ++v) {
      tri[v] = r.integer(jt[t][v], w);
    }
    tris.push_back(tri);
  }
  try {
    m.rebuild(&tris);
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    throw ParseError(path, 0, e.what());
  }
  return m;
}

}  // namespace inhap::friction
