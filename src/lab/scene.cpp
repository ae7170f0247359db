// Scene files (JSON) for the virtual lab: parse, validate, write.
#include "inhap/lab/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "shape_mesh.hpp"

namespace inhap::lab {

namespace {

using nlohmann::json;
using ojson = nlohmann::ordered_json;  // writer: keys in a readable order

constexpr double kCoordLimitMm = 1e6;

/// Reads typed fields out of a JSON object, naming the key path and the file in errors.
class Reader {
 public:
  Reader(const json& j, std::string path, const std::string& file)
      : j_(j), path_(std::move(path)), file_(file) {
    if (!j_.is_object()) fail("expected an object", j_);
  }
  [[noreturn]] void fail(const std::string& what, const json& got) const {
    std::string shown = got.dump();
    if (shown.size() > 40) shown = shown.substr(0, 37) + "...";
    throw ParseError(file_, 0, fmt::format("{}: {}, got {}", path_, what, shown));
  }
  /// Error about field k of this object.
  [[noreturn]] void fail_at(const std::string& k, const std::string& what) const {
    Reader(json::object(), key(k), file_).fail(what, at(k));
  }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  bool has(const std::string& k) const { return j_.contains(k); }
  const json& at(const std::string& k) const {
    if (!j_.contains(k))
      throw ParseError(file_, 0, fmt::format("{}: missing required field", key(k)));
    return j_.at(k);
  }
  double number(const std::string& k, double lo, double hi) const {
    const json& v = at(k);
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo ||
        v.get<double>() > hi)
      Reader(json::object(), key(k), file_)
          .fail(fmt::format("expected a number in [{:g}, {:g}]", lo, hi), v);
    return v.get<double>();
  }
  double number_or(const std::string& k, double def, double lo, double hi) const {
    return has(k) ? number(k, lo, hi) : def;
  }
  std::string string(const std::string& k) const {
    const json& v = at(k);
    if (!v.is_string()) Reader(json::object(), key(k), file_).fail("expected a string", v);
    return v.get<std::string>();
  }
  std::string string_or(const std::string& k, const std::string& def) const {
    return has(k) ? string(k) : def;
  }
  template <int N>
  Eigen::Matrix<double, N, 1> vec(const std::string& k) const {
    const json& v = at(k);
    Eigen::Matrix<double, N, 1> out;
    if (!v.is_array() || v.size() != N)
      Reader(json::object(), key(k), file_)
          .fail(fmt::format("expected an array of {} numbers", N), v);
    for (int i = 0; i < N; ++i) {
      // Coordinates and sizes beyond 1 km are absurd and overflow the physics (1e308 -> inf).
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()) ||
          std::abs(v[i].get<double>()) > kCoordLimitMm)
        Reader(json::object(), key(k), file_)
            .fail(fmt::format("expected an array of {} numbers within +-{:g} mm", N, kCoordLimitMm),
                  v);
      out[i] = v[i].get<double>();
    }
    return out;
  }
  Reader child(const std::string& k) const { return Reader(at(k), key(k), file_); }
  const json& raw() const { return j_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }

 private:
  const json& j_;
  std::string path_;
  const std::string& file_;
};

constexpr double kBig = 1e6;

Shape read_geometry(const Reader& g, const std::filesystem::path& scene_dir) {
  const std::string type = g.string("type");
  Shape shape;
  if (type == "cylinder" || type == "plane") {
    shape = CylinderShape{g.vec<3>("base_center"), g.number("radius", 0, kBig),
                          g.number("height", 0, kBig)};
  } else if (type == "dome") {
    shape = DomeShape{g.vec<3>("base_center"), g.number("base_radius", 0, kBig),
                      g.number("height", 0, kBig)};
  } else if (type == "hemisphere") {
    shape = HemisphereShape{g.vec<3>("base_center"), g.number("radius", 0, kBig)};
  } else if (type == "sphere") {
    shape = SphereShape{g.vec<3>("center"), g.number("radius", 0, kBig)};
  } else if (type == "box") {
    shape = BoxShape{g.vec<3>("center"), 0.5 * g.vec<3>("size")};
  } else if (type == "ridged-slab") {
    RidgedSlabShape r;
    r.base_center = g.vec<3>("base_center");
    r.size_x = g.number("size_x", 0, kBig);
    r.size_y = g.number("size_y", 0, kBig);
    r.thickness = g.number("thickness", 0, kBig);
    r.ridges = static_cast<int>(g.number("ridges", 0, 1000));
    r.ridge_height = g.number_or("ridge_height", 0, 0, kBig);
    r.ridge_width = g.number_or("ridge_width", 0, 0, kBig);
    shape = r;
  } else if (type == "mesh") {
    const Vec3 offset = g.has("offset") ? Vec3(g.vec<3>("offset")) : Vec3::Zero();
    const std::string up = g.string_or("up", "z");
    if (up != "z" && up != "y") g.fail_at("up", "expected \"z\" or \"y\"");
    shape = load_mesh_shape(g.string("path"), scene_dir.string(), g.file(),
                            g.number_or("scale", 1.0, 1e-9, 1e9), offset, up[0]);
  } else {
    g.fail_at("type",
              "expected geometry type cylinder, plane, dome, hemisphere, sphere, box, "
              "ridged-slab or mesh");
  }
  if (std::string err = validate_shape(shape); !err.empty())
    throw ParseError(g.file(), 0, fmt::format("{}: {}", g.path(), err));
  return shape;
}

ContactLaw read_material(const Reader& m) {
  ContactLaw law;
  law.k = m.number("k", 0, kBig);
  law.exponent = m.number_or("exponent", law.exponent, 1, 3);
  law.damping = m.number_or("damping", law.damping, 0, kBig);
  law.k_t = m.number("k_t", 0, kBig);
  law.mu = m.number("mu", 0, 100);
  law.creep = m.number_or("creep", law.creep, 0, kBig);
  if (std::string err = validate_material(law); !err.empty())
    throw ParseError(m.file(), 0, fmt::format("{}.{}", m.path(), err));
  return law;
}

std::vector<Inclusion> read_inclusions(const Reader& root) {
  std::vector<Inclusion> out;
  if (!root.has("inclusions")) return out;
  const json& arr = root.at("inclusions");
  if (!arr.is_array())
    Reader(json::object(), "inclusions", root.file()).fail("expected an array", arr);
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const Reader r(arr[i], fmt::format("inclusions[{}]", i), root.file());
    Inclusion inc;
    inc.center = r.vec<3>("center");
    inc.radius = r.number("radius", 1e-6, kBig);
    inc.stiffness_factor = r.number_or("stiffness_factor", 1.0, 1e-3, 1e3);
    inc.mu_factor = r.number_or("mu_factor", 1.0, 0, 1e3);
    out.push_back(inc);
  }
  return out;
}

ojson vec_json(const Vec3& v) {
  return ojson::array({v.x(), v.y(), v.z()});
}

ojson geometry_json(const Shape& shape) {
  ojson g;
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, CylinderShape>) {
          g = {{"type", "cylinder"},
               {"base_center", vec_json(s.base_center)},
               {"radius", s.radius},
               {"height", s.height}};
        } else if constexpr (std::is_same_v<T, DomeShape>) {
          g = {{"type", "dome"},
               {"base_center", vec_json(s.base_center)},
               {"base_radius", s.base_radius},
               {"height", s.height}};
        } else if constexpr (std::is_same_v<T, HemisphereShape>) {
          g = {{"type", "hemisphere"},
               {"base_center", vec_json(s.base_center)},
               {"radius", s.radius}};
        } else if constexpr (std::is_same_v<T, SphereShape>) {
          g = {{"type", "sphere"}, {"center", vec_json(s.center)}, {"radius", s.radius}};
        } else if constexpr (std::is_same_v<T, BoxShape>) {
          g = {{"type", "box"},
               {"center", vec_json(s.center)},
               {"size", vec_json(2.0 * s.half_size)}};
        } else if constexpr (std::is_same_v<T, RidgedSlabShape>) {
          g = {{"type", "ridged-slab"},
               {"base_center", vec_json(s.base_center)},
               {"size_x", s.size_x},
               {"size_y", s.size_y},
               {"thickness", s.thickness},
               {"ridges", s.ridges},
               {"ridge_height", s.ridge_height},
               {"ridge_width", s.ridge_width}};
        } else {
          g = {{"type", "mesh"},
               {"path", s.path},
               {"scale", s.scale},
               {"offset", vec_json(s.offset)},
               {"up", std::string(1, s.up)}};
        }
      },
      shape.variant());
  return g;
}

std::size_t line_of_byte(std::string_view text, std::size_t byte) {
  byte = std::min(byte, text.size());
  return 1 + static_cast<std::size_t>(
                 std::count(text.begin(), text.begin() + static_cast<long>(byte), '\n'));
}

Scene parse_scene_in(std::string_view text, const std::string& source,
                     const std::filesystem::path& dir) {
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    if (auto p = msg.find("syntax error"); p != std::string::npos) msg = msg.substr(p);
    throw ParseError(source, line_of_byte(text, e.byte ? e.byte - 1 : 0),
                     fmt::format("expected a JSON scene: {}", msg));
  } catch (const json::exception& e) {  // out_of_range 406: a number such as 1e999
    throw ParseError(source, 0,
                     fmt::format("expected a JSON scene with finite numbers: {}", e.what()));
  }
  const Reader root(j, "", source);
  if (root.has("format") && root.string("format") != "inhap-scene")
    root.fail_at("format", "expected \"inhap-scene\"");
  if (root.has("version") && root.number("version", 1, 1) != 1)
    root.fail_at("version", "expected version 1");
  Scene s;
  s.name = root.string_or("name", std::filesystem::path(source).stem().string());
  s.description = root.string_or("description", "");
  const Shape shape = read_geometry(root.child("geometry"), dir);
  s.object = SoftObject(shape, read_material(root.child("material")), read_inclusions(root));
  s.region = default_region(shape);
  if (root.has("region")) {
    const Reader r = root.child("region");
    s.region.center = r.vec<2>("center");
    s.region.radius = r.number("radius", 0, kBig);
  }
  s.source = source;
  return s;
}

/// Puts arrays of plain numbers on one line ([0.0, 0.0, 25.0]) so scene files stay editable.
std::string collapse_number_arrays(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '"') {  // a quote ends the string unless an odd run of backslashes escapes it
      std::size_t slashes = 0;
      while (slashes < i && text[i - 1 - slashes] == '\\') ++slashes;
      if (slashes % 2 == 0) in_string = !in_string;
    }
    if (!in_string && text[i] == '[') {
      const std::size_t close = text.find(']', i);
      const std::string_view inner = close == std::string::npos
                                         ? std::string_view()
                                         : std::string_view(text).substr(i + 1, close - i - 1);
      if (!inner.empty() &&
          inner.find_first_not_of("0123456789+-.eE, \n") == std::string_view::npos) {
        out += '[';
        bool space = false;
        for (char c : inner) {
          if (c == ' ' || c == '\n') {
            space = true;
            continue;
          }
          if (space && out.back() == ',') out += ' ';
          space = false;
          out += c;
        }
        out += ']';
        i = close;
        continue;
      }
    }
    out += text[i];
  }
  return out;
}

}  // namespace

Region default_region(const Shape& shape) {
  Region r;
  const Box3 b = shape.bounds();
  if (b.empty()) return r;
  r.center = Vec2(b.center().x(), b.center().y());
  r.radius = 0.35 * std::min(b.size().x(), b.size().y());
  return r;
}

Scene parse_scene(std::string_view json_text, const std::string& source) {
  return parse_scene_in(json_text, source, ".");
}

Scene load_scene(const std::string& path) {
  const std::string text = read_file(path);
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parse_scene_in(text, path, parent.empty() ? std::filesystem::path(".") : parent);
}

std::string scene_to_json(const Scene& scene) {
  const ContactLaw& m = scene.object.material();
  ojson j;
  j["format"] = "inhap-scene";
  j["version"] = 1;
  j["units"] = "mm, N, s; k N/mm^exponent, k_t N/mm, damping s/mm, creep N s/mm";
  j["name"] = scene.name;
  j["description"] = scene.description;
  j["geometry"] = geometry_json(scene.object.shape());
  j["material"] = {{"k", m.k},   {"exponent", m.exponent}, {"damping", m.damping}, {"k_t", m.k_t},
                   {"mu", m.mu}, {"creep", m.creep}};
  ojson incs = ojson::array();
  for (const auto& inc : scene.object.inclusions())
    incs.push_back({{"center", vec_json(inc.center)},
                    {"radius", inc.radius},
                    {"stiffness_factor", inc.stiffness_factor},
                    {"mu_factor", inc.mu_factor}});
  j["inclusions"] = incs;
  j["region"] = {{"center", ojson::array({scene.region.center.x(), scene.region.center.y()})},
                 {"radius", scene.region.radius}};
  return collapse_number_arrays(j.dump(2)) + "\n";
}

void save_scene(const std::string& path, const Scene& scene) {
  write_file_atomic(path, scene_to_json(scene));
}

}  // namespace inhap::lab
