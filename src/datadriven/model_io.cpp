// Force-model JSON files and model validation (see model_io.hpp).
#include "inhap/datadriven/model_io.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <type_traits>
#include <vector>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/json_guard.hpp"

namespace inhap::datadriven {

using json = nlohmann::ordered_json;

namespace {

constexpr const char* kFormat = "inhap-force-model";

json vec_json(const double* v, Eigen::Index n) {
  return json(std::vector<double>(v, v + n));
}

json axis_json(const RbfExpansion& e) {
  json centres = json::array();
  for (Eigen::Index j = 0; j < e.centres.rows(); ++j) {
    const Eigen::VectorXd c = e.centres.row(j).transpose();
    centres.push_back(vec_json(c.data(), c.size()));
  }
  return json{{"centres", std::move(centres)},
              {"weights", vec_json(e.weights.data(), e.weights.size())},
              {"tail", vec_json(e.tail.data(), e.tail.size())}};
}

template <class T>
json arr3(const std::vector<std::array<T, 3>>& v) {
  json a = json::array();
  for (const auto& x : v) a.push_back({x[0], x[1], x[2]});
  return a;
}

// --- reading helpers: every error names the JSON path -----------------------------------------
struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw ParseError(file, 0, fmt::format("{}: {}", where, what));
  }
  static std::string kind(const json& j) { return j.is_null() ? "null" : j.type_name(); }
  const json& need(const json& j, const char* key, const std::string& where) const {
    if (!j.is_object()) fail(where, fmt::format("expected an object, got {}", kind(j)));
    const auto it = j.find(key);
    if (it == j.end()) fail(where, fmt::format("expected member '{}', got none", key));
    return *it;
  }
  double num(const json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, fmt::format("expected a number, got {}", kind(j)));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(where, "expected a finite number");
    return v;
  }
  long integer(const json& j, const std::string& where, long lo, long hi) const {
    if (!j.is_number_integer() && !j.is_number_unsigned())
      fail(where, fmt::format("expected an integer, got {}", kind(j)));
    const long v = j.get<long>();
    if (v < lo || v > hi)
      fail(where, fmt::format("expected an integer in {}..{}, got {}", lo, hi, v));
    return v;
  }
  std::string str(const json& j, const std::string& where) const {
    if (!j.is_string()) fail(where, fmt::format("expected a string, got {}", kind(j)));
    return j.get<std::string>();
  }
  std::vector<double> nums(const json& j, const std::string& where, long expect = -1) const {
    if (!j.is_array()) fail(where, fmt::format("expected an array, got {}", kind(j)));
    if (expect >= 0 && static_cast<long>(j.size()) != expect)
      fail(where, fmt::format("expected {} numbers, got {}", expect, j.size()));
    std::vector<double> v;
    v.reserve(j.size());
    for (std::size_t i = 0; i < j.size(); ++i)
      v.push_back(num(j[i], fmt::format("{}/{}", where, i)));
    return v;
  }
  std::array<double, kFeatureDim> dimarr(const json& j, const std::string& where) const {
    const auto v = nums(j, where, kFeatureDim);
    std::array<double, kFeatureDim> a{};
    std::copy(v.begin(), v.end(), a.begin());
    return a;
  }
};

RbfExpansion read_axis(const Reader& r, const json& j, const std::string& where) {
  RbfExpansion e;
  const json& c = r.need(j, "centres", where);
  if (!c.is_array()) r.fail(where + "/centres", "expected an array of centres");
  const auto w =
      r.nums(r.need(j, "weights", where), where + "/weights", static_cast<long>(c.size()));
  const auto t = r.nums(r.need(j, "tail", where), where + "/tail");
  if (!t.empty() && t.size() != kFeatureDim + 1)
    r.fail(where + "/tail",
           fmt::format("expected 0 or {} numbers, got {}", kFeatureDim + 1, t.size()));
  e.centres.resize(static_cast<Eigen::Index>(c.size()), kFeatureDim);
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto row = r.nums(c[k], fmt::format("{}/centres/{}", where, k), kFeatureDim);
    for (int d = 0; d < kFeatureDim; ++d)
      e.centres(static_cast<Eigen::Index>(k), d) = row[static_cast<std::size_t>(d)];
  }
  e.weights = Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
  if (!t.empty())
    e.tail = Eigen::Map<const Eigen::VectorXd>(t.data(), static_cast<Eigen::Index>(t.size()));
  return e;
}

BinModel read_bin(const Reader& r, const json& j, const std::string& where) {
  BinModel b;
  b.key_min = r.num(r.need(j, "key_min_mm", where), where + "/key_min_mm");
  b.key_max = r.num(r.need(j, "key_max_mm", where), where + "/key_max_mm");
  b.samples = static_cast<std::size_t>(
      r.integer(r.need(j, "samples", where), where + "/samples", 0, 1L << 40));
  b.offset = r.dimarr(r.need(j, "offset", where), where + "/offset");
  b.scale = r.dimarr(r.need(j, "scale", where), where + "/scale");
  b.box_min = r.dimarr(r.need(j, "box_min", where), where + "/box_min");
  b.box_max = r.dimarr(r.need(j, "box_max", where), where + "/box_max");
  const json& axes = r.need(j, "axes", where);
  if (!axes.is_array() || axes.size() != 3) r.fail(where + "/axes", "expected 3 axes (x, y, z)");
  std::array<RbfExpansion, 3> e;
  for (std::size_t a = 0; a < 3; ++a)
    e[a] = read_axis(r, axes[a], fmt::format("{}/axes/{}", where, a));
  BinModel full(std::move(e));  // the union table is built here
  full.key_min = b.key_min, full.key_max = b.key_max, full.samples = b.samples;
  full.offset = b.offset, full.scale = b.scale, full.box_min = b.box_min, full.box_max = b.box_max;
  return full;
}

void read_reference(const Reader& r, const json& refs, const char* key, std::string& path,
                    std::string& digest) {
  const auto it = refs.find(key);
  if (it == refs.end() || it->is_null()) return;
  const std::string where = std::string("references/") + key;
  path = r.str(r.need(*it, "path", where), where + "/path");
  digest = r.str(r.need(*it, "fnv1a64", where), where + "/fnv1a64");
}

json map_json(const StiffnessPrior& s, const char* model) {
  return {{"model", model},
          {"exponent", s.exponent},
          {"origin_mm", {s.origin.x(), s.origin.y(), s.origin.z()}},
          {"cell_mm", s.cell},
          {"dims", s.dims},
          {"fitted_samples", s.fitted_samples},
          {"ln_k", s.log_k}};
}

StiffnessPrior read_map(const Reader& r, const json& sp, const std::string& w) {
  StiffnessPrior m;
  m.exponent = r.num(r.need(sp, "exponent", w), w + "/exponent");
  const std::vector<double> o = r.nums(r.need(sp, "origin_mm", w), w + "/origin_mm", 3);
  m.origin = Vec3(o[0], o[1], o[2]);
  m.cell = r.num(r.need(sp, "cell_mm", w), w + "/cell_mm");
  const json& dims = r.need(sp, "dims", w);
  if (!dims.is_array() || dims.size() != 3) r.fail(w + "/dims", "expected 3 integers");
  for (std::size_t a = 0; a < 3; ++a)
    m.dims[a] = static_cast<int>(r.integer(dims[a], fmt::format("{}/dims/{}", w, a), 1, 100000));
  m.log_k = r.nums(r.need(sp, "ln_k", w), w + "/ln_k");
  if (sp.contains("fitted_samples"))
    m.fitted_samples = static_cast<std::size_t>(
        r.integer(sp["fitted_samples"], w + "/fitted_samples", 0, 1L << 50));
  try {
    validate_stiffness_prior(m, w);
  } catch (const Error& e) {
    r.fail(w, e.what());
  }
  return m;
}

// The "train" object: the provenance's training parameters and statistics.
json train_json(const ForceModelProvenance& pv) {
  const TrainParams& p = pv.params;
  const TrainStats& st = pv.stats;
  return {{"bins", p.bins},
          {"centers", p.centers},
          {"nonzeros", p.nonzeros},
          {"lambda_ratio", p.lambda_ratio},
          {"seed", p.seed},
          {"linear_tail", p.linear_tail},
          {"sparsa_tolerance", p.sparsa_tolerance},
          {"cg_tolerance", p.cg_tolerance},
          {"ridge", p.ridge},
          {"design", to_string(p.design)},
          {"feature_weights", p.feature_weights},
          {"isotropic_positions", p.isotropic_positions},
          {"normalize_columns", p.normalize_columns},
          {"sparsa_stop", p.sparsa_stop == SparsaStop::kStep ? "step" : "objective"},
          {"sparsa_max_iterations", p.sparsa_iterations},
          {"solver", to_string(p.solver)},
          {"gap_tolerance", p.gap_tolerance},
          {"kmeans_iterations", p.kmeans_iterations},
          {"kmeans_min_moved", p.kmeans_min_moved},
          {"box_margin", p.box_margin},
          {"tangent_mirror", p.tangent_mirror},
          {"stiffness_prior", p.stiffness_prior},
          {"shear_prior", p.shear_prior},
          {"friction_cone", p.friction_cone},
          {"sliding_floor", p.sliding_floor},
          {"fallback", p.fallback},
          {"envelope", p.envelope},
          {"fallback_near_mm", p.fallback_near_mm},
          {"fallback_far_mm", p.fallback_far_mm},
          {"fallback_normal_near_mm", p.fallback_normal_near_mm},
          {"fallback_normal_far_mm", p.fallback_normal_far_mm},
          {"samples", st.samples},
          {"seconds", st.seconds},
          {"support", arr3(st.support)},
          {"sparsa_iterations", arr3(st.sparsa_iterations)},
          {"gap", arr3(st.gap)},
          {"l1_nonzeros", arr3(st.nonzeros)},
          {"cg_iterations", arr3(st.cg_iterations)},
          {"lambda", arr3(st.lambda)},
          {"selected_rows", st.selected_rows},
          {"modeling_range_n", p.modeling_range_n},
          {"above_range", to_string(p.above_range)},
          {"samples_offered", st.offered},
          {"samples_above_range", st.above_range},
          {"samples_excluded", st.excluded},
          {"max_force_n", st.max_force_n}};
}

template <class T>
struct IsStdArray : std::false_type {};
template <class T, std::size_t N>
struct IsStdArray<std::array<T, N>> : std::true_type {};
template <class T>
struct IsStdVector : std::false_type {};
template <class T>
struct IsStdVector<std::vector<T>> : std::true_type {};

// `j` into `dst` (a number, a bool or arrays of them), checked first where nlohmann's plain cast
// is undefined: a float outside an integer member's range (3e69 for a count) or with a fraction.
// Throws inhap::Error (json::type_error for a wrong type).
template <class T>
void read_value(const json& j, T& dst) {
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    if (j.is_number_float()) {
      const double d = j.get<double>(), top = std::ldexp(1.0, std::numeric_limits<T>::digits);
      const double bottom = std::is_signed_v<T> ? -top : 0.0;
      if (!(d >= bottom && d < top && d == std::trunc(d)))
        throw Error(fmt::format("expected an integer in range, got {}", d));
    }
    dst = j.get<T>();
  } else if constexpr (IsStdArray<T>::value || IsStdVector<T>::value) {
    if (!j.is_array()) throw Error(fmt::format("expected an array, got {}", j.type_name()));
    if constexpr (IsStdArray<T>::value) {
      if (j.size() != dst.size())
        throw Error(fmt::format("expected {} values, got {}", dst.size(), j.size()));
    } else {
      dst.resize(j.size());
    }
    for (std::size_t i = 0; i < j.size(); ++i) read_value(j[i], dst[i]);
  } else {
    dst = j.get<T>();
  }
}

// Reads the "train" object `t` into the provenance (every key optional: older files lack some).
void read_train(const Reader& r, const json& t, ForceModelProvenance& pv) {
  auto get = [&](const char* k, auto& dst) {
    if (!t.contains(k)) return;
    try {
      read_value(t[k], dst);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", k, e.what()));
    }
  };
  try {
    get("bins", pv.params.bins);
    get("centers", pv.params.centers);
    get("nonzeros", pv.params.nonzeros);
    get("lambda_ratio", pv.params.lambda_ratio);
    get("seed", pv.params.seed);
    get("linear_tail", pv.params.linear_tail);
    get("sparsa_tolerance", pv.params.sparsa_tolerance);
    get("cg_tolerance", pv.params.cg_tolerance);
    get("ridge", pv.params.ridge);
    get("feature_weights", pv.params.feature_weights);
    // Files written before this option standardised every coordinate on its own.
    pv.params.isotropic_positions = false;
    get("isotropic_positions", pv.params.isotropic_positions);
    get("normalize_columns", pv.params.normalize_columns);
    get("sparsa_max_iterations", pv.params.sparsa_iterations);
    // Files written before the solver choice were trained by SpaRSA.
    pv.params.solver = t.contains("solver") ? l1_solver_from_string(t["solver"].get<std::string>())
                                            : L1Solver::kSparsa;
    get("gap_tolerance", pv.params.gap_tolerance);
    if (t.contains("design")) pv.params.design = design_from_string(t["design"].get<std::string>());
    if (t.contains("sparsa_stop"))
      pv.params.sparsa_stop =
          t["sparsa_stop"] == "step" ? SparsaStop::kStep : SparsaStop::kObjective;
    get("kmeans_iterations", pv.params.kmeans_iterations);
    // Files written before the early stop ran k-means until no sample moved.
    pv.params.kmeans_min_moved = 0;
    get("kmeans_min_moved", pv.params.kmeans_min_moved);
    get("box_margin", pv.params.box_margin);
    if (t.contains("tangent_mirror")) pv.params.tangent_mirror = t["tangent_mirror"].get<bool>();
    if (t.contains("stiffness_prior")) pv.params.stiffness_prior = t["stiffness_prior"].get<bool>();
    if (t.contains("shear_prior")) pv.params.shear_prior = t["shear_prior"].get<bool>();
    if (t.contains("friction_cone")) pv.params.friction_cone = t["friction_cone"].get<bool>();
    if (t.contains("sliding_floor")) pv.params.sliding_floor = t["sliding_floor"].get<bool>();
    if (t.contains("fallback")) pv.params.fallback = t["fallback"].get<bool>();
    if (t.contains("envelope")) pv.params.envelope = t["envelope"].get<bool>();
    get("fallback_near_mm", pv.params.fallback_near_mm);
    get("fallback_far_mm", pv.params.fallback_far_mm);
    // Files from before the normal line: it was off.
    pv.params.fallback_normal_near_mm = pv.params.fallback_normal_far_mm = 0;
    get("fallback_normal_near_mm", pv.params.fallback_normal_near_mm);
    get("fallback_normal_far_mm", pv.params.fallback_normal_far_mm);
    get("samples", pv.stats.samples);
    get("seconds", pv.stats.seconds);
    get("support", pv.stats.support);
    get("sparsa_iterations", pv.stats.sparsa_iterations);
    get("gap", pv.stats.gap);
    get("l1_nonzeros", pv.stats.nonzeros);
    get("cg_iterations", pv.stats.cg_iterations);
    get("lambda", pv.stats.lambda);
    get("selected_rows", pv.stats.selected_rows);
    get("modeling_range_n", pv.params.modeling_range_n);
    if (t.contains("above_range"))
      pv.params.above_range = above_range_from_string(t["above_range"].get<std::string>());
    get("samples_offered", pv.stats.offered);
    get("samples_above_range", pv.stats.above_range);
    get("samples_excluded", pv.stats.excluded);
    get("max_force_n", pv.stats.max_force_n);
  } catch (const json::exception& e) {
    r.fail("train", fmt::format("expected training parameters and statistics, got {}", e.what()));
  } catch (const Error& e) {
    r.fail("train", e.what());
  }
}

// The "fallback" object (the distance grid is built after validation).
Fallback read_fallback(const Reader& r, const json& fb) {
  Fallback f;
  f.near_mm = r.num(r.need(fb, "near_mm", "fallback"), "fallback/near_mm");
  f.far_mm = r.num(r.need(fb, "far_mm", "fallback"), "fallback/far_mm");
  if (fb.contains("normal_near_mm") || fb.contains("normal_far_mm")) {  // absent: off (older files)
    f.normal_near_mm = r.num(r.need(fb, "normal_near_mm", "fallback"), "fallback/normal_near_mm");
    f.normal_far_mm = r.num(r.need(fb, "normal_far_mm", "fallback"), "fallback/normal_far_mm");
  }
  const json& law = r.need(fb, "law", "fallback");
  f.law.depth_mm = r.nums(r.need(law, "depth_mm", "fallback/law"), "fallback/law/depth_mm");
  f.law.force_n = r.nums(r.need(law, "force_n", "fallback/law"), "fallback/law/force_n");
  f.law.slope_n_per_mm =
      r.num(r.need(law, "slope_n_per_mm", "fallback/law"), "fallback/law/slope_n_per_mm");
  const json& sup = r.need(fb, "support", "fallback");
  f.support.cell_mm = r.num(r.need(sup, "cell_mm", "fallback/support"), "fallback/support/cell_mm");
  const json& pts = r.need(sup, "points_mm", "fallback/support");
  if (!pts.is_array()) r.fail("fallback/support/points_mm", "expected an array of [x, y, z]");
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const auto x = r.nums(pts[k], fmt::format("fallback/support/points_mm/{}", k), 3);
    f.support.points.emplace_back(x[0], x[1], x[2]);
  }
  return f;
}

// The "envelope" object; -1 in f_max_n marks a block without samples.
ForceEnvelope read_envelope(const Reader& r, const json& ev) {
  ForceEnvelope e;
  const auto num = [&](const char* key) {
    return r.num(r.need(ev, key, "envelope"), fmt::format("envelope/{}", key));
  };
  e.cell_mm = num("cell_mm");
  e.depth_step_mm = num("depth_step_mm");
  e.margin_rel = num("margin_rel");
  e.margin_n = num("margin_n");
  const auto o = r.nums(r.need(ev, "origin_mm", "envelope"), "envelope/origin_mm", 3);
  e.origin = Vec3(o[0], o[1], o[2]);
  const auto d = r.nums(r.need(ev, "dims", "envelope"), "envelope/dims", 3);
  for (std::size_t a = 0; a < 3; ++a) {
    if (!(d[a] >= 1 && d[a] <= 200) || d[a] != std::floor(d[a]))
      r.fail("envelope/dims", "expected three integers in 1..200");
    e.dims[a] = static_cast<int>(d[a]);
  }
  e.depth_bins = static_cast<int>(
      r.integer(r.need(ev, "depth_bins", "envelope"), "envelope/depth_bins", 1, 100));
  for (double v : r.nums(r.need(ev, "global_n", "envelope"), "envelope/global_n"))
    e.global.push_back(static_cast<float>(v));
  for (double v : r.nums(r.need(ev, "f_max_n", "envelope"), "envelope/f_max_n"))
    e.f_max.push_back(v < 0 ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(v));
  for (double v : r.nums(r.need(ev, "deepest_bin", "envelope"), "envelope/deepest_bin")) {
    if (!(v >= -1 && v <= 100) || v != std::floor(v))
      r.fail("envelope/deepest_bin", "expected integers in -1..100");
    e.deepest.push_back(static_cast<std::int16_t>(v));
  }
  e.global_deepest = static_cast<int>(r.integer(r.need(ev, "global_deepest_bin", "envelope"),
                                                "envelope/global_deepest_bin", -1, 100));
  return e;
}

json envelope_json(const ForceEnvelope& e) {
  // Floats written as doubles come back bit-identical (forces after save and load too).
  std::vector<double> g, f;
  for (float v : e.global) g.push_back(static_cast<double>(v));
  for (float v : e.f_max) f.push_back(std::isnan(v) ? -1.0 : static_cast<double>(v));
  return {{"about",
           "|f| <= (1 + margin_rel) max |f| of the training samples within one cell of q and "
           "one depth step of ||q - p|| deeper + margin_n, growing as ((b + 1) / (D + 1))^1.5 "
           "beyond the deepest bin D with data; f_max_n per cell and depth bin (depth fastest, "
           "then x, y, z), -1: none there (global_n of the depth bin)"},
          {"cell_mm", e.cell_mm},
          {"depth_step_mm", e.depth_step_mm},
          {"margin_rel", e.margin_rel},
          {"margin_n", e.margin_n},
          {"origin_mm", {e.origin.x(), e.origin.y(), e.origin.z()}},
          {"dims", {e.dims[0], e.dims[1], e.dims[2]}},
          {"depth_bins", e.depth_bins},
          {"global_n", std::move(g)},
          {"f_max_n", std::move(f)},
          {"deepest_bin", e.deepest},
          {"global_deepest_bin", e.global_deepest}};
}

}  // namespace

std::string file_digest(const std::string& path) {
  const std::string bytes = read_file(path);
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return fmt::format("{:016x}", h);
}

std::string force_model_to_json(const ForceModel& m, const ForceModelProvenance& pv) {
  json j;
  j["format"] = kFormat;
  j["version"] = kForceModelVersion;
  j["units"] = {{"position", "mm"}, {"velocity", "mm/s"}, {"force", "N"}, {"time", "s"}};
  j["features"] = to_string(m.features);
  j["feature_dim"] = kFeatureDim;
  j["rbf"] = "r^3";
  j["force_limit_n"] = m.force_limit_n;
  if (m.bin_blend > 0) j["bin_blend_mm"] = m.bin_blend;
  if (m.friction_cone > 0) j["friction_cone"] = m.friction_cone;
  if (m.sliding_mu > 0) j["sliding_mu"] = m.sliding_mu;
  j["foaw"] = {{"dt_s", m.foaw.dt_s},
               {"max_window", m.foaw.max_window},
               {"noise_bound_mm", m.foaw.noise_bound_mm}};
  json refs = json::object();
  refs["sys"] =
      pv.sys_path.empty() ? json(nullptr) : json{{"path", pv.sys_path}, {"fnv1a64", pv.sys_digest}};
  refs["mesh"] = pv.mesh_path.empty() ? json(nullptr)
                                      : json{{"path", pv.mesh_path}, {"fnv1a64", pv.mesh_digest}};
  refs["recording"] = pv.recording_path.empty() ? json(nullptr)
                                                : json{{"path", pv.recording_path},
                                                       {"fnv1a64", pv.recording_digest},
                                                       {"time_unit", pv.time_unit},
                                                       {"length_unit", pv.length_unit}};
  j["references"] = refs;
  j["proxy_source"] = pv.proxy_source;
  if (!pv.estimated.empty()) j["estimated"] = pv.estimated;
  j["train"] = train_json(pv);
  j["edges_mm"] = m.edges;
  json bins = json::array();
  for (const BinModel& b : m.bins) {
    bins.push_back({{"key_min_mm", b.key_min},
                    {"key_max_mm", b.key_max},
                    {"samples", b.samples},
                    {"offset", b.offset},
                    {"scale", b.scale},
                    {"box_min", b.box_min},
                    {"box_max", b.box_max},
                    {"axes", json::array({axis_json(b.axes()[0]), axis_json(b.axes()[1]),
                                          axis_json(b.axes()[2])})}});
  }
  j["bins"] = std::move(bins);
  if (!m.prior.empty())
    j["stiffness_prior"] = map_json(m.prior, "f_n = k(q) d^alpha, ln k trilinear on a grid over q");
  if (!m.shear.empty())
    j["shear_prior"] =
        map_json(m.shear,
                 "f_t = -k(q) |u_t|^alpha u_t / |u_t|, u_t = tangential part of p - q, ln k "
                 "trilinear on a grid over q");
  if (!m.fallback.empty()) {
    const Fallback& fb = m.fallback;
    json pts = json::array();
    for (const Vec3& x : fb.support.points) pts.push_back({x.x(), x.y(), x.z()});
    j["fallback"] = {
        {"about",
         "f = (1 - w) f_model + w (law(n . (q - p)) n + shear prior), w = smoothstep of the "
         "distance from q to the nearest training proxy between near_mm and far_mm; before "
         "that, f_model's normal component blends towards f_model's at p' = q - (n . (q - p)) n "
         "(no tangential displacement) with the smoothstep between normal_near_mm and "
         "normal_far_mm (0 and 0: off)"},
        {"near_mm", fb.near_mm},
        {"far_mm", fb.far_mm},
        {"normal_near_mm", fb.normal_near_mm},
        {"normal_far_mm", fb.normal_far_mm},
        {"law",
         {{"depth_mm", fb.law.depth_mm},
          {"force_n", fb.law.force_n},
          {"slope_n_per_mm", fb.law.slope_n_per_mm}}},
        {"support", {{"cell_mm", fb.support.cell_mm}, {"points_mm", std::move(pts)}}}};
  }
  if (!m.envelope.empty()) j["envelope"] = envelope_json(m.envelope);
  require_finite_json(j, "force model JSON");
  return j.dump(1) + "\n";
}

TrainedForceModel trained_force_model_from_json(const std::string& text,
                                                const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::out_of_range& e) {  // 406: a number such as 1e999
    throw ParseError(source, 0, fmt::format("expected JSON with finite numbers, got {}", e.what()));
  } catch (const json::parse_error& e) {
    const std::size_t upto = std::min<std::size_t>(e.byte, text.size());
    const std::size_t line =
        1 + static_cast<std::size_t>(
                std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(upto), '\n'));
    throw ParseError(source, line,
                     fmt::format("expected valid JSON, got a syntax error ({})", e.what()));
  }
  const Reader r{source};
  const std::string fmt_name = r.str(r.need(j, "format", "(root)"), "format");
  if (fmt_name != kFormat)
    r.fail("format", fmt::format("expected '{}', got '{}'", kFormat, fmt_name));
  const long version = r.integer(r.need(j, "version", "(root)"), "version", 0, 1000000);
  if (version != kForceModelVersion)
    r.fail("version", fmt::format("expected {}, got {}", kForceModelVersion, version));
  r.integer(r.need(j, "feature_dim", "(root)"), "feature_dim", kFeatureDim, kFeatureDim);
  TrainedForceModel out;
  ForceModel& m = out.model;
  ForceModelProvenance& pv = out.provenance;
  try {
    m.features = feature_set_from_string(r.str(r.need(j, "features", "(root)"), "features"));
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    r.fail("features", e.what());
  }
  m.force_limit_n = r.num(r.need(j, "force_limit_n", "(root)"), "force_limit_n");
  if (j.contains("bin_blend_mm")) {
    m.bin_blend = r.num(j["bin_blend_mm"], "bin_blend_mm");
    if (!(m.bin_blend >= 0)) r.fail("bin_blend_mm", "expected >= 0");
  }
  if (j.contains("friction_cone")) {
    m.friction_cone = r.num(j["friction_cone"], "friction_cone");
    if (!(m.friction_cone >= 0)) r.fail("friction_cone", "expected >= 0");
  }
  if (j.contains("sliding_mu")) {
    m.sliding_mu = r.num(j["sliding_mu"], "sliding_mu");
    if (!(m.sliding_mu >= 0)) r.fail("sliding_mu", "expected >= 0");
  }
  const json& fo = r.need(j, "foaw", "(root)");
  m.foaw.dt_s = r.num(r.need(fo, "dt_s", "foaw"), "foaw/dt_s");
  m.foaw.max_window = static_cast<int>(
      r.integer(r.need(fo, "max_window", "foaw"), "foaw/max_window", 1, kFoawMaxWindow - 1));
  m.foaw.noise_bound_mm = r.num(r.need(fo, "noise_bound_mm", "foaw"), "foaw/noise_bound_mm");
  const json& refs = r.need(j, "references", "(root)");
  read_reference(r, refs, "sys", pv.sys_path, pv.sys_digest);
  read_reference(r, refs, "mesh", pv.mesh_path, pv.mesh_digest);
  read_reference(r, refs, "recording", pv.recording_path, pv.recording_digest);
  if (!pv.recording_path.empty()) {
    const json& rr = refs["recording"];
    if (rr.contains("time_unit"))
      pv.time_unit = r.str(rr["time_unit"], "references/recording/time_unit");
    if (rr.contains("length_unit"))
      pv.length_unit = r.str(rr["length_unit"], "references/recording/length_unit");
  }
  if (j.contains("proxy_source")) pv.proxy_source = r.str(j["proxy_source"], "proxy_source");
  if (j.contains("estimated")) {
    const json& es = j["estimated"];
    if (!es.is_array()) r.fail("estimated", "expected an array of names");
    for (std::size_t k = 0; k < es.size(); ++k)
      pv.estimated.push_back(r.str(es[k], fmt::format("estimated/{}", k)));
  }
  if (j.contains("train") && j["train"].is_object()) {  // provenance; tolerated when partial
    read_train(r, j["train"], pv);
    pv.params.features = m.features;
  }
  if (j.contains("stiffness_prior") && !j["stiffness_prior"].is_null())
    m.prior = read_map(r, j["stiffness_prior"], "stiffness_prior");
  if (j.contains("shear_prior") && !j["shear_prior"].is_null())
    m.shear = read_map(r, j["shear_prior"], "shear_prior");
  if (j.contains("fallback") && !j["fallback"].is_null())
    m.fallback = read_fallback(r, j["fallback"]);
  if (j.contains("envelope") && !j["envelope"].is_null())
    m.envelope = read_envelope(r, j["envelope"]);
  m.edges = r.nums(r.need(j, "edges_mm", "(root)"), "edges_mm");
  const json& bins = r.need(j, "bins", "(root)");
  if (!bins.is_array()) r.fail("bins", "expected an array");
  for (std::size_t b = 0; b < bins.size(); ++b)
    m.bins.push_back(read_bin(r, bins[b], fmt::format("bins/{}", b)));
  try {
    validate_model(m, "");
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    throw ParseError(source, 0, e.what());
  }
  if (!m.fallback.support.empty()) m.fallback.support.build(m.fallback.reach_mm());
  return out;
}

ForceModel force_model_from_json(const std::string& text, const std::string& source) {
  return trained_force_model_from_json(text, source).model;
}

void validate_model(const ForceModel& m, const std::string& where) {
  auto fail = [&](const std::string& what) {
    throw Error(where.empty() ? what : fmt::format("{}: {}", where, what));
  };
  try {
    m.foaw.validate();
  } catch (const Error& e) {
    fail(fmt::format("foaw: {}", e.what()));
  }
  if (!(m.force_limit_n > 0) || !(m.force_limit_n <= kDeviceForceLimitN))
    fail(fmt::format(
        "force_limit_n: expected a force in (0, {}] N (a model may lower the device's limit, "
        "never raise it), got {}",
        kDeviceForceLimitN, m.force_limit_n));
  if (m.bins.empty()) fail("bins: expected at least one bin, got none");
  if (m.friction_cone > 0 && m.features != FeatureSet::kLocalFrame)
    fail("friction_cone: expected local-frame features (the cone is about the normal)");
  if (m.sliding_mu > 0 && m.features != FeatureSet::kLocalFrame)
    fail("sliding_mu: expected local-frame features (the floor is about the normal)");
  for (const auto& [map, name] :
       {std::pair{&m.prior, "stiffness_prior"}, {&m.shear, "shear_prior"}}) {
    if (map->log_k.empty()) continue;
    if (m.features != FeatureSet::kLocalFrame)
      fail(fmt::format("{}: expected local-frame features (the prior needs the normal)", name));
    try {
      validate_stiffness_prior(*map, name);
    } catch (const Error& e) {
      fail(e.what());
    }
  }
  if (!m.fallback.law.depth_mm.empty() || !m.fallback.support.points.empty()) {
    if (m.features != FeatureSet::kLocalFrame)
      fail("fallback: expected local-frame features (the law needs the normal)");
    try {
      validate_fallback(m.fallback, "fallback");
    } catch (const Error& e) {
      fail(e.what());
    }
  }
  try {
    validate_envelope(m.envelope, "envelope");
  } catch (const Error& e) {
    fail(e.what());
  }
  if (m.edges.size() + 1 != m.bins.size())
    fail(fmt::format("edges_mm: expected {} edges for {} bins, got {}", m.bins.size() - 1,
                     m.bins.size(), m.edges.size()));
  for (std::size_t i = 0; i < m.edges.size(); ++i)
    if (!std::isfinite(m.edges[i]) || (i > 0 && !(m.edges[i] >= m.edges[i - 1])))
      fail(fmt::format("edges_mm/{}: expected finite, non-decreasing edges", i));
  for (std::size_t b = 0; b < m.bins.size(); ++b) {
    const BinModel& bm = m.bins[b];
    for (int d = 0; d < kFeatureDim; ++d) {
      const auto ud = static_cast<std::size_t>(d);
      if (!(bm.scale[ud] > 0) || !std::isfinite(bm.scale[ud]) || !std::isfinite(bm.offset[ud]))
        fail(fmt::format("bins/{}/scale/{}: expected a positive finite scale, got {}", b, d,
                         bm.scale[ud]));
      if (!(bm.box_min[ud] <= bm.box_max[ud]) || !std::isfinite(bm.box_min[ud]) ||
          !std::isfinite(bm.box_max[ud]))
        fail(fmt::format("bins/{}/box_min/{}: expected box_min <= box_max", b, d));
    }
    for (std::size_t a = 0; a < 3; ++a) {
      const RbfExpansion& e = bm.axes()[a];
      const std::string at = fmt::format("bins/{}/axes/{}", b, a);
      if (e.centres.cols() != kFeatureDim) fail(at + "/centres: expected 9 coordinates per centre");
      if (e.weights.size() != e.centres.rows())
        fail(at + "/weights: expected one weight per centre");
      if (e.tail.size() != 0 && e.tail.size() != kFeatureDim + 1)
        fail(at + "/tail: expected 0 or 10 numbers");
      if (!e.centres.allFinite() || !e.weights.allFinite() || !e.tail.allFinite())
        fail(at + ": expected finite centres, weights and tail");
    }
  }
}

void save_force_model(const std::string& path, const ForceModel& model,
                      const ForceModelProvenance& provenance) {
  validate_model(model, path);
  write_file_atomic(path, force_model_to_json(model, provenance));
}

TrainedForceModel load_trained_force_model(const std::string& path) {
  return trained_force_model_from_json(read_file(path), path);
}

ForceModel load_force_model(const std::string& path) {
  return load_trained_force_model(path).model;
}

}  // namespace inhap::datadriven
