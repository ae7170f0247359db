// inhap model train | eval | render: the data-driven force model of thesis sec. 4.4-4.5.
// Units: positions mm, velocities mm/s, forces N, time s.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/metrics.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "model_flags.hpp"

namespace inhap::cli {
namespace {

using namespace inhap::datadriven;

constexpr double kFewContactSeconds = 30.0;  // less contact than this gets a warning

struct ProxyOptions {
  std::string prefix = "q", contact_column = "contact";
  double contact_threshold = 0.05;
};

void add_proxy_options(CLI::App* c, ProxyOptions& o) {
  c->add_option("--proxy-prefix", o.prefix,
                "Proxy columns <prefix>x,<prefix>y,<prefix>z of the recording, mm (written by the "
                "proxy estimator)")
      ->capture_default_str();
  c->add_option("--contact-column", o.contact_column,
                "Contact flag column (non-zero = contact); when absent, contact = |f| above "
                "--contact-threshold")
      ->capture_default_str();
  c->add_option("--contact-threshold", o.contact_threshold, "Force magnitude for contact, N")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
}

/// Normals at q for local-frame models: columns nx,ny,nz when the recording has them, else the
/// outward normal of the shape mesh (probe-centre surface) closest to q.
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
  const friction::MeshSurface shape(read_mesh(mesh), 0.0);
  for (std::size_t i = 0; i < rec.size(); ++i) {
    Vec3 c, n;
    if (t.contact[i] && shape.closest(t.q[i], c, n)) t.n[i] = n;
  }
}

ProxyTrack track_of(const Recording& rec, const std::string& path, const ProxyOptions& o) {
  return proxy_from_columns(rec, path, o.prefix, o.contact_column, o.contact_threshold);
}

// ----------------------------------------------------------------------------------- train
struct TrainOptions {
  std::string recording, sys, mesh, out, preset = "best", above_range = "keep";
  std::string design = to_string(preset_params("best").design), features = "local";
  TrainParams params = preset_params("best");
  FoawParams foaw;
  double force_limit_n = kDeviceForceLimitN;
  ProxyOptions proxy;
  bool verbose = false;
  std::set<std::string> given;  ///< long names of the options given on the command line
};

/// The preset's settings, overridden by every option given explicitly. Without normal columns
/// and without --mesh, the default local-frame pipeline cannot run: the "world" preset is used
/// instead (said on stderr) unless local features were asked for explicitly.
TrainParams resolve_params(TrainOptions& o, bool have_normals) {
  std::string preset = o.preset;
  const bool local_asked = o.given.count("--features") && o.features == "local";
  if (!have_normals && !local_asked && preset_params(preset).features == FeatureSet::kLocalFrame &&
      !o.given.count("--features")) {
    fmt::print(stderr,
               "inhap: no normal columns nx,ny,nz and no --mesh: preset '{}' needs the surface "
               "normal, training with preset 'world' (world-frame features) instead\n",
               preset);
    preset = "world";
  }
  TrainParams p = preset_params(preset);
  const TrainParams& g = o.params;
  const auto given = [&](const char* name) { return o.given.count(name) > 0; };
  if (given("--bins")) p.bins = g.bins;
  if (given("--centers")) p.centers = g.centers;
  if (given("--nonzeros")) p.nonzeros = g.nonzeros;
  if (given("--lambda-ratio")) p.lambda_ratio = g.lambda_ratio;
  if (given("--tail")) p.linear_tail = g.linear_tail;
  if (given("--tangent-mirror")) p.tangent_mirror = g.tangent_mirror;
  if (given("--stiffness-prior")) p.stiffness_prior = g.stiffness_prior;
  if (given("--shear-prior")) p.shear_prior = g.shear_prior;
  if (given("--friction-cone")) p.friction_cone = g.friction_cone;
  if (given("--fallback")) p.fallback = g.fallback;
  if (given("--fallback-near")) p.fallback_near_mm = g.fallback_near_mm;
  if (given("--fallback-far")) p.fallback_far_mm = g.fallback_far_mm;
  if (given("--solver")) p.solver = g.solver;
  if (given("--feature-weights")) p.feature_weights = g.feature_weights;
  if (given("--bin-blend")) p.bin_blend = g.bin_blend;
  if (given("--design")) p.design = design_from_string(o.design);
  if (given("--features")) p.features = feature_set_from_string(o.features);
  if (p.features != FeatureSet::kLocalFrame) {  // the local-only settings of a local preset
    if (!given("--tangent-mirror")) p.tangent_mirror = false;
    if (!given("--stiffness-prior")) p.stiffness_prior = false;
    if (!given("--shear-prior")) p.shear_prior = false;
    if (!given("--friction-cone")) p.friction_cone = false;
    if (!given("--fallback")) p.fallback = false;
  }
  p.seed = g.seed;
  p.threads = g.threads;
  p.modeling_range_n = g.modeling_range_n;
  p.above_range = above_range_from_string(o.above_range);
  return p;
}

/// One line on the forces above the modeling range and above the render clamp (never silent).
void report_range(const ForceModel& m, const TrainingSet& set, double force_limit_n) {
  const TrainStats& s = m.stats;
  const TrainParams& p = m.params;
  if (s.above_range == 0) {
    fmt::print(stderr, "inhap: all {} samples within the {:.2f} N modeling range (max {:.2f} N)\n",
               s.offered, p.modeling_range_n, s.max_force_n);
    return;
  }
  fmt::print(stderr,
             "inhap: {} of {} samples ({:.1f} %) above the {:.2f} N modeling range (max {:.2f} "
             "N): {} ({}); {} above the {:.2f} N render clamp (device limit), where rendering "
             "caps the force\n",
             s.above_range, s.offered,
             100.0 * static_cast<double>(s.above_range) /
                 static_cast<double>(std::max<std::size_t>(s.offered, 1)),
             p.modeling_range_n, s.max_force_n,
             p.above_range == AboveRange::kKeep ? "kept" : "excluded",
             p.above_range == AboveRange::kKeep ? "--above-range exclude leaves them out"
                                                : "--above-range keep trains on them",
             count_above(set.f, force_limit_n), force_limit_n);
}

/// Writes where the recording covered the object beside the model and says it in one line.
void report_coverage(const TrainingSet& set, const std::string& path) {
  const CoverageMap map(set.q, set.f);
  write_coverage(path, map);
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& q : set.q)
    if (q.allFinite()) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  std::vector<double> fmax;
  for (const CoverageCell& c : map.cells()) fmax.push_back(c.f_max);
  std::sort(fmax.begin(), fmax.end());
  const double med = fmax.empty() ? 0.0 : fmax[fmax.size() / 2];
  fmt::print(
      stderr,
      "inhap: coverage: {} cells of {:g} mm visited by q (x {:.1f}..{:.1f}, y {:.1f}..{:.1f} "
      "mm), largest |f| per cell median {:.2f} N; elsewhere the model extrapolates -> {}\n",
      map.cells().size(), map.params().cell_mm, lo.x(), hi.x(), lo.y(), hi.y(), med, path);
  const std::vector<CoverageGap> gaps = coverage_gaps(map);
  if (!gaps.empty()) {
    fmt::print(stderr, "inhap: coverage: explore more around (x, y mm, unvisited area):");
    for (const CoverageGap& g : gaps)
      fmt::print(stderr, " ({:.0f}, {:.0f}) {:.0f} mm^2", g.x_mm, g.y_mm,
                 static_cast<double>(g.cells) * map.params().cell_mm * map.params().cell_mm);
    fmt::print(stderr, "\n");
  }
}

void run_train(TrainOptions o) {
  const Recording rec = read_recording(o.recording);
  ProxyTrack track = track_of(rec, o.recording, o.proxy);
  const bool have_normals =
      (rec.find_extra("nx") && rec.find_extra("ny") && rec.find_extra("nz")) || !o.mesh.empty();
  o.params = resolve_params(o, have_normals);
  if (o.params.features == FeatureSet::kLocalFrame) add_normals(track, rec, o.recording, o.mesh);
  o.foaw.dt_s = median_dt(rec);
  const TrainingSet set = make_training_set(rec, track, o.foaw);
  fmt::print(stderr, "inhap: {} samples, {} in contact ({}), proxy from {}\n", rec.size(),
             set.size(), track.contact_source, track.proxy_source);
  const double contact_s = static_cast<double>(set.size()) * o.foaw.dt_s;
  if (contact_s < kFewContactSeconds)
    fmt::print(stderr,
               "inhap: warning: only {:.1f} s of contact to train on; a model needs about {:.0f} s "
               "or more of varied contact to generalise (expect large errors)\n",
               contact_s, kFewContactSeconds);
  const auto t0 = std::chrono::steady_clock::now();
  o.params.progress = [t0](double frac, const std::string&) {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    progress("train", frac, frac > 0 ? el * (1 - frac) / frac : 0);
  };
  ForceModel m = train_force_model(set, o.params, o.foaw);
  m.force_limit_n = o.force_limit_n;
  m.proxy_source = track.proxy_source;
  if (!o.sys.empty()) {
    m.sys_path = o.sys;
    m.sys_digest = file_digest(o.sys);
  }
  if (!o.mesh.empty()) {
    m.mesh_path = o.mesh;
    m.mesh_digest = file_digest(o.mesh);
  }
  save_force_model(o.out, m);
  report_range(m, set, o.force_limit_n);
  report_coverage(set, coverage_path_for(o.out));
  fmt::print("trained {} samples in {:.1f} s: features {}, {} bins, design {}, non-zeros per axis",
             m.stats.samples, m.stats.seconds, to_string(m.features), m.bins.size(),
             to_string(m.params.design));
  for (const auto& s : m.stats.support) fmt::print(" {}/{}/{}", s[0], s[1], s[2]);
  fmt::print("\n");
  for (std::size_t b = 0; b < m.stats.gap.size(); ++b)  // the l1 fit's certificate per bin
    for (int c = 0; c < 3; ++c) {
      const auto uc = static_cast<std::size_t>(c);
      fmt::print("  bin {} axis {}: {} relative gap {:.2e}, {} iterations, {} non-zeros\n", b,
                 "xyz"[c], to_string(m.params.solver), m.stats.gap[b][uc],
                 m.stats.sparsa_iterations[b][uc], m.stats.nonzeros[b][uc]);
    }
  if (o.verbose) {
    fmt::print("  stages (CPU s, summed over threads):");
    for (const auto& [name, s] : m.stats.stage_cpu_s) fmt::print(" {} {:.2f}", name, s);
    fmt::print("; wall {:.2f} s\n", m.stats.seconds);
  }
  fmt::print("model -> {}\n", o.out);
}

// ------------------------------------------------------------------------------ eval/render
struct ReplayOptions {
  std::string model, recording, json, out, mesh;
  ProxyOptions proxy;
};

struct Replayed {
  Recording rec;
  ProxyTrack track;
  std::vector<Vec3> forces;
};

/// The mesh a local-frame model needs: --mesh, else the model's reference, taken as written
/// (relative to the current folder) or relative to the model file's folder. An error says
/// where the path came from and that --mesh overrides it.
std::string model_mesh(const ReplayOptions& o, const ForceModel& m) {
  if (!o.mesh.empty()) return o.mesh;
  namespace fs = std::filesystem;
  std::error_code ec;
  if (m.mesh_path.empty())
    throw Error(
        fmt::format("{}: the model uses local-frame features but names no mesh; pass "
                    "--mesh FILE",
                    o.model));
  if (fs::is_regular_file(m.mesh_path, ec)) return m.mesh_path;
  const fs::path beside = fs::path(o.model).parent_path() / m.mesh_path;
  if (fs::path(m.mesh_path).is_relative() && fs::is_regular_file(beside, ec))
    return beside.string();
  throw Error(fmt::format(
      "{}: the mesh '{}' named by the model (references.mesh.path) is found neither from the "
      "current folder nor from the model's folder; pass --mesh FILE to give it",
      o.model, m.mesh_path));
}

Replayed replay_file(const ReplayOptions& o, const ForceModel& m) {
  Replayed r{read_recording(o.recording), {}, {}};
  r.track = track_of(r.rec, o.recording, o.proxy);
  if (m.features == FeatureSet::kLocalFrame) {
    // Normal columns in the recording come first; the mesh is only looked for without them.
    const bool has_normals =
        r.rec.find_extra("nx") && r.rec.find_extra("ny") && r.rec.find_extra("nz");
    add_normals(r.track, r.rec, o.recording, has_normals ? std::string() : model_mesh(o, m));
  }
  r.forces = replay(m, r.rec, r.track);
  return r;
}

struct Coverage {
  bool known = false;
  std::string file;
  double outside_share = 0, outside_position_share = 0;
};

/// Share of the in-contact samples outside the training support (coverage file beside the
/// model; unknown when there is none), printed in one line.
Coverage coverage_of(const std::string& model_path, const Replayed& r) {
  Coverage c;
  c.file = coverage_path_for(model_path);
  if (!std::filesystem::exists(c.file)) {
    fmt::print(stderr, "inhap: no coverage file {}: training support unknown\n", c.file);
    return c;
  }
  const CoverageMap map = read_coverage(c.file);
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
  fmt::print(stderr,
             "inhap: {:.1f} % of the contact samples outside the training support ({:.1f} % far "
             "from any training proxy, the rest beyond its force range)\n",
             100 * c.outside_share, 100 * c.outside_position_share);
  return c;
}

void run_eval(const ReplayOptions& o) {
  const ForceModel m = load_force_model(o.model);
  const Replayed r = replay_file(o, m);
  std::vector<Vec3> rendered, measured;
  for (std::size_t i = 0; i < r.rec.size(); ++i)
    if (r.track.contact[i]) {
      rendered.push_back(r.forces[i]);
      measured.push_back(r.rec.f[i]);
    }
  if (rendered.empty())
    throw Error(fmt::format("{}: expected samples in contact ({}), got none", o.recording,
                            r.track.contact_source));
  const ForceErrors e = force_errors(rendered, measured);
  const Coverage cov = coverage_of(o.model, r);
  nlohmann::ordered_json j;
  j["model"] = o.model;
  j["recording"] = o.recording;
  j["samples"] = r.rec.size();
  j["contact_samples"] = rendered.size();
  j["proxy_source"] = r.track.proxy_source;
  j["contact_source"] = r.track.contact_source;
  j["units"] = {{"force", "N"}};
  // Measured forces above the model's render clamp: the rendered force is capped there (the
  // device limit), so the errors on those samples include the clamp. Said, not hidden.
  const std::size_t above = count_above(measured, m.force_limit_n);
  j["force_limit_n"] = m.force_limit_n;
  j["measured_above_force_limit"] = above;
  if (cov.known)
    j["coverage"] = {{"file", cov.file},
                     {"outside_share", cov.outside_share},
                     {"outside_position_share", cov.outside_position_share}};
  j["errors"] = nlohmann::ordered_json::parse(force_errors_json(e));
  if (!o.json.empty()) write_file_atomic(o.json, j.dump(1) + "\n");
  fmt::print(
      "{} contact samples: RMSE x/y/z {:.3f} {:.3f} {:.3f} N, median AE x/y/z {:.3f} {:.3f} {:.3f} "
      "N, "
      "RE mean {:.3f} median {:.3f}\n",
      e.n, e.rmse[0], e.rmse[1], e.rmse[2], e.ae_axis_median[0], e.ae_axis_median[1],
      e.ae_axis_median[2], e.re_mean, e.re_median);
  if (above > 0)
    fmt::print(
        "{} contact samples measured above the {:.2f} N render clamp (device limit): the "
        "rendered force is capped there\n",
        above, m.force_limit_n);
}

void run_render(const ReplayOptions& o) {
  const ForceModel m = load_force_model(o.model);
  const Replayed r = replay_file(o, m);
  coverage_of(o.model, r);
  const std::vector<std::string> comments{
      "units: t s, p mm, f (rendered) N, mf (measured) N",
      fmt::format("rendered by inhap model render from {} with {}", o.recording, o.model)};
  CsvWriter w(o.out, {"t", "px", "py", "pz", "fx", "fy", "fz", "mfx", "mfy", "mfz", "contact"},
              comments);
  for (std::size_t i = 0; i < r.rec.size(); ++i) {
    const Vec3 &p = r.rec.p[i], &f = r.forces[i], &mf = r.rec.f[i];
    w.row({r.rec.t[i], p.x(), p.y(), p.z(), f.x(), f.y(), f.z(), mf.x(), mf.y(), mf.z(),
           r.track.contact[i] ? 1.0 : 0.0});
  }
  w.commit();
  fmt::print("{} samples rendered -> {}\n", r.rec.size(), o.out);
}

void register_model(CLI::App& app) {
  auto* model = app.add_subcommand(
      "model",
      "Data-driven force model f = g(p, pdot, q) (thesis 4.4): r^3 RBFs per ||q - p|| bin.\n"
      "Recordings need proxy columns qx,qy,qz (mm) and a contact column (or a force threshold).");
  model->require_subcommand(1);

  auto tr = std::make_shared<TrainOptions>();
  auto* ct = model->add_subcommand(
      "train",
      "Train a model from a recording (writes model JSON). With no flags: preset 'best', the "
      "documented pipeline\n(local-frame features, tangent mirror, stiffness and shear priors, "
      "friction cone, feature weights 1 5 0.5,\nbin blend 1 mm; needs normals nx,ny,nz or "
      "--mesh, else preset 'world' with a note). Options given\nexplicitly override the "
      "preset. Forces above --modeling-range are counted and reported, never clipped.");
  ct->add_option("--recording", tr->recording, "Recording CSV (t s, p mm, f N, qx,qy,qz mm)")
      ->required();
  ct->add_option("--sys", tr->sys, "Sliding-yield-surface file to reference in the model");
  ct->add_option("--mesh", tr->mesh, "Shape mesh to reference in the model");
  ct->add_option("--out", tr->out, "Model file to write (.json)")->required();
  ct->add_option("--preset", tr->preset,
                 "best = the documented pipeline; world = world-frame (q - p, q, pdot) features, "
                 "no priors (no normals needed); thesis = the thesis' settings (sec. 4.4: world "
                 "frame, 5 bins, no tail, M x N design, equal weights)")
      ->capture_default_str()
      ->check(CLI::IsMember(preset_names()));
  ct->add_option("--modeling-range", tr->params.modeling_range_n,
                 "Modeling range, N: samples with |f| above it are counted and reported, and "
                 "kept or excluded (--above-range)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ct->add_option("--above-range", tr->above_range,
                 "keep = train on forces above the modeling range as measured; exclude = leave "
                 "those samples out (either way they are counted and reported; nothing is "
                 "clipped)")
      ->capture_default_str()
      ->check(CLI::IsMember({"keep", "exclude"}));
  ct->add_option("--bins", tr->params.bins, "Bins by ||q - p|| (equal counts; default: preset)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  ct->add_option("--centers", tr->params.centers, "M: k-means clusters (selected samples) per bin")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ct->add_option("--nonzeros", tr->params.nonzeros, "Wanted non-zeros per axis (0 = M)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  ct->add_option("--lambda-ratio", tr->params.lambda_ratio, "lambda = ratio * ||A~^T f~||_inf")
      ->capture_default_str();
  ct->add_option("--seed", tr->params.seed, "Seed of the k-means++ draws")->capture_default_str();
  ct->add_option("--design", tr->design,
                 "thesis: A~ is M x N_bin (rows = selected samples, sec. 4.4.2); regression: A~ is "
                 "N_bin x M (rows = every sample, columns = selected samples); default: preset")
      ->capture_default_str()
      ->check(CLI::IsMember({"thesis", "regression"}));
  ct->add_option("--features", tr->features,
                 "ue_q_v = (q - p, q, pdot); p_v_q = (p, pdot, q); local = (q - p, q, pdot) with "
                 "q - p, pdot and the force in the surface frame at q (normals from columns "
                 "nx,ny,nz or from --mesh); default: preset")
      ->capture_default_str()
      ->check(CLI::IsMember({"ue_q_v", "p_v_q", "local"}));
  add_switch(
      *ct, "tail", tr->params.linear_tail,
      "Linear polynomial tail on every expansion (the thesis has none; default: preset, on in "
      "best and world, off in thesis)",
      false);
  add_local_training_flags(*ct, tr->params, "default: preset; on in best, off in world and thesis");
  ct->add_option("--feature-weights", tr->params.feature_weights,
                 "Weights of the three feature groups after standardisation (default: preset; "
                 "best 1 5 0.5)");
  ct->add_option("--bin-blend", tr->params.bin_blend,
                 "Half-width of the blend band around bin edges, mm of ||q - p|| (0: hard "
                 "switch; default: preset)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  ct->add_option("--threads", tr->params.threads, "Worker threads (0 = all cores)")
      ->capture_default_str();
  ct->add_option("--foaw-window", tr->foaw.max_window, "FOAW window cap, samples")
      ->capture_default_str()
      ->check(CLI::Range(1, kFoawMaxWindow - 1));
  ct->add_option("--foaw-noise", tr->foaw.noise_bound_mm, "FOAW noise bound d, mm")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  ct->add_option("--force-limit", tr->force_limit_n,
                 fmt::format("Rendered force clamp, N (may lower the device's {} N, never raise "
                             "it; the training data "
                             "are not clipped)",
                             kDeviceForceLimitN))
      ->capture_default_str()
      ->check(CLI::Range(1e-9, kDeviceForceLimitN));
  add_proxy_options(ct, tr->proxy);
  ct->add_flag("--verbose", tr->verbose,
               "Print the CPU time of each training stage (s, summed over threads)");
  ct->callback([tr, ct] {
    for (const CLI::Option* opt : ct->get_options())
      if (opt->count() > 0)
        for (const std::string& name : opt->get_lnames())  // --no-x counts as --x given
          tr->given.insert("--" + (name.rfind("no-", 0) == 0 ? name.substr(3) : name));
    run_train(*tr);
  });

  auto ev = std::make_shared<ReplayOptions>();
  auto* ce = model->add_subcommand(
      "eval", "Replay a recording through the servo renderer; errors (eq. 4.27-4.31)");
  ce->add_option("--model", ev->model, "Model JSON")->required();
  ce->add_option("--recording", ev->recording, "Test recording CSV with proxy columns")->required();
  ce->add_option("--json", ev->json, "Write the error report (N) as JSON here");
  add_proxy_options(ce, ev->proxy);
  ce->add_option("--mesh", ev->mesh,
                 "Shape mesh for the normals of a local-frame model (default: the model's)");
  ce->callback([ev] { run_eval(*ev); });

  auto rn = std::make_shared<ReplayOptions>();
  auto* cr = model->add_subcommand("render",
                                   "Replay a recording at servo rate; write rendered forces (N)");
  cr->add_option("--model", rn->model, "Model JSON")->required();
  cr->add_option("--recording", rn->recording, "Recording CSV with proxy columns")->required();
  cr->add_option("--out", rn->out,
                 "CSV to write: t,px,py,pz,fx,fy,fz (rendered),mfx,mfy,mfz (measured),contact")
      ->required();
  add_proxy_options(cr, rn->proxy);
  cr->add_option("--mesh", rn->mesh,
                 "Shape mesh for the normals of a local-frame model (default: the model's)");
  cr->callback([rn] { run_render(*rn); });
}

}  // namespace

INHAP_COMMAND(40, "model", register_model);

}  // namespace inhap::cli
