// Force-model evaluation on the virtual lab (see forces_lab.hpp). Units: mm, N, s; us.
//
// Proxy and contact (ForceLabOptions::proxy):
//   estimated (default): the scene is palpated once (palpate_scene: 9 reference points on
//     planar, 18 on the dome, as `inhap eval sys`), the sliding yield surfaces fitted, and the
//     friction module's proxy estimator (proxy_step, with creep) is run over the training and
//     test recordings: q, the surface normal at q and geometric contact with the palpated shape
//     mesh ("proxy_source": "estimated:sys", "contact_source": "estimated:geometric");
//   truth: the lab's true proxy (truth sidecar ax,ay,az), the object's normal at it and the truth
//     contact flag.
// Scoring is always against the measured force, on the samples the lab says are in contact (the
// same set for both sources).
#include "inhap/eval/forces_lab.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <unordered_map>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/core/stats.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/datadriven/servo.hpp"
#include "inhap/eval/lab_files.hpp"
#include "inhap/eval/recordings.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/proxy_track.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::eval {
namespace {

using namespace inhap::datadriven;

struct Durations {
  double train_s, test_s;
};

Durations durations_for(const std::string& scene) {
  if (scene == "planar") return {65.0, 37.0};  // thesis 4.5.1: ~65,000 / ~37,000 samples
  if (scene == "dome") return {52.0, 24.0};    // thesis 4.5.2: ~52,000 / ~24,000 samples
  return {60.0, 30.0};
}

/// Proxy q, normal and contact of every sample from the lab's ground truth (anchor = true
/// proxy; normal of the object's surface closest to it).
ProxyTrack truth_track(const lab::Scene& scene, const lab::LabRecording& lr) {
  const Recording& rec = lr.rec;
  ProxyTrack t;
  t.proxy_source = "truth";
  t.contact_source = "truth";
  t.q.resize(rec.size());
  t.n.assign(rec.size(), Vec3::UnitZ());
  t.contact.resize(rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    t.contact[i] = lr.truth.contact[i] != 0 && lr.truth.anchor[i].allFinite();
    t.q[i] = t.contact[i] ? lr.truth.anchor[i] : rec.p[i];
    if (t.contact[i]) {
      const lab::SurfaceQuery sq = scene.object.query(t.q[i]);
      if (std::isfinite(sq.distance) && sq.normal.allFinite()) t.n[i] = sq.normal;
    }
  }
  return t;
}

/// Proxy q, normal at q and geometric contact from the friction module's estimator.
ProxyTrack palpation_track(const ScenePalpation& pal, const Recording& rec) {
  const friction::ProxyColumns c =
      friction::proxy_track(friction::ProxyModel{&pal.sys, pal.shape.get()}, rec);
  ProxyTrack t;
  t.proxy_source = "estimated:sys";
  t.contact_source = "estimated:geometric";
  t.q.resize(rec.size());
  t.n.assign(rec.size(), Vec3::UnitZ());
  t.contact.resize(rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    t.contact[i] = c.contact[i] && c.q[i].allFinite();
    t.q[i] = t.contact[i] ? c.q[i] : rec.p[i];
    if (t.contact[i]) t.n[i] = c.n[i];
  }
  return t;
}

/// The ordinary random free exploration (the test run; the training run with "random").
lab::LabRecording record_random(const lab::Scene& scene, double seconds, std::uint64_t seed,
                                const Progress& prog, lab::Physics physics) {
  lab::RecordSpec spec;
  spec.physics = physics;
  spec.operator_name = "explore";
  spec.seconds = seconds;
  spec.seed = seed;
  return lab::record_scene(scene, spec, prog);
}

/// The explore operator's coverage-driven training mode (`inhap lab record --coverage`).
lab::LabRecording record_coverage(const lab::Scene& scene, double seconds, std::uint64_t seed,
                                  const ForceLabOptions& o, const Progress& prog) {
  lab::RecordSpec spec;
  spec.operator_name = "explore";
  spec.seconds = seconds;
  spec.seed = seed;
  spec.physics = o.physics;
  spec.explore.coverage = true;
  spec.explore.coverage_share = o.coverage_share;
  spec.explore.seconds_per_spot = o.seconds_per_spot;
  spec.explore.coverage_force_min = o.coverage_force_min;
  spec.explore.coverage_force_max = o.coverage_force_max;
  return lab::record_scene(scene, spec, prog);
}

/// Estimated vs true proxy of the test run: RMS distance where both are in contact, and the
/// fraction of samples whose contact flags agree.
void compare_with_truth(ForceLabResult& d, const ProxyTrack& truth) {
  double sq = 0;
  std::size_t both = 0, agree = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    agree += (truth.contact[i] != 0) == (d.test_track.contact[i] != 0);
    if (truth.contact[i] && d.test_track.contact[i]) {
      sq += (truth.q[i] - d.test_track.q[i]).squaredNorm();
      ++both;
    }
  }
  d.proxy_rms_mm =
      both ? std::sqrt(sq / static_cast<double>(both)) : std::numeric_limits<double>::quiet_NaN();
  d.contact_agreement = truth.size() ? static_cast<double>(agree) / truth.size() : 0.0;
}

ForceReplay timed_replay(const ForceModel& m, const Recording& rec, const ProxyTrack& track) {
  ForceReplay r;
  r.forces = replay(m, rec, track, &r.step_us);
  return r;
}

/// Statistics of an empty subset (or of a variant not run): n = 0, NaN (written as null).
ForceErrors no_errors() {
  ForceErrors e;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  e.ae_mean = e.ae_median = e.re_mean = e.re_median = nan;
  e.rmse.fill(nan);
  e.ae_axis_median.fill(nan);
  return e;
}

/// Errors over in-contact samples with t >= t_from (and mask[i] when a mask is given); an
/// empty subset gives n = 0 and NaN statistics (written as null).
ForceErrors errors_from(const Recording& rec, const std::vector<char>& contact,
                        const std::vector<Vec3>& f, double t_from,
                        const std::vector<char>* mask = nullptr) {
  std::vector<Vec3> r, m;
  for (std::size_t i = 0; i < rec.size(); ++i)
    if (contact[i] && rec.t[i] >= t_from && (!mask || (*mask)[i])) {
      r.push_back(f[i]);
      m.push_back(rec.f[i]);
    }
  if (r.empty()) return no_errors();
  return force_errors(r, m);
}

/// Test samples "covered" by the training run: some training contact sample lies within
/// `radius` mm in (q, ||q - p||) space (same spot, same elastic displacement magnitude).
std::vector<char> coverage(const Recording& train, const ProxyTrack& tr, const Recording& test,
                           const ProxyTrack& te, double radius) {
  auto cell = [radius](double v) { return static_cast<long>(std::floor(v / radius)); };
  auto key = [](long a, long b, long c) {
    return (a * 73856093L) ^ (b * 19349663L) ^ (c * 83492791L);
  };
  std::unordered_multimap<long, Eigen::Vector4d> grid;
  for (std::size_t i = 0; i < train.size(); ++i)
    if (tr.contact[i]) {
      const Vec3& q = tr.q[i];
      grid.emplace(key(cell(q.x()), cell(q.y()), cell(q.z())),
                   Eigen::Vector4d(q.x(), q.y(), q.z(), (q - train.p[i]).norm()));
    }
  std::vector<char> out(test.size(), 0);
  for (std::size_t i = 0; i < test.size(); ++i) {
    if (!te.contact[i]) continue;
    const Vec3& q = te.q[i];
    const Eigen::Vector4d x(q.x(), q.y(), q.z(), (q - test.p[i]).norm());
    for (long a = -1; a <= 1 && !out[i]; ++a)
      for (long b = -1; b <= 1 && !out[i]; ++b)
        for (long c = -1; c <= 1 && !out[i]; ++c) {
          const auto range =
              grid.equal_range(key(cell(q.x()) + a, cell(q.y()) + b, cell(q.z()) + c));
          for (auto it = range.first; it != range.second; ++it)
            if ((it->second - x).norm() <= radius) {
              out[i] = 1;
              break;
            }
        }
  }
  return out;
}

/// Training vs test ranges of the with-proxy model (see ForceSupport).
ForceSupport support_stats(ForceLabResult& d, const std::vector<char>& scored) {
  ForceSupport s;
  d.test_support.assign(d.test.rec.size(), SupportCheck{});
  const ForceModel& m = d.proxy.model;
  auto ranges = [&](const Recording& rec, const ProxyTrack& tr, std::vector<double>& depth,
                    std::vector<double>& speed, std::vector<Vec3>& v) {
    v = foaw_velocities(rec.p, m.foaw);
    for (std::size_t i = 0; i < rec.size(); ++i)
      if (tr.contact[i]) {
        depth.push_back((tr.q[i] - rec.p[i]).norm());
        speed.push_back(v[i].norm());
      }
  };
  std::vector<double> dtr, str, dte, ste;
  std::vector<Vec3> vtr, vte;
  ranges(d.train.rec, d.train_track, dtr, str, vtr);
  ranges(d.test.rec, d.test_track, dte, ste, vte);
  if (dtr.empty() || dte.empty()) return s;
  s.train_depth_p99 = quantile(dtr, 0.99), s.train_depth_max = quantile(dtr, 1.0);
  s.train_speed_p99 = quantile(str, 0.99), s.train_speed_max = quantile(str, 1.0);
  s.test_depth_p99 = quantile(dte, 0.99), s.test_depth_max = quantile(dte, 1.0);
  s.test_speed_p99 = quantile(ste, 0.99), s.test_speed_max = quantile(ste, 1.0);
  const Recording& rec = d.test.rec;
  const ProxyTrack& te = d.test_track;
  std::array<double, 3> sse{}, sse_out{};
  std::size_t any = 0, deep = 0, fast = 0;
  std::array<std::size_t, 3> out{};
  for (std::size_t i = 0; i < rec.size(); ++i) {
    if (!te.contact[i] || !scored[i]) continue;
    ++s.samples;
    const Vec3 n = te.n.size() == rec.size() ? te.n[i] : Vec3::UnitZ();
    const SupportCheck c =
        support_check(m, d.proxy.provenance.params.box_margin, rec.p[i], vte[i], te.q[i], n);
    d.test_support[i] = c;
    const bool outside = c.excess[0] > 0 || c.excess[1] > 0 || c.excess[2] > 0;
    any += outside;
    for (int g = 0; g < 3; ++g) out[g] += c.excess[g] > 0;
    deep += (te.q[i] - rec.p[i]).norm() > s.train_depth_max;
    fast += vte[i].norm() > s.train_speed_max;
    const Vec3 e = d.proxy.replay.forces[i] - rec.f[i];
    for (int a = 0; a < 3; ++a) {
      sse[a] += e[a] * e[a];
      if (outside) sse_out[a] += e[a] * e[a];
    }
  }
  const double n = std::max<double>(1.0, static_cast<double>(s.samples));
  s.outside_any = static_cast<double>(any) / n;
  for (int g = 0; g < 3; ++g) s.outside[g] = static_cast<double>(out[g]) / n;
  for (int a = 0; a < 3; ++a) s.sse_share_outside[a] = sse[a] > 0 ? sse_out[a] / sse[a] : 0.0;
  s.beyond_depth = static_cast<double>(deep) / n;
  s.beyond_speed = static_cast<double>(fast) / n;
  return s;
}

/// The test run as replayed: measured and rendered force, q, normal and contact flags.
void write_replay(const std::string& path, const ForceLabResult& d,
                  const std::vector<char>& scored) {
  const std::vector<std::string> comments{
      "units: t s, p q mm, f (measured) and r (rendered) N; contact = the track's flag, scored = "
      "the lab's contact flag"};
  CsvWriter w(path, {"t",       "px",     "py",  "pz",       "fx",       "fy",       "fz",     "rx",
                     "ry",      "rz",     "qx",  "qy",       "qz",       "nx",       "ny",     "nz",
                     "contact", "scored", "bin", "excess_u", "excess_q", "excess_v", "nearest"},
              comments);
  const Recording& rec = d.test.rec;
  const ProxyTrack& tr = d.test_track;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const Vec3 &p = rec.p[i], &f = rec.f[i], &r = d.proxy.replay.forces[i], &q = tr.q[i];
    const Vec3 n = tr.n.size() == rec.size() ? tr.n[i] : Vec3::UnitZ();
    const SupportCheck& c = d.test_support[i];
    w.row({rec.t[i],
           p.x(),
           p.y(),
           p.z(),
           f.x(),
           f.y(),
           f.z(),
           r.x(),
           r.y(),
           r.z(),
           q.x(),
           q.y(),
           q.z(),
           n.x(),
           n.y(),
           n.z(),
           tr.contact[i] ? 1.0 : 0.0,
           scored[i] ? 1.0 : 0.0,
           static_cast<double>(c.bin),
           c.excess[0],
           c.excess[1],
           c.excess[2],
           c.nearest});
  }
  w.commit();
}

ForceVariant run_variant(const ForceLabResult& d, const std::vector<char>& scored,
                         const ProxyTrack& tr, const ProxyTrack& te, TrainParams p,
                         const char* what, const std::string& label, const Progress& progress) {
  FoawParams foaw;
  foaw.dt_s = median_dt(d.train.rec);
  foaw.max_window = foaw_window_samples(0.016, foaw.dt_s);  // 16 samples at 1 kHz
  const TrainingSet set = make_training_set(d.train.rec, tr, foaw);
  ForceVariant v;
  TrainedForceModel trained =
      train_with_provenance(set, p, foaw, [&](const std::string&, double f, double) {
        if (progress) progress(fmt::format("{} {}", label, what), f, 0);
      });
  v.model = std::move(trained.model);
  v.provenance = std::move(trained.provenance);
  v.provenance.proxy_source = tr.proxy_source;
  v.train_contact = set.size();
  v.replay = timed_replay(v.model, d.test.rec, te);
  // Scored against the measured force on the samples the lab says are in contact.
  v.all = errors_from(d.test.rec, scored, v.replay.forces, -1e300);
  v.sliding = errors_from(d.test.rec, scored, v.replay.forces, d.t_slide);
  return v;
}

/// Proxy tracks of both runs from the chosen source (see the file comment); returns the truth
/// track of the test run (its contact flags are the scoring set).
ProxyTrack make_tracks(ForceLabResult& d, const lab::Scene& scene, const ForceLabOptions& o,
                       const std::string& label) {
  const std::string& name = o.scene;
  ProxyTrack test_truth = truth_track(scene, d.test);
  if (o.proxy == "truth") {
    d.train_track = truth_track(scene, d.train);
    d.test_track = test_truth;
    d.proxy_rms_mm = d.contact_agreement = std::numeric_limits<double>::quiet_NaN();
  } else if (o.proxy == "recording") {
    d.estimate = estimate_recording(d.train.rec, {}, name + " training recording");
    d.train_track = eval::estimated_track(d.train.rec, d.estimate->sys, d.estimate->mesh);
    d.test_track = eval::estimated_track(d.test.rec, d.estimate->sys, d.estimate->mesh);
    compare_with_truth(d, test_truth);
  } else {
    ScenePalpationOptions po;
    po.scene = name;
    po.seed = o.train_seed;
    po.quick = o.quick;
    po.physics = lab::to_string(o.physics);
    if (o.quick) po.points = name == "dome" ? "rings:1,3:20" : "grid:2x2:25";
    po.progress_label = label + " palpation";
    po.progress = o.progress;
    const ScenePalpation pal = palpate_scene(po);
    d.palpation_s = pal.wall_s;
    d.reference_points = pal.points.size();
    d.train_track = palpation_track(pal, d.train.rec);
    d.test_track = palpation_track(pal, d.test.rec);
    compare_with_truth(d, test_truth);
  }
  return test_truth;
}

}  // namespace

ForceLabResult evaluate_forces_on_lab(const ForceLabOptions& o) {
  const std::string& name = o.scene;
  const std::string label = o.progress_label.empty() ? name : o.progress_label;
  if (o.proxy != "estimated" && o.proxy != "truth" && o.proxy != "recording")
    throw Error(fmt::format(
        "eval forces: --proxy: expected estimated, recording or truth, got '{}'", o.proxy));
  if (o.train_operator != "coverage" && o.train_operator != "random")
    throw Error(fmt::format("eval forces: --train-operator: expected coverage or random, got '{}'",
                            o.train_operator));
  const lab::Scene scene = lab::builtin_scene(name);
  Durations dur = durations_for(name);
  if (o.quick) dur = {dur.train_s / 2, dur.test_s / 2};
  auto prog = [&](const char* what) {
    return Progress([&label, &o, what](const std::string&, double f, double) {
      if (o.progress) o.progress(fmt::format("{} {}", label, what), f, 0);
    });
  };
  ForceLabResult d;
  d.name = name;
  d.train =
      o.train_operator == "coverage"
          ? record_coverage(scene, dur.train_s, o.train_seed, o, prog("train recording"))
          : record_random(scene, dur.train_s, o.train_seed, prog("train recording"), o.physics);
  d.test = record_random(scene, dur.test_s, o.test_seed, prog("test recording"), o.physics);
  d.train = downsample_recording(d.train, o.rate_hz, o.train_seed);
  d.test = downsample_recording(d.test, o.rate_hz, o.test_seed);
  if (!o.keep.empty()) {
    std::filesystem::create_directories(o.keep);
    lab::write_lab_recording(o.keep + "/" + name + "-train.csv", d.train);
    lab::write_lab_recording(o.keep + "/" + name + "-test.csv", d.test);
  }
  const ProxyTrack test_truth = make_tracks(d, scene, o, label);
  const std::vector<double>& tt = d.test.rec.t;
  d.t_slide = tt.front() + (tt.back() - tt.front()) * 2.0 / 3.0;
  const TrainParams& p = o.params;
  const std::vector<char>& scored = test_truth.contact;

  d.proxy =
      run_variant(d, scored, d.train_track, d.test_track, p, "train (proxy)", label, o.progress);
  if (d.proxy.all.n == 0)
    throw Error(fmt::format(
        "eval forces: {}: expected samples in contact in the test recording, got none", name));
  if (o.baselines) {
    // Pre-thesis baselines on the same recordings: (p, pdot) only (q = p), and q held at the
    // contact-onset point (u = p - p_c of earlier data-driven methods).
    // The normals stay those of the proxy's tracks (used by local-frame features only).
    const std::string& cs = d.train_track.contact_source;
    auto with_n = [](ProxyTrack t, const ProxyTrack& from) {
      t.n = from.n;
      return t;
    };
    d.no_proxy = run_variant(
        d, scored,
        with_n(position_only_track(d.train.rec, d.train_track.contact, cs), d.train_track),
        with_n(position_only_track(d.test.rec, d.test_track.contact, cs), d.test_track), p,
        "train (no proxy)", label, o.progress);
    d.onset = run_variant(
        d, scored, with_n(entry_proxy_track(d.train.rec, d.train_track.contact, cs), d.train_track),
        with_n(entry_proxy_track(d.test.rec, d.test_track.contact, cs), d.test_track), p,
        "train (onset proxy)", label, o.progress);
  }
  if (!o.baselines) {
    for (ForceVariant* v : {&d.no_proxy, &d.onset}) v->all = v->sliding = no_errors();
  }
  d.support = support_stats(d, scored);
  if (!o.keep.empty()) {
    save_force_model(o.keep + "/" + name + "-model.json", d.proxy.model, d.proxy.provenance);
    write_replay(o.keep + "/" + name + "-test-replay.csv", d, scored);
    if (o.baselines) {
      save_force_model(o.keep + "/" + name + "-model-noproxy.json", d.no_proxy.model,
                       d.no_proxy.provenance);
      save_force_model(o.keep + "/" + name + "-model-onset.json", d.onset.model,
                       d.onset.provenance);
    }
  }
  const std::vector<char> covered =
      coverage(d.train.rec, d.train_track, d.test.rec, d.test_track, 3.0);
  d.covered = errors_from(d.test.rec, scored, d.proxy.replay.forces, -1e300, &covered);
  return d;
}

ForceCoverage training_coverage(const ForceLabResult& d) {
  std::vector<Vec3> q, f;
  for (std::size_t i = 0; i < d.train.rec.size(); ++i)
    if (d.train_track.contact[i]) q.push_back(d.train_track.q[i]), f.push_back(d.train.rec.f[i]);
  const datadriven::CoverageMap map(q, f);
  ForceCoverage c;
  std::size_t n = 0, out = 0;
  for (std::size_t i = 0; i < d.test.rec.size(); ++i)
    if (d.test_track.contact[i])
      ++n, out += map.outside(d.test_track.q[i], d.test.rec.f[i].norm()) ? 1 : 0;
  c.outside = n ? static_cast<double>(out) / static_cast<double>(n) : 0.0;
  c.gaps = datadriven::coverage_gaps(map);
  c.cell_mm = map.params().cell_mm;
  c.map = map;
  return c;
}

void apply_thesis_settings(TrainParams& p, const std::function<bool(const std::string&)>& given) {
  if (!given("--bins")) p.bins = 5;
  if (!given("--tail")) p.linear_tail = false;
  if (!given("--feature-weights")) p.feature_weights = {1.0, 1.0, 1.0};
  if (!given("--ridge")) p.ridge = 0.0;
  if (!given("--box-margin")) p.box_margin = 0.1;
  if (!given("--bin-blend")) p.bin_blend = 0.0;
  if (!given("--tangent-mirror")) p.tangent_mirror = false;
  if (!given("--stiffness-prior")) p.stiffness_prior = false;
  if (!given("--shear-prior")) p.shear_prior = false;
  if (!given("--friction-cone")) p.friction_cone = false;
  if (!given("--sliding-floor")) p.sliding_floor = false;
}

}  // namespace inhap::eval
