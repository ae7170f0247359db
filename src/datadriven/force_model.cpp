// Clustered r^3 RBF force model: training and evaluation (see force_model.hpp).
#include "inhap/datadriven/force_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <numeric>
#include <thread>
#include <utility>

#include <time.h>

#include "force_model_priors.hpp"
#include "inhap/core/cancel.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/kmeans.hpp"

namespace inhap::datadriven {

using detail::fit_fallback;
using detail::fit_friction_cone;
using detail::fit_priors;
using detail::fit_sliding_mu;

const char* to_string(FeatureSet f) {
  if (f == FeatureSet::kLocalFrame) return "local";
  return f == FeatureSet::kDisplacementProxyVelocity ? "ue_q_v" : "p_v_q";
}

FeatureSet feature_set_from_string(const std::string& s) {
  if (s == "ue_q_v") return FeatureSet::kDisplacementProxyVelocity;
  if (s == "p_v_q") return FeatureSet::kPositionVelocityProxy;
  if (s == "local") return FeatureSet::kLocalFrame;
  throw Error(fmt::format("expected feature set 'ue_q_v' or 'p_v_q', got '{}'", s));
}

const char* to_string(Design d) {
  return d == Design::kThesis ? "thesis" : "regression";
}

Design design_from_string(const std::string& s) {
  if (s == "thesis") return Design::kThesis;
  if (s == "regression") return Design::kRegression;
  throw Error(fmt::format("expected design 'thesis' or 'regression', got '{}'", s));
}

void TrainParams::validate() const {
  if (bins < 1 || bins > 100) throw Error(fmt::format("expected 1..100 bins, got {}", bins));
  if (centers < 1) throw Error(fmt::format("expected at least 1 centre per bin, got {}", centers));
  if (nonzeros < 0 || nonzeros > centers)
    throw Error(
        fmt::format("expected 0..{} wanted non-zeros (<= centres), got {}", centers, nonzeros));
  if (!(lambda_ratio > 0 && lambda_ratio < 1))
    throw Error(fmt::format("expected a lambda ratio in (0, 1), got {}", lambda_ratio));
  if (!(box_margin >= 0))
    throw Error(fmt::format("expected a box margin >= 0, got {}", box_margin));
  if (!(bin_blend >= 0) || !std::isfinite(bin_blend))
    throw Error(fmt::format("expected a bin blend half-width >= 0 mm, got {}", bin_blend));
  for (double w : feature_weights)
    if (!(w > 0) || !std::isfinite(w))
      throw Error(fmt::format("expected feature weights > 0, got {}", w));
  if (!(sparsa_tolerance > 0) || !(cg_tolerance > 0) || !(gap_tolerance > 0))
    throw Error("expected positive tolerances");
  if (!(modeling_range_n > 0) || !std::isfinite(modeling_range_n))
    throw Error(fmt::format("expected a modeling range > 0 N, got {}", modeling_range_n));
  if (!(kmeans_min_moved >= 0 && kmeans_min_moved < 1))
    throw Error(
        fmt::format("expected a k-means moved fraction in [0, 1), got {}", kmeans_min_moved));
  if (!(ridge >= 0)) throw Error(fmt::format("expected a ridge >= 0, got {}", ridge));
  if (friction_cone && features != FeatureSet::kLocalFrame)
    throw Error("expected local-frame features with the friction-cone guard (it needs the normal)");
  if (sliding_floor && features != FeatureSet::kLocalFrame)
    throw Error("expected local-frame features with the sliding floor (it needs the normal)");
  if (stiffness_prior && features != FeatureSet::kLocalFrame)
    throw Error("expected local-frame features with the stiffness prior (it needs the normal)");
  if (stiffness_prior) stiffness.validate();
  if (shear_prior && features != FeatureSet::kLocalFrame)
    throw Error("expected local-frame features with the shear prior (it needs the normal)");
  if (shear_prior) shear.validate();
  if (fallback && features != FeatureSet::kLocalFrame)
    throw Error("expected local-frame features with the fallback law (it needs the normal)");
  if (!(fallback_near_mm >= 0) || !(fallback_far_mm > fallback_near_mm) ||
      !std::isfinite(fallback_far_mm))
    throw Error(fmt::format("expected 0 <= fallback near < far distance (mm), got {} and {}",
                            fallback_near_mm, fallback_far_mm));
  if (!valid_normal_blend(fallback_normal_near_mm, fallback_normal_far_mm))
    throw Error(fmt::format(
        "expected 0 <= fallback normal near < far distance (mm; --fallback-normal-near, "
        "--fallback-normal-far; 0 and 0: off), got {} and {}",
        fallback_normal_near_mm, fallback_normal_far_mm));
}

namespace {

// CPU time of the calling thread, s (stage timers: unlike wall time, not inflated by load).
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// CPU seconds per training stage, summed over threads.
class StageLog {
 public:
  void add(const std::string& name, double s) {
    std::lock_guard lock(mutex_);
    for (auto& e : stages_)
      if (e.first == name) {
        e.second += s;
        return;
      }
    stages_.emplace_back(name, s);
  }
  // Adds the CPU time since the last lap (or construction of `lap`) to `name`.
  void lap(const std::string& name, double& since) {
    const double now = thread_cpu_s();
    add(name, now - since);
    since = now;
  }
  std::vector<std::pair<std::string, double>> take() { return std::move(stages_); }

 private:
  std::mutex mutex_;
  std::vector<std::pair<std::string, double>> stages_;
};

struct BinResult {
  BinModel model;
  std::array<int, 3> support{}, sparsa_it{}, cg_it{}, nonzeros{};
  std::array<double, 3> lambda{}, gap{};
  int selected = 0;
};

std::uint64_t bin_seed(std::uint64_t seed, int bin) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ull * static_cast<std::uint64_t>(bin + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  return z ^ (z >> 27);
}

// The feature groups that are positions in world axes (mm): p and q of (p, pdot, q), q of the
// others.
bool position_group(FeatureSet s, int g) {
  return s == FeatureSet::kPositionVelocityProxy ? (g == 0 || g == 2) : g == 1;
}

void normalise(Eigen::MatrixXd& x, BinModel& bm, const TrainParams& prm) {
  const Eigen::Index n = x.rows();
  const double margin = prm.box_margin;
  std::array<double, kFeatureDim> mean{}, sd{};
  for (int d = 0; d < kFeatureDim; ++d) {
    const auto ud = static_cast<std::size_t>(d);
    mean[ud] = x.col(d).mean();
    sd[ud] = std::sqrt((x.col(d).array() - mean[ud]).square().sum() / static_cast<double>(n));
  }
  // A position is standardised with one scale for its three coordinates (their RMS spread):
  // a millimetre is as far along one axis as along another, and a coordinate the data hardly
  // moves along (the height of a flat object's proxy, spread 0.1 mm) is not stretched into the
  // distance that matters most.
  if (prm.isotropic_positions)
    for (int g = 0; g < 3; ++g) {
      if (!position_group(prm.features, g)) continue;
      const auto u = static_cast<std::size_t>(3 * g);
      const double rms =
          std::sqrt((sd[u] * sd[u] + sd[u + 1] * sd[u + 1] + sd[u + 2] * sd[u + 2]) / 3);
      sd[u] = sd[u + 1] = sd[u + 2] = rms;
    }
  for (int d = 0; d < kFeatureDim; ++d) {
    const auto ud = static_cast<std::size_t>(d);
    bm.offset[ud] = mean[ud];
    bm.scale[ud] = (sd[ud] > 1e-12 ? sd[ud] : 1.0) / prm.feature_weights[ud / 3];
    x.col(d) = (x.col(d).array() - mean[ud]) / bm.scale[ud];
    const double lo = x.col(d).minCoeff(), hi = x.col(d).maxCoeff();
    bm.box_min[ud] = lo - margin * (hi - lo);
    bm.box_max[ud] = hi + margin * (hi - lo);
  }
}

// The l1 problem of one bin: A (rows x candidates), its right-hand sides, the tail basis of the
// rows and the feature vector of every candidate centre.
struct Problem {
  Eigen::MatrixXd a, f, p;
  std::vector<int> candidate;  // candidate column j -> sample index
};

Problem build_problem(const Eigen::MatrixXd& x, const Eigen::MatrixXd& f,
                      const std::vector<int>& selected, const TrainParams& prm) {
  const Eigen::Index m = static_cast<Eigen::Index>(selected.size());
  Eigen::MatrixXd sel(m, kFeatureDim), fsel(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) {
    sel.row(i) = x.row(selected[static_cast<std::size_t>(i)]);
    fsel.row(i) = f.row(selected[static_cast<std::size_t>(i)]);
  }
  Problem pb;
  if (prm.design == Design::kThesis) {  // rows: selected samples; columns: every sample
    pb.a = rbf_matrix(sel, x);
    pb.f = std::move(fsel);
    if (prm.linear_tail) pb.p = tail_matrix(sel);
    pb.candidate.resize(static_cast<std::size_t>(x.rows()));
    std::iota(pb.candidate.begin(), pb.candidate.end(), 0);
  } else {  // rows: every sample; columns: selected samples
    pb.a = rbf_matrix(x, sel);
    pb.f = f;
    if (prm.linear_tail) pb.p = tail_matrix(x);
    pb.candidate = selected;
  }
  return pb;
}

// A bin with the range, normalisation and box of `g` and the expansions `axes`.
BinModel with_axes(const BinModel& g, std::array<RbfExpansion, 3> axes) {
  BinModel b(std::move(axes));
  b.key_min = g.key_min, b.key_max = g.key_max, b.samples = g.samples;
  b.offset = g.offset, b.scale = g.scale, b.box_min = g.box_min, b.box_max = g.box_max;
  return b;
}

// Least-squares refit of each axis on the support SpaRSA chose (and the tail), warm-started at
// its weights; fills the per-axis counts of `out`.
std::array<RbfExpansion, 3> debias(const Problem& pb, const Eigen::MatrixXd& x,
                                   const std::vector<L1Fit>& sol, const Eigen::VectorXd& colscale,
                                   const Eigen::MatrixXd& tail_coef, const TrainParams& prm,
                                   BinResult& out) {
  const Eigen::Index rows = pb.a.rows(), t = prm.linear_tail ? kFeatureDim + 1 : 0;
  std::array<RbfExpansion, 3> axes;
  for (int c = 0; c < 3; ++c) {
    const auto uc = static_cast<std::size_t>(c);
    const std::vector<int>& sup = sol[uc].support;
    const Eigen::Index k = static_cast<Eigen::Index>(sup.size());
    Eigen::MatrixXd b(rows, k + t);
    Eigen::VectorXd x0(k + t);
    for (Eigen::Index j = 0; j < k; ++j) {
      const int col = sup[static_cast<std::size_t>(j)];
      b.col(j) = pb.a.col(col);
      x0[j] = sol[uc].w[col] / colscale[col];
    }
    if (t) {
      b.rightCols(t) = pb.p;
      x0.tail(t) = tail_coef.col(c);
    }
    const CgResult cg = cg_least_squares(b, pb.f.col(c), x0, prm.cg_tolerance, 0, prm.ridge);
    RbfExpansion& e = axes[uc];
    e.centres.resize(k, kFeatureDim);
    for (Eigen::Index j = 0; j < k; ++j)
      e.centres.row(j) =
          x.row(pb.candidate[static_cast<std::size_t>(sup[static_cast<std::size_t>(j)])]);
    e.weights = cg.x.head(k);
    if (t) e.tail = cg.x.tail(t);
    out.support[uc] = static_cast<int>(k);
    out.sparsa_it[uc] = sol[uc].iterations;
    out.nonzeros[uc] = sol[uc].nonzeros;
    out.gap[uc] = sol[uc].relative_gap;
    out.cg_it[uc] = cg.iterations;
  }
  return axes;
}

BinResult train_bin(Eigen::MatrixXd x, const Eigen::MatrixXd& f, const TrainParams& prm, int bin,
                    StageLog& log) {
  double clock = thread_cpu_s();
  BinResult out;
  BinModel& bm = out.model;
  bm.samples = static_cast<std::size_t>(x.rows());
  normalise(x, bm, prm);
  const KMeansResult km = kmeans(x, {.k = prm.centers,
                                     .max_iterations = prm.kmeans_iterations,
                                     .seed = bin_seed(prm.seed, bin),
                                     .min_moved = prm.kmeans_min_moved});
  out.selected = static_cast<int>(km.selected.size());
  log.lap("k-means", clock);
  Problem pb = build_problem(x, f, km.selected, prm);
  Eigen::MatrixXd tail_coef, target = pb.f;
  if (prm.linear_tail) {  // unpenalised tail: fitted first, SpaRSA sees the residual
    tail_coef = pb.p.colPivHouseholderQr().solve(pb.f);
    target -= pb.p * tail_coef;
  }
  SparsaParams sp;
  sp.max_nonzeros = prm.nonzeros > 0 ? prm.nonzeros : prm.centers;
  sp.stop = prm.sparsa_stop;
  sp.tolerance = prm.sparsa_tolerance;
  sp.max_iterations = prm.sparsa_iterations;
  // Optional column scaling (a diagonal preconditioner; the l1 penalty then treats near and far
  // centres alike). Weights are mapped back before debiasing.
  Eigen::VectorXd colscale = Eigen::VectorXd::Ones(pb.a.cols());
  if (prm.normalize_columns) {
    colscale = pb.a.colwise().norm().transpose();
    for (Eigen::Index j = 0; j < colscale.size(); ++j)
      if (!(colscale[j] > 0)) colscale[j] = 1;
    pb.a *= colscale.cwiseInverse().asDiagonal();
  }
  std::vector<double> lambda(3);
  for (int c = 0; c < 3; ++c) {
    const double g = (pb.a.transpose() * target.col(c)).lpNorm<Eigen::Infinity>();
    lambda[static_cast<std::size_t>(c)] = g > 0 ? prm.lambda_ratio * g : 1e-300;
    out.lambda[static_cast<std::size_t>(c)] = lambda[static_cast<std::size_t>(c)];
  }
  LassoParams lp;
  lp.max_nonzeros = sp.max_nonzeros;
  lp.gap_tolerance = prm.gap_tolerance;
  log.lap("matrix", clock);
  const std::vector<L1Fit> sol = solve_l1(prm.solver, pb.a, target, lambda, sp, lp);
  log.lap("l1", clock);
  if (prm.normalize_columns) pb.a *= colscale.asDiagonal();
  std::array<RbfExpansion, 3> axes = debias(pb, x, sol, colscale, tail_coef, prm, out);
  log.lap("debias", clock);
  bm = with_axes(bm, std::move(axes));
  return out;
}

void check_training_set(const TrainingSet& data, const TrainParams& params) {
  const std::size_t n = data.size();
  if (data.v.size() != n || data.q.size() != n || data.f.size() != n ||
      (!data.n.empty() && data.n.size() != n))
    throw Error("force model training: expected p, v, q, f (and n) of equal length");
  if (params.features == FeatureSet::kLocalFrame && data.n.size() != n)
    throw Error("force model training: the local-frame features need the normal at q (n)");
  if (n < 2 * static_cast<std::size_t>(params.bins))
    throw Error(fmt::format("force model training: expected at least {} in-contact samples, got {}",
                            2 * params.bins, n));
  for (std::size_t i = 0; i < n; ++i)
    if (!data.p[i].allFinite() || !data.v[i].allFinite() || !data.q[i].allFinite() ||
        !data.f[i].allFinite())
      throw Error(fmt::format("force model training: sample {} is not finite", i));
}

// Runs task(0..n-1) on `threads` threads (each task writes only its own outputs, so results do
// not depend on the thread count); the first exception is rethrown after all have finished.
void parallel_for(int n, int threads, const std::function<void(int)>& task) {
  std::atomic<int> next{0};
  std::mutex mutex;
  std::exception_ptr error;
  const CancelFlag* cancel = current_cancel();
  auto worker = [&] {
    const CancelScope scope(cancel);  // the caller's flag in every worker
    for (int i = next++; i < n; i = next++) {
      try {
        check_cancel();
        task(i);
      } catch (...) {
        std::lock_guard lock(mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < std::clamp(threads, 1, n); ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// Features and target forces of the samples order[s0..s1) (one bin): forces minus the priors'
// force, in the local frame when the features are; mirrored about the normal when asked.
std::pair<Eigen::MatrixXd, Eigen::MatrixXd> bin_samples(const TrainingSet& data,
                                                        const TrainParams& params,
                                                        const std::vector<std::size_t>& order,
                                                        std::size_t s0, std::size_t s1,
                                                        const std::vector<Vec3>& base) {
  const auto m = static_cast<Eigen::Index>(s1 - s0);
  const bool local = params.features == FeatureSet::kLocalFrame;
  const bool mirror = local && params.tangent_mirror;
  Eigen::MatrixXd x(mirror ? 2 * m : m, kFeatureDim), f(mirror ? 2 * m : m, 3);
  double row[kFeatureDim];
  for (Eigen::Index i = 0; i < m; ++i) {
    const std::size_t k = order[s0 + static_cast<std::size_t>(i)];
    const SurfaceFrame fr = data.n.empty() ? SurfaceFrame{} : surface_frame(data.n[k]);
    make_features(params.features, data.p[k], data.v[k], data.q[k], fr, row);
    for (int d = 0; d < kFeatureDim; ++d) x(i, d) = row[d];
    f.row(i) = (local ? fr.to_local(data.f[k]) : data.f[k]).transpose();
    f.row(i) -= base[k].transpose();  // 0 unless a prior is on (local frame: z = normal)
  }
  if (mirror) {  // the same samples turned by 180 deg about the normal: tangential parts negated
    x.bottomRows(m) = x.topRows(m);
    f.bottomRows(m) = f.topRows(m);
    for (int d : {0, 1, 6, 7}) x.col(d).tail(m) *= -1.0;
    for (int a : {0, 1}) f.col(a).tail(m) *= -1.0;
  }
  return {std::move(x), std::move(f)};
}

// The training proper on the samples kept (train_force_model counts and filters first).
TrainedForceModel train_kept(const TrainingSet& data, const TrainParams& params,
                             const FoawParams& foaw, const Progress& progress,
                             std::chrono::steady_clock::time_point t0) {
  check_training_set(data, params);
  const std::size_t n = data.size();
  TrainedForceModel trained;
  ForceModel& model = trained.model;
  TrainStats& stats = trained.provenance.stats;
  trained.provenance.params = params;
  model.features = params.features;
  model.foaw = foaw;
  model.bin_blend = params.bin_blend;

  // Equal-count bins by ||q - p|| (stable order for ties).
  std::vector<double> key(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = (data.q[i] - data.p[i]).norm();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  const auto nb = static_cast<std::size_t>(params.bins);
  std::vector<std::size_t> start(nb + 1);
  for (std::size_t b = 0; b <= nb; ++b) start[b] = n * b / nb;
  for (std::size_t b = 1; b < nb; ++b)
    model.edges.push_back(0.5 * (key[order[start[b] - 1]] + key[order[start[b]]]));

  // Local stiffness and shear priors (subtracted from the force the RBFs learn; base[i] = their
  // force at sample i, local frame) and friction cone.
  StageLog log;
  double clock = thread_cpu_s();
  std::vector<Vec3> base(n, Vec3::Zero());
  if (params.features == FeatureSet::kLocalFrame) {
    if (params.stiffness_prior || params.shear_prior) fit_priors(data, params, model, base);
    if (params.friction_cone) model.friction_cone = fit_friction_cone(data);
    if (params.sliding_floor) model.sliding_mu = fit_sliding_mu(data);
    if (params.fallback) model.fallback = fit_fallback(data, params, model.prior);
  }
  if (params.envelope) model.envelope = make_force_envelope(data.q, data.p, data.f);
  log.lap("priors", clock);

  std::vector<BinResult> results(nb);
  std::mutex progress_mutex;
  int finished = 0;
  const int threads =
      params.threads > 0 ? params.threads : static_cast<int>(std::thread::hardware_concurrency());
  parallel_for(params.bins, threads, [&](int bi) {
    const auto b = static_cast<std::size_t>(bi);
    const std::size_t s0 = start[b], s1 = start[b + 1];
    auto [x, f] = bin_samples(data, params, order, s0, s1, base);
    results[b] = train_bin(std::move(x), f, params, bi, log);
    results[b].model.key_min = key[order[s0]];
    results[b].model.key_max = key[order[s1 - 1]];
    std::lock_guard lock(progress_mutex);
    ++finished;
    if (progress)
      progress(fmt::format("bin {} done", bi), static_cast<double>(finished) / params.bins, 0.0);
  });

  for (auto& r : results) {
    stats.support.push_back(r.support);
    stats.sparsa_iterations.push_back(r.sparsa_it);
    stats.gap.push_back(r.gap);
    stats.nonzeros.push_back(r.nonzeros);
    stats.cg_iterations.push_back(r.cg_it);
    stats.lambda.push_back(r.lambda);
    stats.selected_rows.push_back(r.selected);
    model.bins.push_back(std::move(r.model));
  }
  stats.stage_cpu_s = log.take();
  stats.samples = n;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return trained;
}

}  // namespace

TrainedForceModel train_with_provenance(const TrainingSet& data, const TrainParams& params,
                                        const FoawParams& foaw, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  params.validate();
  foaw.validate();
  // Forces above the modeling range: counted, then kept or left out; never clipped.
  std::vector<char> above(data.f.size(), 0);
  double max_force = 0;
  for (std::size_t i = 0; i < data.f.size(); ++i) {
    const double mag = data.f[i].norm();
    above[i] = mag > params.modeling_range_n;
    if (std::isfinite(mag)) max_force = std::max(max_force, mag);
  }
  const auto n_above = static_cast<std::size_t>(std::count(above.begin(), above.end(), 1));
  const std::size_t n = data.size();
  const bool consistent = data.v.size() == n && data.q.size() == n && data.f.size() == n &&
                          (data.n.empty() || data.n.size() == n);
  TrainedForceModel trained;
  if (params.above_range == AboveRange::kExclude && n_above > 0 && consistent) {
    TrainingSet kept;
    const bool normals = !data.n.empty(), slid = data.slip.size() == n;
    for (std::size_t i = 0; i < n; ++i) {
      if (above[i]) continue;
      if (slid) kept.slip.push_back(data.slip[i]);
      kept.p.push_back(data.p[i]);
      kept.v.push_back(data.v[i]);
      kept.q.push_back(data.q[i]);
      kept.f.push_back(data.f[i]);
      if (normals) kept.n.push_back(data.n[i]);
    }
    trained = train_kept(kept, params, foaw, progress, t0);
    trained.provenance.stats.excluded = n_above;
  } else {
    trained = train_kept(data, params, foaw, progress, t0);
  }
  TrainStats& stats = trained.provenance.stats;
  stats.offered = data.size();
  stats.above_range = n_above;
  stats.max_force_n = max_force;
  return trained;
}

ForceModel train_force_model(const TrainingSet& data, const TrainParams& params,
                             const FoawParams& foaw, const Progress& progress) {
  return train_with_provenance(data, params, foaw, progress).model;
}

}  // namespace inhap::datadriven
