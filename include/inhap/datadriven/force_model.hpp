// The clustered data-driven force model of thesis sec. 4.4: f = g(p, pdot, q), one polyharmonic
// (r^3) RBF expansion per force axis and per bin of ||q - p||.
//
// Units: p, q in mm, pdot in mm/s, forces in N. Features are normalised per dimension (per bin)
// before distances are taken, so centres and the clamping box are dimensionless.
//
// Training (train_force_model):
//   1. bins: the samples are split into `bins` groups of equal count by the elastic
//      displacement magnitude ||q - p|| (thesis 4.4.3);
//   2. per bin: feature vectors x (9-D, see FeatureSet), normalised to zero mean and unit
//      standard deviation per dimension;
//   3. k-means (k-means++ seeding) with M clusters; the recorded sample nearest each centroid is
//      a selected row ("random selection" of Sianov and Harders);
//   4. A~ (M x N_bin): A~(i, j) = psi(||x_sel_i - x_j||), psi(r) = r^3, every sample of the bin
//      a candidate centre; f~ = forces of the selected rows, one problem per force axis;
//   5. the l1 fit with lambda = lambda_ratio ||A~^T f~||_inf: SpaRSA (default), which stops at
//      the wanted number of non-zeros or on slow progress (sparsa.hpp), or coordinate descent to
//      the optimum with a duality-gap certificate (lasso.hpp; non-zeros beyond the wanted
//      number are dropped, smallest first);
//   6. CG debiasing on the support (tolerance 1e-9).
// Bins are trained in parallel (std::thread); results do not depend on the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "inhap/core/progress.hpp"
#include "inhap/core/types.hpp"
#include "inhap/datadriven/envelope.hpp"
#include "inhap/datadriven/fallback.hpp"
#include "inhap/datadriven/foaw.hpp"
#include "inhap/datadriven/lasso.hpp"
#include "inhap/datadriven/rbf.hpp"
#include "inhap/datadriven/sparsa.hpp"
#include "inhap/datadriven/stiffness_prior.hpp"
#include "inhap/geometry/surface_frame.hpp"

namespace inhap::datadriven {

inline constexpr int kFeatureDim = 9;
/// Normal force below which the friction-cone guard uses this value instead, N.
inline constexpr double kConeFloorN = 0.3;

/// Which 9-D vector the RBFs see.
enum class FeatureSet {
  kDisplacementProxyVelocity,  ///< (q - p, q, pdot): "displacement, proxy and velocities" (default)
  kPositionVelocityProxy,      ///< (p, pdot, q) as written in eq. 4.1
  /// (R (q - p), q, R pdot) with R = the surface frame at q (rows t0, t1, n: tangents and
  /// outward normal); the force is learnt in that frame too and turned back to world axes when
  /// rendered. Needs the normal at q (the proxy estimator's frame, or a shape mesh).
  kLocalFrame,
};
const char* to_string(FeatureSet f);
/// Parses "ue_q_v" or "p_v_q"; throws inhap::Error otherwise.
FeatureSet feature_set_from_string(const std::string& s);

/// The library's surface frame (inhap/geometry/surface_frame.hpp): local z along the outward
/// normal; the force model uses the world-x rule surface_frame(n) for t0.
using inhap::surface_frame;
using inhap::SurfaceFrame;

/// Fills x[0..8] with the raw (unnormalised) features; `frame` is used by kLocalFrame only.
inline void make_features(FeatureSet set, const Vec3& p, const Vec3& v, const Vec3& q,
                          const SurfaceFrame& frame, double* x) {
  const bool local = set == FeatureSet::kLocalFrame;
  const bool ue = local || set == FeatureSet::kDisplacementProxyVelocity;
  const Vec3 a = local ? frame.to_local(q - p) : ue ? Vec3(q - p) : p;
  const Vec3 b = ue ? q : v;
  const Vec3 c = local ? frame.to_local(v) : ue ? v : q;
  for (int i = 0; i < 3; ++i) {
    x[i] = a[i];
    x[3 + i] = b[i];
    x[6 + i] = c[i];
  }
}
inline void make_features(FeatureSet set, const Vec3& p, const Vec3& v, const Vec3& q, double* x) {
  make_features(set, p, v, q, SurfaceFrame{}, x);
}

/// A proxy that moved by more than this since the previous tick in contact is sliding, mm (the
/// proxy estimator leaves q exactly where it was while the probe sticks).
inline constexpr double kSlidingStepMm = 1e-6;

/// In-contact training samples (all vectors the same length).
struct TrainingSet {
  std::vector<Vec3> p;  ///< probe centre, mm
  std::vector<Vec3> v;  ///< probe velocity (FOAW), mm/s
  std::vector<Vec3> q;  ///< proxy, mm
  std::vector<Vec3> f;  ///< measured force, N
  std::vector<Vec3> n;  ///< outward surface normal at q (empty: +z; used by kLocalFrame)
  /// Slip speed: how fast the proxy moved since the previous in-contact sample, mm/s; 0 where it
  /// held (moved by kSlidingStepMm or less: sticking); empty: not known.
  std::vector<double> slip;
  std::size_t size() const { return p.size(); }
};

/// Shape of the l1 problem of a bin (both use the M k-means-selected samples).
enum class Design {
  kThesis,      ///< A~ is M x N_bin: rows = selected samples, columns = every sample (sec. 4.4.2)
  kRegression,  ///< A~ is N_bin x M: rows = every sample, columns = selected samples
};
const char* to_string(Design d);
/// Parses "thesis" or "regression"; throws inhap::Error otherwise.
Design design_from_string(const std::string& s);

/// What training does with samples whose force magnitude exceeds the modeling range.
enum class AboveRange {
  kKeep,     ///< train on them as measured (counted and reported)
  kExclude,  ///< leave them out (counted and reported)
};
const char* to_string(AboveRange a);
/// Parses "keep" or "exclude"; throws inhap::Error otherwise.
AboveRange above_range_from_string(const std::string& s);

struct TrainParams {
  int bins = 2;                 ///< bins by ||q - p||, equal counts (thesis: 5; 2 measured best)
  int centers = 300;            ///< M: k-means clusters = selected rows per bin
  int nonzeros = 0;             ///< wanted non-zeros per axis (0 = M)
  double lambda_ratio = 0.001;  ///< lambda = ratio * ||A~^T f~||_inf
  std::uint64_t seed = 1;
  bool linear_tail = true;  ///< linear polynomial tail on every expansion (thesis: none)
  FeatureSet features = FeatureSet::kDisplacementProxyVelocity;
  Design design = Design::kRegression;  ///< measured better than kThesis (docs/force-model.md)
  bool normalize_columns = true;        ///< solve the l1 problem on unit-norm columns of A~
  /// l1 solver. SpaRSA is the default of these bare parameters: at lambda_ratio 0.001 the
  /// certified optimum (kCd) keeps few centres and underfits the plain synthetic law without
  /// priors (docs/force-model.md). The preset "best" (what `model train` runs) uses kCd.
  L1Solver solver = L1Solver::kSparsa;
  double gap_tolerance = 1e-6;  ///< cd: relative duality gap that ends the fit
  SparsaStop sparsa_stop = SparsaStop::kObjective;
  double sparsa_tolerance = 1e-4;  ///< of sparsa_stop (relative objective change)
  int sparsa_iterations = 5000;    ///< SpaRSA iterations at most (all stages)
  double cg_tolerance = 1e-9;      ///< CG debiasing tolerance (thesis)
  /// Relative Tikhonov term of the debiasing (0 = plain least squares, which CG cannot bring
  /// to 1e-9 on the numerically singular r^3 supports).
  double ridge = 1e-8;
  int kmeans_iterations = 100;
  /// k-means stops when an iteration moves at most this fraction of a bin's samples (0: when
  /// none moves; KMeansParams::min_moved).
  double kmeans_min_moved = 1e-3;
  /// Weights of the three 3-D feature groups after standardisation (in FeatureSet order):
  /// distances see (x_d - mean_d) / sd_d * weight_group(d).
  std::array<double, 3> feature_weights{1.0, 3.0, 0.5};
  /// Positions (q; p and q of p_v_q) standardised with one scale for their three coordinates
  /// (the RMS of their spreads) instead of one per coordinate. Off: per coordinate (files
  /// written before this option).
  bool isotropic_positions = true;
  double box_margin = 0.5;  ///< clamping box = training range +- margin * range (per dim)
  /// Half-width (mm of ||q - p||) of the band around each bin edge in which the two bins'
  /// forces are blended (smoothstep weights), so the rendered force has no jump at the edge.
  /// 0 = hard switch (thesis).
  double bin_blend = 0.0;
  /// Local-frame features only: also train on every sample turned by 180 deg about the normal
  /// (tangential displacement, velocity and force negated), i.e. assume the material responds
  /// alike in every tangential direction; a push straight along the normal then gets no
  /// tangential force from its neighbours' shear. Doubles the training rows.
  bool tangent_mirror = false;
  /// Local-frame features only: fit a local stiffness prior f_n = k(q) d^alpha (d = n . (q - p),
  /// see stiffness_prior.hpp) to all training samples first; the RBFs learn the rest and the prior
  /// is added back when rendering, so the stiffness seen at shallow depth carries to deep pushes.
  bool stiffness_prior = false;
  StiffnessPriorParams stiffness;  ///< settings of the prior's fit
  /// Local-frame features only: fit a local shear prior f_t = -k_t(q) |u_t|^(beta - 1) u_t
  /// (u_t = tangential part of p - q, mm; k_t in N/mm^beta; the same map fit as the stiffness
  /// prior, on |f_t| against |u_t| of the samples whose tangential force opposes u_t) first;
  /// the RBFs learn the rest. The tangential spring then extrapolates along the law the data
  /// show instead of the RBFs' tail, and the shear stiffness seen at a spot is kept there.
  bool shear_prior = false;
  /// Settings of the shear prior's fit (min_depth = the smallest |u_t| fitted, mm; min_force =
  /// the smallest |f_t|, N).
  StiffnessPriorParams shear{.min_depth = 0.2, .min_force = 0.1};
  /// Local-frame features only: keep the rendered force inside the friction cone seen in
  /// training, |f_t| <= c max(f_n, 0.3 N) with c the 99.5 % quantile of |f_t| / f_n over the
  /// training samples pressed with f_n >= 1 N (a guard against the RBFs' extrapolation of
  /// tangential force).
  bool friction_cone = false;
  /// Local-frame features only: while the proxy slides (it moved since the previous tick in
  /// contact, TrainingSet::slip > 0) render at least the Coulomb force |f_t| >= mu_s f_n (and
  /// at most the friction cone's c f_n) along the proxy's tangential lag q - p, with mu_s the
  /// 10 % quantile of |f_t| / f_n over the training samples whose proxy slid, pressed with
  /// f_n >= 1 N (at least 20 of them; else no floor). The RBFs regress a sliding sample's
  /// tangential force towards its neighbours' (which stick and pull less); a proxy on its yield
  /// surface says the probe is at the friction limit.
  bool sliding_floor = false;
  /// Local-frame features only: outside the training support blend towards the recording's own
  /// depth-force law (fallback.hpp): the model as trained within fallback_near_mm of a training
  /// proxy, the monotone law f_n(d) (times the stiffness prior's local k(q) when there is one,
  /// plus the shear prior) beyond fallback_far_mm, mm.
  bool fallback = false;
  double fallback_near_mm = 6.0;
  double fallback_far_mm = 12.0;
  /// With the fallback, between fallback_normal_near_mm and fallback_normal_far_mm of the nearest
  /// training proxy the normal force blends towards the model's on the proxy's normal line at the
  /// same depth (no tangential displacement; fallback.hpp), mm; 0 and 0: off.
  double fallback_normal_near_mm = 2.0;
  double fallback_normal_far_mm = 4.0;
  /// Bound every rendered force by the training data's force envelope near the state
  /// (envelope.hpp): |f| <= (1 + 0.25) max |f| seen within one 8 mm cell of q and one 0.5 mm step
  /// of ||q - p|| deeper, + 0.25 N. No force the data never showed.
  bool envelope = true;
  /// Modeling range, N: samples with |f| above it are counted (TrainStats::above_range) and kept
  /// or excluded as `above_range` says. Training never clips a target.
  double modeling_range_n = 5.0;
  AboveRange above_range = AboveRange::kKeep;
  int threads = 0;        ///< worker threads (0 = hardware concurrency)
  void validate() const;  ///< throws inhap::Error on out-of-range values
};

/// One bin of ||q - p|| (mm) with its normalisation and one expansion per force axis. Complete
/// when constructed: the constructor builds the evaluation table of its expansions, which are
/// read-only afterwards (a new set of expansions is a new BinModel).
struct BinModel {
  double key_min = 0, key_max = 0;           ///< range of ||q - p|| among its training samples, mm
  std::array<double, kFeatureDim> offset{};  ///< normalisation: z = (x - offset) / scale
  ///< (scale = standard deviation / feature weight)
  std::array<double, kFeatureDim> scale{};
  std::array<double, kFeatureDim> box_min{}, box_max{};  ///< clamping box of z
  std::size_t samples = 0;                               ///< training samples in the bin

  BinModel() = default;  ///< no expansions (zero force)
  /// Centres in z, weights in N; builds the union table (none when an axis has not 9 coordinates
  /// per centre and one weight per centre: such a bin renders zero and fails validate_model).
  explicit BinModel(std::array<RbfExpansion, 3> axes);
  const std::array<RbfExpansion, 3>& axes() const { return axes_; }
  /// Derived (not saved): the union of the three axes' centres with a weight column per axis
  /// (zero where an axis does not use a centre), so that each distance is computed once per
  /// step. K_union x D column-major and K_union x 3.
  const Eigen::MatrixXd& union_centres() const { return union_centres_; }
  const Eigen::MatrixXd& union_weights() const { return union_weights_; }

 private:
  std::array<RbfExpansion, 3> axes_;
  Eigen::MatrixXd union_centres_, union_weights_;
};

/// Training diagnostics (not needed to render; part of the provenance).
struct TrainStats {
  double seconds = 0;
  std::size_t samples = 0;
  std::vector<std::array<int, 3>> support;            ///< per bin and axis: non-zeros kept
  std::vector<std::array<int, 3>> sparsa_iterations;  ///< l1 solver iterations (cd: sweeps)
  /// Per bin and axis: relative duality gap (P - D) / P of the l1 fit at its lambda (cd and
  /// SpaRSA alike; <= TrainParams::gap_tolerance certifies the optimum) and its non-zeros
  /// before any were dropped. Empty in model files written before they were kept.
  std::vector<std::array<double, 3>> gap;
  std::vector<std::array<int, 3>> nonzeros;
  std::vector<std::array<int, 3>> cg_iterations;
  std::vector<std::array<double, 3>> lambda;
  std::vector<int> selected_rows;  ///< per bin
  std::size_t offered = 0;         ///< samples given to training (before any exclusion)
  std::size_t above_range = 0;     ///< of them, |f| > TrainParams::modeling_range_n
  std::size_t excluded = 0;        ///< of them, left out (AboveRange::kExclude)
  double max_force_n = 0;          ///< largest |f| offered, N
  /// CPU seconds per training stage, summed over the threads that ran it (priors, kmeans,
  /// matrix, l1, debias, ...), in the order first seen; with wall-clock `seconds` it says where
  /// the time goes on a loaded machine. Not saved.
  std::vector<std::pair<std::string, double>> stage_cpu_s;
};

/// The run-time model: the constants the servo step reads, nothing else (how it was made is the
/// ForceModelProvenance beside it). Complete when its parts are: the bins build their tables when
/// constructed, the fallback's distance grid is built by whoever makes it (training, the file
/// reader).
struct ForceModel {
  FeatureSet features = FeatureSet::kDisplacementProxyVelocity;
  std::vector<double> edges;  ///< bins-1 increasing thresholds on ||q - p||, mm
  std::vector<BinModel> bins;
  FoawParams foaw;             ///< velocity filter used for training; the renderer uses the same
  double force_limit_n = 6.2;  ///< output clamp, N (device limit)
  double bin_blend = 0.0;      ///< mm; see TrainParams::bin_blend
  StiffnessPrior prior;  ///< local stiffness prior (empty: none), added along n to the RBF force
  StiffnessPrior shear;  ///< local shear prior (empty: none), added along -u_t to the RBF force
  double friction_cone = 0;  ///< c of TrainParams::friction_cone (0: no guard)
  double sliding_mu = 0;     ///< mu_s of TrainParams::sliding_floor (0: no floor)
  Fallback fallback;         ///< outside the training support (empty: none)
  ForceEnvelope envelope;    ///< cap on |f| from the training data (empty: none)

  /// Bin index for a displacement magnitude (mm).
  int bin_of(double key) const;
};

/// How a model was made (not needed to render): kept beside the model in its file.
struct ForceModelProvenance {
  TrainParams params;  ///< as trained
  TrainStats stats;
  std::string sys_path, mesh_path;       ///< references (may be empty)
  std::string sys_digest, mesh_digest;   ///< FNV-1a 64 of the referenced files (hex)
  std::string proxy_source = "columns";  ///< where q came from when training
  /// The training recording (model eval fits the baselines on it) and the units its t and p
  /// columns were in ("s" | "ms", "mm" | "m").
  std::string recording_path, recording_digest, time_unit = "s", length_unit = "mm";
  /// What was estimated from the recording itself ("surface", "normals", "proxy", "friction").
  std::vector<std::string> estimated;
};

/// A model with its provenance: what training returns and a model file holds.
struct TrainedForceModel {
  ForceModel model;
  ForceModelProvenance provenance;
};

/// Names of the training presets: "best" (the documented pipeline: local-frame features, tangent
/// mirror, stiffness and shear priors, friction cone, feature weights 1 5 0.5, bins blended over
/// +-1 mm; needs the normal at q), "world" (world-frame (q - p, q, pdot) features with the
/// TrainParams defaults; for recordings without normals or a shape mesh) and "thesis" (the
/// thesis' settings of sec. 4.4: world frame, 5 bins, no tail, equal weights, M x N design, plain
/// least squares, 10 % clamping margin, hard bin switch).
std::vector<std::string> preset_names();
/// TrainParams of a preset; throws inhap::Error naming the presets when unknown.
TrainParams preset_params(const std::string& name);

/// Counts the samples with |f| > modeling_range_n (a diagnostic; training does it too).
std::size_t count_above(const std::vector<Vec3>& f, double modeling_range_n);

/// Trains the model; `progress` is called (from worker threads, serialised) with "bin K done",
/// the fraction done, eta 0. The provenance holds `params`, the statistics and proxy_source
/// "columns" (the caller fills in the references). Throws inhap::Error when there are too few
/// samples (fewer than 2 per bin), non-finite values or bad parameters.
TrainedForceModel train_with_provenance(const TrainingSet& data, const TrainParams& params,
                                        const FoawParams& foaw = {}, const Progress& progress = {});
/// The same, the model alone.
ForceModel train_force_model(const TrainingSet& data, const TrainParams& params,
                             const FoawParams& foaw = {}, const Progress& progress = {});

/// Model force for one input, N: bin by ||q - p||, normalise, clamp to the bin's box, evaluate
/// the three expansions, clamp the magnitude to force_limit_n. Non-finite input gives zero.
/// Servo-safe: no allocation, no exceptions.
Vec3 model_force(const ForceModel& model, const Vec3& p, const Vec3& v, const Vec3& q);
/// The same with the outward surface normal at q (used by FeatureSet::kLocalFrame) and the
/// proxy's slip speed (mm/s; > 0 while it slides turns on TrainParams::sliding_floor).
Vec3 model_force(const ForceModel& model, const Vec3& p, const Vec3& v, const Vec3& q,
                 const Vec3& normal, double slip_mm_s = 0);

/// Where an input lies relative to the training data of its bin (a diagnostic, not for the
/// servo loop).
struct SupportCheck {
  int bin = -1;  ///< bin of ||q - p|| (-1: non-finite input or no bins)
  /// Per feature group (q - p, q, pdot): the largest excess of a normalised coordinate beyond
  /// the bin's training range [min, max], as a fraction of that range (0 = inside).
  std::array<double, 3> excess{};
  double nearest = 0;  ///< distance from the normalised input to the bin's nearest centre (z units)
};
/// `box_margin`: TrainParams::box_margin of the training (the bins' boxes are the training range
/// widened by it).
SupportCheck support_check(const ForceModel& model, double box_margin, const Vec3& p, const Vec3& v,
                           const Vec3& q, const Vec3& normal);

/// Checks a model's internal consistency (sizes, finiteness, ordering). Throws inhap::Error
/// naming what is wrong, prefixed with `where`.
void validate_model(const ForceModel& model, const std::string& where);

}  // namespace inhap::datadriven
