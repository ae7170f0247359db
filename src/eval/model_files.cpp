// The data-driven force model on recording files (`inhap model train|eval|render`).
// Units: positions mm, forces N, times s.
#include "inhap/eval/model_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/mesh_io.hpp"

namespace inhap::eval {

using namespace inhap::datadriven;

namespace {
constexpr double kFewContactSeconds = 30.0;  // less contact than this gets a warning
}

ProxyTrack track_of(const Recording& rec, const std::string& path, const ProxyColumnsSpec& o) {
  return proxy_from_columns(rec, path, o.prefix, o.contact_column, o.contact_threshold_n);
}

bool has_normal_columns(const Recording& rec) {
  return rec.find_extra("nx") && rec.find_extra("ny") && rec.find_extra("nz");
}

void add_normals(ProxyTrack& t, const Recording& rec, const std::string& path,
                 const std::string& mesh) {
  const auto *nx = rec.find_extra("nx"), *ny = rec.find_extra("ny"), *nz = rec.find_extra("nz");
  t.n.assign(rec.size(), Vec3::UnitZ());
  if (nx && ny && nz) {
    for (std::size_t i = 0; i < rec.size(); ++i) t.n[i] = Vec3((*nx)[i], (*ny)[i], (*nz)[i]);
    return;
  }
  if (mesh.empty())
    throw ParseError(path, 1,
                     "local-frame features: expected normal columns nx,ny,nz or a shape mesh "
                     "(--mesh), got neither");
  add_normals(t, read_mesh(mesh));
}

void add_normals(ProxyTrack& t, const TriMesh& mesh) {
  t.n.assign(t.q.size(), Vec3::UnitZ());
  const friction::MeshSurface shape(mesh, 0.0);
  for (std::size_t i = 0; i < t.q.size(); ++i) {
    Vec3 c, n;
    if (t.contact[i] && shape.closest(t.q[i], c, n)) t.n[i] = n;
  }
}

namespace {

// --proxy-prefix p: the probe as its own proxy (q = p); contact from the contact column, else
// from the force.
ProxyTrack probe_track(const Recording& rec, const ProxyColumnsSpec& o) {
  std::vector<char> c;
  std::string source;
  if (const std::vector<double>* cc = rec.find_extra(o.contact_column)) {
    for (double x : *cc) c.push_back(x != 0.0);
    source = "column:" + o.contact_column;
  } else {
    c = force_contact(rec, o.contact_threshold_n);
    source = fmt::format("force>{}N", o.contact_threshold_n);
  }
  ProxyTrack t = position_only_track(rec, c, source);
  t.proxy_source = "probe (--proxy-prefix p)";
  return t;
}

// The training recording's proxy track: its proxy columns; the probe itself for --proxy-prefix p
// (q = p, no elastic displacement); else estimated from the recording (r.estimate).
ProxyTrack train_track(const Recording& rec, const TrainFileOptions& o, TrainFileResult& r) {
  const std::string& prefix = o.proxy.prefix;
  if (prefix == "p") return probe_track(rec, o.proxy);
  if (has_proxy_columns(rec, prefix)) return track_of(rec, o.recording, o.proxy);
  if (o.request.given.count("--proxy-prefix"))
    throw ParseError(o.recording, 1,
                     fmt::format("--proxy-prefix {0}: expected proxy columns {0}x,{0}y,{0}z (mm), "
                                 "got none; leave the flag out to estimate the proxy from the "
                                 "recording, or give --proxy-prefix p to use the probe itself",
                                 prefix));
  EstimateParams ep = o.estimate;
  ep.contact_threshold_n = o.proxy.contact_threshold_n;
  r.estimate = estimate_recording(rec, ep, o.recording);
  return estimated_track(rec, r.estimate->sys, r.estimate->mesh);
}

// The options given explicitly override the preset's.
void override_given(TrainParams& p, const TrainRequest& r) {
  const TrainParams& g = r.params;
  const auto given = [&](const char* name) { return r.given.count(name) > 0; };
  if (given("--bins")) p.bins = g.bins;
  if (given("--centers")) p.centers = g.centers;
  if (given("--nonzeros")) p.nonzeros = g.nonzeros;
  if (given("--lambda-ratio")) p.lambda_ratio = g.lambda_ratio;
  if (given("--tail")) p.linear_tail = g.linear_tail;
  if (given("--tangent-mirror")) p.tangent_mirror = g.tangent_mirror;
  if (given("--stiffness-prior")) p.stiffness_prior = g.stiffness_prior;
  if (given("--shear-prior")) p.shear_prior = g.shear_prior;
  if (given("--friction-cone")) p.friction_cone = g.friction_cone;
  if (given("--sliding-floor")) p.sliding_floor = g.sliding_floor;
  if (given("--fallback")) p.fallback = g.fallback;
  if (given("--envelope")) p.envelope = g.envelope;
  if (given("--isotropic-positions")) p.isotropic_positions = g.isotropic_positions;
  if (given("--fallback-near")) p.fallback_near_mm = g.fallback_near_mm;
  if (given("--fallback-far")) p.fallback_far_mm = g.fallback_far_mm;
  if (given("--fallback-normal-near")) p.fallback_normal_near_mm = g.fallback_normal_near_mm;
  if (given("--fallback-normal-far")) p.fallback_normal_far_mm = g.fallback_normal_far_mm;
  if (given("--solver")) p.solver = g.solver;
  if (given("--feature-weights")) p.feature_weights = g.feature_weights;
  if (given("--bin-blend")) p.bin_blend = g.bin_blend;
  if (given("--design")) p.design = design_from_string(r.design);
  if (given("--features")) p.features = feature_set_from_string(r.features);
  if (p.features != FeatureSet::kLocalFrame) {  // the local-only settings of a local preset
    if (!given("--tangent-mirror")) p.tangent_mirror = false;
    if (!given("--stiffness-prior")) p.stiffness_prior = false;
    if (!given("--shear-prior")) p.shear_prior = false;
    if (!given("--friction-cone")) p.friction_cone = false;
    if (!given("--sliding-floor")) p.sliding_floor = false;
    if (!given("--fallback")) p.fallback = false;
  }
}

}  // namespace

TrainParams resolve_train_params(const TrainRequest& r, bool have_normals, std::string* note) {
  std::string preset = r.preset;
  const bool local_asked = r.given.count("--features") && r.features == "local";
  if (!have_normals && !local_asked && preset_params(preset).features == FeatureSet::kLocalFrame &&
      !r.given.count("--features")) {
    if (note)
      *note = fmt::format(
          "no normal columns nx,ny,nz and no --mesh: preset '{}' needs the surface normal, "
          "training with preset 'world' (world-frame features) instead",
          preset);
    preset = "world";
  }
  TrainParams p = preset_params(preset);
  override_given(p, r);
  p.seed = r.params.seed;
  p.threads = r.params.threads;
  p.modeling_range_n = r.params.modeling_range_n;
  p.above_range = above_range_from_string(r.above_range);
  return p;
}

std::string range_note(const ForceModelProvenance& m, const TrainingSet& set,
                       double force_limit_n) {
  const TrainStats& s = m.stats;
  const TrainParams& p = m.params;
  if (s.above_range == 0)
    return fmt::format("all {} samples within the {:.2f} N modeling range (max {:.2f} N)",
                       s.offered, p.modeling_range_n, s.max_force_n);
  const bool keep = p.above_range == AboveRange::kKeep;
  return fmt::format(
      "{} of {} samples ({:.1f} %) above the {:.2f} N modeling range (max {:.2f} N): {} ({}); {} "
      "above the {:.2f} N render clamp (device limit), where rendering caps the force",
      s.above_range, s.offered,
      100.0 * static_cast<double>(s.above_range) /
          static_cast<double>(std::max<std::size_t>(s.offered, 1)),
      p.modeling_range_n, s.max_force_n, keep ? "kept" : "excluded",
      keep ? "--above-range exclude leaves them out" : "--above-range keep trains on them",
      count_above(set.f, force_limit_n), force_limit_n);
}

std::vector<std::string> write_training_coverage(const TrainingSet& set, const std::string& path) {
  const CoverageMap map(set.q, set.f);
  write_coverage(path, map);
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& q : set.q)
    if (q.allFinite()) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  std::vector<double> fmax;
  for (const CoverageCell& c : map.cells()) fmax.push_back(c.f_max);
  std::sort(fmax.begin(), fmax.end());
  const double med = fmax.empty() ? 0.0 : fmax[fmax.size() / 2];
  std::vector<std::string> lines;
  lines.push_back(fmt::format(
      "coverage: {} cells of {:g} mm visited by q (x {:.1f}..{:.1f}, y {:.1f}..{:.1f} mm), "
      "largest |f| per cell median {:.2f} N; elsewhere the model extrapolates -> {}",
      map.cells().size(), map.params().cell_mm, lo.x(), hi.x(), lo.y(), hi.y(), med, path));
  const std::vector<CoverageGap> gaps = coverage_gaps(map);
  if (!gaps.empty()) {
    std::string line = "coverage: explore more around (x, y mm, unvisited area):";
    for (const CoverageGap& g : gaps)
      line +=
          fmt::format(" ({:.0f}, {:.0f}) {:.0f} mm^2", g.x_mm, g.y_mm,
                      static_cast<double>(g.cells) * map.params().cell_mm * map.params().cell_mm);
    lines.push_back(line);
  }
  return lines;
}

TrainFileResult train_from_file(const TrainFileOptions& o) {
  TrainFileResult r = train_from_recording(read_recording_in(o.recording, o.units), o);
  ForceModelProvenance& m = r.model.provenance;
  m.recording_path = o.recording;
  m.recording_digest = file_digest(o.recording);
  return r;
}

TrainFileResult train_from_recording(const Recording& rec, const TrainFileOptions& o) {
  TrainFileResult r;
  const auto say = [&](std::string line) {
    if (o.on_note) o.on_note(line);
    r.notes.push_back(std::move(line));
  };
  ProxyTrack track = train_track(rec, o, r);
  if (r.estimate) {
    say(estimate_note(*r.estimate));
    for (const std::string& w :
         {estimate_warning(*r.estimate), estimate_contact_warning(*r.estimate)})
      if (!w.empty()) say(w);
  }
  const bool have_normals = has_normal_columns(rec) || !o.mesh.empty() || r.estimate;
  std::string note;
  TrainParams params = resolve_train_params(o.request, have_normals, &note);
  if (!note.empty()) say(note);
  if (r.estimate && params.tangent_mirror && !o.request.given.count("--tangent-mirror")) {
    // A real material need not answer alike in every tangential direction (measured on
    // recordings of a silicone phantom: docs/real-recordings.md).
    params.tangent_mirror = false;
    say("tangent mirror off for an estimated proxy (--tangent-mirror turns it on)");
  }
  if (params.features == FeatureSet::kLocalFrame && !r.estimate)
    add_normals(track, rec, o.recording, o.mesh);
  FoawParams foaw = o.foaw;
  foaw.dt_s = median_dt(rec);
  if (!o.request.given.count("--foaw-window"))
    foaw.max_window = foaw_window_samples(o.velocity_window_s, foaw.dt_s);
  r.set = make_training_set(rec, track, foaw);
  if (r.estimate) r.baseline_set = baseline_samples(rec, track, foaw, o.proxy);
  say(fmt::format("{} samples, {} in contact ({}), proxy from {}", rec.size(), r.set.size(),
                  track.contact_source, track.proxy_source));
  const double contact_s = static_cast<double>(r.set.size()) * foaw.dt_s;
  if (contact_s < kFewContactSeconds)
    say(fmt::format(
        "warning: only {:.1f} s of contact to train on; a model needs about {:.0f} s or more of "
        "varied contact to generalise (expect large errors)",
        contact_s, kFewContactSeconds));
  const auto t0 = std::chrono::steady_clock::now();
  Progress train_progress;
  if (o.progress)
    train_progress = [t0, progress = o.progress](const std::string&, double frac, double) {
      const double el =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      progress("train", frac, frac > 0 ? el * (1 - frac) / frac : 0);
    };
  r.model = train_with_provenance(r.set, params, foaw, train_progress);
  r.model.model.force_limit_n = o.force_limit_n;
  ForceModelProvenance& m = r.model.provenance;
  m.proxy_source = track.proxy_source;
  m.time_unit = o.units.time;
  m.length_unit = o.units.length;
  if (r.estimate) m.estimated = {"surface", "normals", "proxy", "friction"};
  if (!o.sys.empty()) {
    m.sys_path = o.sys;
    m.sys_digest = file_digest(o.sys);
  }
  if (!o.mesh.empty()) {
    m.mesh_path = o.mesh;
    m.mesh_digest = file_digest(o.mesh);
  }
  return r;
}

std::string train_summary(const TrainedForceModel& tm, bool verbose) {
  const ForceModelProvenance& m = tm.provenance;
  std::string s = fmt::format(
      "trained {} samples in {:.1f} s: features {}, {} bins, design {}, non-zeros per "
      "axis",
      m.stats.samples, m.stats.seconds, to_string(tm.model.features), tm.model.bins.size(),
      to_string(m.params.design));
  for (const auto& x : m.stats.support) s += fmt::format(" {}/{}/{}", x[0], x[1], x[2]);
  s += "\n";
  for (std::size_t b = 0; b < m.stats.gap.size(); ++b)  // the l1 fit's certificate per bin
    for (int c = 0; c < 3; ++c) {
      const auto uc = static_cast<std::size_t>(c);
      s += fmt::format("  bin {} axis {}: {} relative gap {:.2e}, {} iterations, {} non-zeros\n", b,
                       "xyz"[c], to_string(m.params.solver), m.stats.gap[b][uc],
                       m.stats.sparsa_iterations[b][uc], m.stats.nonzeros[b][uc]);
    }
  if (verbose) {
    s += "  stages (CPU s, summed over threads):";
    for (const auto& [name, cpu] : m.stats.stage_cpu_s) s += fmt::format(" {} {:.2f}", name, cpu);
    s += fmt::format("; wall {:.2f} s\n", m.stats.seconds);
  }
  return s;
}

namespace {

// A file the model names (references.<key>.path): as written, else beside the model file.
std::string resolve_reference(const std::string& model_path, const std::string& path,
                              const char* key) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return path;
  const fs::path beside = fs::path(model_path).parent_path() / path;
  if (fs::path(path).is_relative() && fs::is_regular_file(beside, ec)) return beside.string();
  throw Error(fmt::format(
      "{}: the {} '{}' named by the model (references.{}.path) is found neither from the "
      "current folder nor from the model's folder",
      model_path, key, path, key));
}

}  // namespace

std::string model_mesh(const std::string& model_path, const std::string& mesh_flag,
                       const ForceModelProvenance& m) {
  if (!mesh_flag.empty()) return mesh_flag;
  if (m.mesh_path.empty())
    throw Error(
        fmt::format("{}: the model uses local-frame features but names no mesh; pass "
                    "--mesh FILE",
                    model_path));
  try {
    return resolve_reference(model_path, m.mesh_path, "mesh");
  } catch (const Error& e) {
    throw Error(fmt::format("{}; pass --mesh FILE to give it", e.what()));
  }
}

std::vector<std::string> write_estimate_files(const std::string& model_path,
                                              const RecordingEstimate& e, ForceModelProvenance& m) {
  namespace fs = std::filesystem;
  std::string stem = model_path;
  if (fs::path(stem).extension() == ".json") stem.resize(stem.size() - 5);
  const std::string mesh = stem + ".surface.ply", sys = stem + ".sys.json";
  write_mesh(mesh, e.mesh);
  friction::write_sys_json(sys, e.sys);
  m.mesh_path = fs::path(mesh).filename().string();
  m.mesh_digest = file_digest(mesh);
  m.sys_path = fs::path(sys).filename().string();
  m.sys_digest = file_digest(sys);
  return {mesh, sys};
}

namespace {

// The shape (or estimated surface) mesh of a model source.
TriMesh source_mesh(const ModelSource& m) {
  if (m.mesh) return *m.mesh;
  if (m.mesh_flag.empty() && m.estimate) return m.estimate->mesh;
  if (m.path.empty() && m.mesh_flag.empty())
    throw Error(
        "force model in memory: it uses local-frame features or an estimated proxy but has no "
        "mesh; give a shape mesh");
  return read_mesh(model_mesh(m.path, m.mesh_flag, m.model->provenance));
}

// The yield surfaces of a model trained on an estimated proxy.
friction::SysModel source_sys(const ModelSource& m) {
  if (m.estimate) return m.estimate->sys;
  const ForceModelProvenance& pv = m.model->provenance;
  if (m.path.empty() || pv.sys_path.empty())
    throw Error(
        fmt::format("{}: the model's proxy was estimated but it names no yield surfaces "
                    "(references.sys)",
                    m.path.empty() ? "force model in memory" : m.path));
  return friction::read_sys_json(resolve_reference(m.path, pv.sys_path, "sys"));
}

SupportShare share_outside(const CoverageMap& map, const ReplayedFile& r, std::string file) {
  SupportShare c;
  c.file = std::move(file);
  std::size_t n = 0, out = 0, out_pos = 0;
  for (std::size_t i = 0; i < r.rec.size(); ++i)
    if (r.track.contact[i]) {
      ++n;
      out += map.outside(r.track.q[i], r.rec.f[i].norm()) ? 1 : 0;
      out_pos += map.outside(r.track.q[i]) ? 1 : 0;
    }
  c.known = true;
  c.outside_share = n ? static_cast<double>(out) / static_cast<double>(n) : 0.0;
  c.outside_position_share = n ? static_cast<double>(out_pos) / static_cast<double>(n) : 0.0;
  return c;
}

}  // namespace

ProxyTrack replay_track(const ModelSource& m, const Recording& rec, const std::string& recording,
                        const ProxyColumnsSpec& proxy) {
  const TrainedForceModel& tm = *m.model;
  if (proxy.prefix == "p") return probe_track(rec, proxy);
  if (tm.provenance.proxy_source != "estimated") {
    ProxyTrack t = track_of(rec, recording, proxy);
    if (tm.model.features == FeatureSet::kLocalFrame) {  // normal columns first, else the mesh
      if (has_normal_columns(rec))
        add_normals(t, rec, recording, std::string());
      else
        add_normals(t, source_mesh(m));
    }
    return t;
  }
  const friction::SysModel sys = source_sys(m);
  return estimated_track(rec, sys, source_mesh(m));
}

ProxyTrack replay_track(const std::string& model_path, const TrainedForceModel& tm,
                        const Recording& rec, const std::string& recording,
                        const ProxyColumnsSpec& proxy, const std::string& mesh_flag) {
  ModelSource m;
  m.model = &tm;
  m.path = model_path;
  m.mesh_flag = mesh_flag;
  return replay_track(m, rec, recording, proxy);
}

ReplayedFile replay_recording(const ModelSource& m, Recording rec, const std::string& recording,
                              const ProxyColumnsSpec& proxy) {
  ReplayedFile r{std::move(rec), {}, {}};
  r.track = replay_track(m, r.rec, recording, proxy);
  r.forces = replay(m.model->model, r.rec, r.track);
  return r;
}

ReplayedFile replay_file(const std::string& model_path, const TrainedForceModel& tm,
                         const std::string& recording, const ProxyColumnsSpec& proxy,
                         const std::string& mesh_flag, const RecordingUnits& units) {
  ModelSource m;
  m.model = &tm;
  m.path = model_path;
  m.mesh_flag = mesh_flag;
  return replay_recording(m, read_recording_in(recording, units), recording, proxy);
}

SupportShare support_share(const std::string& model_path, const ReplayedFile& r) {
  const std::string file = coverage_path_for(model_path);
  // Returned as prvalues, not a named local: GCC 12 warns (-Warray-bounds, a false positive) on
  // the std::string move of a named return when the standard headers come from a PCH.
  if (!std::filesystem::exists(file)) return SupportShare{.file = file};
  return share_outside(read_coverage(file), r, file);
}

SupportShare support_share(const ModelSource& m, const ReplayedFile& r) {
  if (m.set) return share_outside(CoverageMap(m.set->q, m.set->f), r, std::string());
  if (m.path.empty())
    return SupportShare{.file = "(none: a model in memory without its training samples)"};
  return support_share(m.path, r);
}

std::string support_note(const SupportShare& c) {
  if (!c.known) return fmt::format("no coverage file {}: training support unknown", c.file);
  return fmt::format(
      "{:.1f} % of the contact samples outside the training support ({:.1f} % far from any "
      "training proxy, the rest beyond its force range)",
      100 * c.outside_share, 100 * c.outside_position_share);
}

std::vector<char> scored_samples(const Recording& rec, const ProxyTrack& t,
                                 const ProxyColumnsSpec& proxy) {
  return t.proxy_source == "estimated" ? force_contact(rec, proxy.contact_threshold_n) : t.contact;
}

TrainingSet baseline_samples(const Recording& rec, ProxyTrack track, const FoawParams& foaw,
                             const ProxyColumnsSpec& proxy) {
  track.contact = scored_samples(rec, track, proxy);
  return make_training_set(rec, track, foaw);
}

namespace {

// The samples the baselines are fitted on: `train` when given, else the training samples in
// memory, else the training recording the model file names; nullopt with the reason in `note`
// when there are none.
std::optional<TrainingSet> baseline_set(const ModelSource& m, const ProxyColumnsSpec& proxy,
                                        const Recording* train, const std::string& train_name,
                                        std::string& note) {
  const TrainedForceModel& tm = *m.model;
  if (train) {
    note = fmt::format("baselines fitted on {}", train_name);
    return baseline_samples(*train, replay_track(m, *train, train_name, proxy), tm.model.foaw,
                            proxy);
  }
  if (m.baseline_set || m.set) {
    note = "baselines fitted on the training samples";
    return m.baseline_set ? *m.baseline_set : *m.set;
  }
  const ForceModelProvenance& pv = tm.provenance;
  if (pv.recording_path.empty()) {
    note = "no baselines: the model names no training recording; give --train FILE";
    return std::nullopt;
  }
  std::string path;
  try {
    path = resolve_reference(m.path, pv.recording_path, "recording");
  } catch (const Error& e) {
    note = fmt::format("no baselines: {}; give --train FILE", e.what());
    return std::nullopt;
  }
  const Recording rec = read_recording_in(path, {pv.time_unit, pv.length_unit});
  note = fmt::format("baselines fitted on {}", path);
  return baseline_samples(rec, replay_track(m, rec, path, proxy), tm.model.foaw, proxy);
}

}  // namespace

ModelEvalResult evaluate_model(const ModelSource& m, const ReplayedFile& r,
                               const std::string& recording, const ProxyColumnsSpec& proxy,
                               const Recording* train, const std::string& train_name) {
  const TrainedForceModel& tm = *m.model;
  const std::vector<char> mask = scored_samples(r.rec, r.track, proxy);
  std::vector<Vec3> rendered, measured;
  for (std::size_t i = 0; i < r.rec.size(); ++i)
    if (mask[i]) {
      rendered.push_back(r.forces[i]);
      measured.push_back(r.rec.f[i]);
    }
  if (rendered.empty())
    throw Error(fmt::format("{}: expected samples in contact ({}), got none", recording,
                            r.track.contact_source));
  ModelEvalResult e;
  e.errors = force_errors(rendered, measured);
  e.contact_samples = rendered.size();
  e.support = support_share(m, r);
  nlohmann::ordered_json& j = e.json;
  j["model"] = m.path;
  j["recording"] = recording;
  j["samples"] = r.rec.size();
  j["contact_samples"] = rendered.size();
  j["proxy_source"] = r.track.proxy_source;
  j["contact_source"] = r.track.contact_source;
  j["units"] = {{"force", "N"}};
  // Measured forces above the model's render clamp: the rendered force is capped there (the
  // device limit), so the errors on those samples include the clamp. Said, not hidden.
  e.above_force_limit = count_above(measured, tm.model.force_limit_n);
  e.force_limit_n = tm.model.force_limit_n;
  j["force_limit_n"] = tm.model.force_limit_n;
  j["measured_above_force_limit"] = e.above_force_limit;
  if (e.support.known)
    j["coverage"] = {{"file", e.support.file},
                     {"outside_share", e.support.outside_share},
                     {"outside_position_share", e.support.outside_position_share}};
  j["errors"] = nlohmann::ordered_json::parse(force_errors_json(e.errors));
  const std::optional<TrainingSet> set =
      baseline_set(m, proxy, train, train_name, e.baselines_note);
  if (set) {
    e.baselines =
        score_with_baselines(r.forces, *set, r.rec, foaw_velocities(r.rec.p, tm.model.foaw), mask);
    j["baselines"] = baselines_json(*e.baselines);
    j["verdict"] = e.baselines->verdict;
  }
  return e;
}

ModelEvalResult evaluate_model_file(const std::string& model_path, const std::string& recording,
                                    const ProxyColumnsSpec& proxy, const std::string& mesh_flag,
                                    const RecordingUnits& units, const std::string& train) {
  const TrainedForceModel tm = load_trained_force_model(model_path);
  ModelSource m;
  m.model = &tm;
  m.path = model_path;
  m.mesh_flag = mesh_flag;
  const ReplayedFile r = replay_recording(m, read_recording_in(recording, units), recording, proxy);
  if (train.empty()) return evaluate_model(m, r, recording, proxy);
  const ForceModelProvenance& pv = tm.provenance;
  const Recording rec = read_recording_in(train, {pv.time_unit, pv.length_unit});
  return evaluate_model(m, r, recording, proxy, &rec, train);
}

std::string model_eval_text(const ModelEvalResult& r) {
  const ForceErrors& e = r.errors;
  std::string s = fmt::format(
      "{} contact samples: RMSE x/y/z {:.3f} {:.3f} {:.3f} N, median AE x/y/z {:.3f} {:.3f} {:.3f} "
      "N, "
      "RE mean {:.3f} median {:.3f}\n",
      e.n, e.rmse[0], e.rmse[1], e.rmse[2], e.ae_axis_median[0], e.ae_axis_median[1],
      e.ae_axis_median[2], e.re_mean, e.re_median);
  if (r.baselines) s += baseline_text(*r.baselines);
  if (r.above_force_limit > 0)
    s += fmt::format(
        "{} contact samples measured above the {:.2f} N render clamp (device limit): the "
        "rendered force is capped there\n",
        r.above_force_limit, r.force_limit_n);
  return s;
}

void write_rendered_csv(const std::string& out, const ReplayedFile& r, const std::string& recording,
                        const std::string& model_path) {
  const std::vector<std::string> comments{
      "units: t s, p mm, f (rendered) N, mf (measured) N",
      fmt::format("rendered by inhap model render from {} with {}", recording, model_path)};
  CsvWriter w(out, {"t", "px", "py", "pz", "fx", "fy", "fz", "mfx", "mfy", "mfz", "contact"},
              comments);
  for (std::size_t i = 0; i < r.rec.size(); ++i) {
    const Vec3 &p = r.rec.p[i], &f = r.forces[i], &mf = r.rec.f[i];
    w.row({r.rec.t[i], p.x(), p.y(), p.z(), f.x(), f.y(), f.z(), mf.x(), mf.y(), mf.z(),
           r.track.contact[i] ? 1.0 : 0.0});
  }
  w.commit();
}

}  // namespace inhap::eval
