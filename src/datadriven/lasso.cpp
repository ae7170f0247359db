// Coordinate descent for the l1 problem with a lambda path, strong-rule screening, working-set
// Gram updates and a duality-gap certificate (see include/inhap/datadriven/lasso.hpp).
#include "inhap/datadriven/lasso.hpp"

#include <fmt/format.h>
#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <thread>

#include "inhap/core/cancel.hpp"
#include "inhap/core/error.hpp"

namespace inhap::datadriven {

const char* to_string(L1Solver s) {
  return s == L1Solver::kSparsa ? "sparsa" : "cd";
}

L1Solver l1_solver_from_string(const std::string& s) {
  if (s == "cd") return L1Solver::kCd;
  if (s == "sparsa") return L1Solver::kSparsa;
  throw Error(fmt::format("expected an l1 solver 'cd' or 'sparsa', got '{}'", s));
}

namespace {

double soft(double u, double t) {
  return u > t ? u - t : (u < -t ? u + t : 0.0);
}

// Runs fn(begin, end) on `threads` contiguous parts of [0, n) (the calling thread takes one).
template <class Fn>
void split_range(Eigen::Index n, int threads, Fn&& fn) {
  const Eigen::Index t = std::clamp<Eigen::Index>(threads, 1, std::max<Eigen::Index>(1, n / 64));
  if (t <= 1) {
    fn(Eigen::Index{0}, n);
    return;
  }
  std::vector<std::thread> pool;
  const CancelFlag* cancel = current_cancel();
  for (Eigen::Index i = 1; i < t; ++i)
    pool.emplace_back([&, i, cancel] {
      const CancelScope scope(cancel);
      fn(n * i / t, n * (i + 1) / t);
    });
  fn(Eigen::Index{0}, n / t);
  for (auto& th : pool) th.join();
}

// g = A^T r over all columns.
void full_gradient(const Eigen::MatrixXd& a, const Eigen::VectorXd& r, Eigen::VectorXd& g,
                   int threads) {
  split_range(a.cols(), threads, [&](Eigen::Index b, Eigen::Index e) {
    g.segment(b, e - b).noalias() = a.middleCols(b, e - b).transpose() * r;
  });
}

// Primal and dual values from ||r||^2, r^T f, ||A^T r||_inf and ||w||_1.
LassoCertificate certificate(double rr, double rf, double gmax, double l1, double lambda) {
  LassoCertificate c;
  rr = std::max(rr, 0.0);
  const double s = gmax > lambda ? lambda / gmax : 1.0;
  c.primal = 0.5 * rr + lambda * l1;
  c.dual = s * rf - 0.5 * s * s * rr;
  c.gap = std::max(c.primal - c.dual, 0.0);
  c.kkt = gmax / lambda;
  return c;
}

// The working set W: its columns, their Gram matrix and the coordinate state.
struct WorkingSet {
  std::vector<int> idx;      // columns of A in W
  Eigen::MatrixXd gram;      // A_W^T A_W (k x k; storage may be larger)
  Eigen::VectorXd w, g, q;   // weights, A_W^T r, A_W^T f (first k entries used)
  std::vector<char> member;  // per column of A: in W
  Eigen::Index size() const { return static_cast<Eigen::Index>(idx.size()); }

  void add(const Eigen::MatrixXd& a, const std::vector<int>& cols, const Eigen::VectorXd& atf,
           const Eigen::VectorXd& grad, int threads) {
    const Eigen::Index k = size(), n = static_cast<Eigen::Index>(cols.size()), kn = k + n;
    if (kn > gram.rows()) {  // grow storage geometrically
      const Eigen::Index cap = std::max<Eigen::Index>(kn, 2 * gram.rows());
      Eigen::MatrixXd g2(cap, cap);
      g2.topLeftCorner(k, k) = gram.topLeftCorner(k, k);
      gram.swap(g2);
      w.conservativeResize(cap);
      g.conservativeResize(cap);
      q.conservativeResize(cap);
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      const int c = cols[static_cast<std::size_t>(i)];
      idx.push_back(c);
      member[static_cast<std::size_t>(c)] = 1;
      w[k + i] = 0;
      g[k + i] = grad[c];
      q[k + i] = atf[c];
    }
    // New Gram columns k..kn-1 (rows 0..kn-1) by dot products, split over the new columns.
    split_range(n, threads, [&](Eigen::Index b, Eigen::Index e) {
      for (Eigen::Index j = k + b; j < k + e; ++j) {
        const auto aj = a.col(idx[static_cast<std::size_t>(j)]);
        for (Eigen::Index l = 0; l <= j; ++l)
          gram(l, j) =
              (l == j) ? aj.squaredNorm() : a.col(idx[static_cast<std::size_t>(l)]).dot(aj);
      }
    });
    for (Eigen::Index j = k; j < kn; ++j)
      for (Eigen::Index l = 0; l < j; ++l) gram(j, l) = gram(l, j);
  }

  // One cyclic sweep at lambda; returns the largest G_jj dw^2 (objective scale of a step).
  double sweep(double lambda) {
    const Eigen::Index k = size();
    double dmax = 0;
    for (Eigen::Index j = 0; j < k; ++j) {
      const double d = gram(j, j);
      if (!(d > 0)) continue;
      const double wj = w[j];
      if (wj == 0.0 && std::fabs(g[j]) <= lambda) continue;  // stays at zero
      const double wn = soft(wj + g[j] / d, lambda / d);
      const double dw = wn - wj;
      if (dw == 0.0) continue;
      w[j] = wn;
      g.head(k).noalias() -= dw * gram.col(j).head(k);
      dmax = std::max(dmax, d * dw * dw);
    }
    return dmax;
  }

  // Certificate of the problem restricted to W (from Gram quantities, no pass over A).
  LassoCertificate restricted(double lambda, double fnorm2) const {
    const Eigen::Index k = size();
    const double wq = w.head(k).dot(q.head(k)), wg = w.head(k).dot(g.head(k));
    const double gmax = k ? g.head(k).lpNorm<Eigen::Infinity>() : 0.0;
    return certificate(fnorm2 - wq - wg, fnorm2 - wq, gmax, w.head(k).lpNorm<1>(), lambda);
  }
};

// Newton steps on the non-zeros with their signs fixed (feature-sign search, Lee et al., NIPS
// 2006): w_S <- G_SS^-1 (q_S - lambda sign(w_S)), stopping at the first coefficient that would
// change sign (it becomes zero and the step repeats without it). Each accepted step lowers the
// objective; on the correct support and signs one step lands on the restricted optimum, which
// cyclic coordinate descent approaches only slowly on the near-collinear r^3 columns.
void newton_polish(WorkingSet& s, double lambda) {
  const Eigen::Index k = s.size();
  std::vector<Eigen::Index> sup;
  Eigen::MatrixXd gss;
  Eigen::VectorXd rhs, wn, d;
  for (Eigen::Index rep = 0; rep <= k; ++rep) {
    sup.clear();
    for (Eigen::Index i = 0; i < k; ++i)
      if (s.w[i] != 0.0) sup.push_back(i);
    const auto ns = static_cast<Eigen::Index>(sup.size());
    if (ns == 0) return;
    gss.resize(ns, ns);
    rhs.resize(ns);
    d.resize(ns);
    for (Eigen::Index a = 0; a < ns; ++a) {
      const Eigen::Index ia = sup[static_cast<std::size_t>(a)];
      for (Eigen::Index b = 0; b < ns; ++b)
        gss(a, b) = s.gram(ia, sup[static_cast<std::size_t>(b)]);
      // Newton step on Q(w) = 1/2 w'Gw - q'w + lambda theta'w: G d = g - lambda theta.
      rhs[a] = s.g[ia] - (s.w[ia] > 0 ? lambda : -lambda);
    }
    d = gss.ldlt().solve(rhs);
    if (!d.allFinite()) return;
    double t = 1.0;
    Eigen::Index cross = -1;
    for (Eigen::Index a = 0; a < ns; ++a) {
      const double wa = s.w[sup[static_cast<std::size_t>(a)]], wb = wa + d[a];
      if ((wa > 0 && wb < 0) || (wa < 0 && wb > 0) || wb == 0.0) {
        const double ta = wa / (wa - wb);
        if (ta < t) {
          t = ta;
          cross = a;
        }
      }
    }
    d *= t;
    // Objective change of the step (exact while no sign changes): -g'd + 1/2 d'Gd + lambda
    // theta'd; reject a step that does not lower it (rounding on a singular G_SS).
    double l1 = 0;
    for (Eigen::Index a = 0; a < ns; ++a)
      l1 += (s.w[sup[static_cast<std::size_t>(a)]] > 0 ? d[a] : -d[a]);
    double gd = 0;
    for (Eigen::Index a = 0; a < ns; ++a) gd += s.g[sup[static_cast<std::size_t>(a)]] * d[a];
    const double dq = -gd + 0.5 * d.dot(gss * d) + lambda * l1;
    if (!(dq < 0)) return;
    for (Eigen::Index a = 0; a < ns; ++a) {
      const Eigen::Index ia = sup[static_cast<std::size_t>(a)];
      s.w[ia] = a == cross ? 0.0 : s.w[ia] + d[a];
      s.g.head(k).noalias() -= d[a] * s.gram.col(ia).head(k);
    }
    if (cross < 0) return;
  }
}

// Coordinate descent with Newton steps on W until its restricted gap <= tol * P or the sweep
// budget is spent.
void solve_restricted(WorkingSet& s, double lambda, double fnorm2, double tol, int& sweeps,
                      int max_sweeps) {
  while (sweeps < max_sweeps) {
    check_cancel();
    double dmax = 0;
    for (int i = 0; i < 10 && sweeps < max_sweeps; ++i) {
      dmax = s.sweep(lambda);
      ++sweeps;
      if (dmax == 0.0) break;
    }
    newton_polish(s, lambda);
    const LassoCertificate c = s.restricted(lambda, fnorm2);
    if (dmax == 0.0 || c.gap <= tol * c.primal) return;
  }
}

struct FullCheck {
  LassoCertificate cert;
  std::vector<int> violators;  // columns off W with |a_j^T r| > lambda, largest first
};

// r = f - A_W w, grad = A^T r; refreshes W's gradient and returns the certificate and the KKT
// violators off W.
FullCheck full_check(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, WorkingSet& s,
                     double lambda, Eigen::VectorXd& r, Eigen::VectorXd& grad, int threads) {
  r = f;
  const Eigen::Index k = s.size();
  for (Eigen::Index i = 0; i < k; ++i)
    if (s.w[i] != 0.0) r.noalias() -= s.w[i] * a.col(s.idx[static_cast<std::size_t>(i)]);
  full_gradient(a, r, grad, threads);
  for (Eigen::Index i = 0; i < k; ++i) s.g[i] = grad[s.idx[static_cast<std::size_t>(i)]];
  FullCheck out;
  for (Eigen::Index j = 0; j < grad.size(); ++j)
    if (!s.member[static_cast<std::size_t>(j)] && std::fabs(grad[j]) > lambda)
      out.violators.push_back(static_cast<int>(j));
  std::stable_sort(out.violators.begin(), out.violators.end(),
                   [&](int p, int q) { return std::fabs(grad[p]) > std::fabs(grad[q]); });
  out.cert = certificate(r.squaredNorm(), r.dot(f), grad.lpNorm<Eigen::Infinity>(),
                         s.w.head(k).lpNorm<1>(), lambda);
  return out;
}

std::vector<int> top_support(const Eigen::VectorXd& x, int k) {
  std::vector<int> idx;
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (x[i] != 0.0) idx.push_back(static_cast<int>(i));
  if (k > 0 && static_cast<int>(idx.size()) > k) {
    std::stable_sort(idx.begin(), idx.end(),
                     [&](int p, int q) { return std::fabs(x[p]) > std::fabs(x[q]); });
    idx.resize(static_cast<std::size_t>(k));
    std::sort(idx.begin(), idx.end());
  }
  return idx;
}

// Strong-rule candidates off W at lambda_k (previous path point lambda_prev, gradient grad).
std::vector<int> strong_set(const WorkingSet& s, const Eigen::VectorXd& grad, double lambda_k,
                            double lambda_prev) {
  std::vector<int> add;
  const double thr = std::max(2 * lambda_k - lambda_prev, 0.0);
  for (Eigen::Index j = 0; j < grad.size(); ++j)
    if (!s.member[static_cast<std::size_t>(j)] && std::fabs(grad[j]) > thr)
      add.push_back(static_cast<int>(j));
  std::stable_sort(add.begin(), add.end(),
                   [&](int p, int q) { return std::fabs(grad[p]) > std::fabs(grad[q]); });
  return add;
}

// The first max(grow_min, grow_factor * non-zeros) of `cols` (sorted by violation, largest first):
// the working set grows geometrically instead of taking every screened column of a dense,
// highly correlated r^3 matrix at once (its Gram matrix is the main cost).
std::vector<int> capped(std::vector<int> cols, const WorkingSet& s, const LassoParams& p) {
  Eigen::Index nz = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i) nz += s.w[i] != 0.0;
  const auto cap = static_cast<std::size_t>(
      std::max<double>(p.grow_min, p.grow_factor * static_cast<double>(nz)));
  if (cols.size() > cap) cols.resize(cap);
  return cols;
}

LassoResult solve_one(const Eigen::MatrixXd& a, const Eigen::VectorXd& f,
                      const Eigen::VectorXd& atf, double lambda, const LassoParams& p) {
  const Eigen::Index n = a.cols();
  const double fnorm2 = f.squaredNorm();
  const double lam_max = atf.lpNorm<Eigen::Infinity>();
  LassoResult res;
  res.w = Eigen::VectorXd::Zero(n);
  res.lambda = lambda;
  if (lam_max <= lambda) {  // w = 0 is optimal
    res.objective = 0.5 * fnorm2;
    res.kkt = lam_max / lambda;
    res.converged = true;
    return res;
  }
  WorkingSet s;
  s.member.assign(static_cast<std::size_t>(n), 0);
  Eigen::VectorXd grad = atf, r(f.size());
  double lam_prev = lam_max;
  int sweeps = 0;
  const double coarse_tol = std::max(p.gap_tolerance, 1e-4);
  for (;;) {
    const double lam = p.path_ratio > 0 ? std::max(lambda, p.path_ratio * lam_prev) : lambda;
    const bool last = lam <= lambda;
    s.add(a, capped(strong_set(s, grad, lam, lam_prev), s, p), atf, grad, p.threads);
    const double tol = last ? p.gap_tolerance : coarse_tol;
    double sub_tol = tol;
    FullCheck chk;
    for (;;) {
      check_cancel();
      solve_restricted(s, lam, fnorm2, sub_tol, sweeps, p.max_sweeps);
      chk = full_check(a, f, s, lam, r, grad, p.threads);
      ++res.passes;
      if (!chk.violators.empty()) {
        s.add(a, capped(std::move(chk.violators), s, p), atf, grad, p.threads);
        continue;
      }
      if (chk.cert.gap <= tol * chk.cert.primal || sweeps >= p.max_sweeps) break;
      sub_tol *= 0.1;  // the restricted gap (Gram arithmetic) was optimistic: tighten
    }
    res.w.setZero();
    for (Eigen::Index i = 0; i < s.size(); ++i) res.w[s.idx[static_cast<std::size_t>(i)]] = s.w[i];
    res.nonzeros = static_cast<int>((res.w.array() != 0.0).count());
    res.lambda = lam;
    res.objective = chk.cert.primal;
    res.gap = chk.cert.gap;
    res.kkt = chk.cert.kkt;
    res.converged = chk.cert.gap <= tol * chk.cert.primal;
    if (p.max_nonzeros > 0 && res.nonzeros >= p.max_nonzeros) {
      res.reached_nonzeros = true;
      break;
    }
    if (last || sweeps >= p.max_sweeps) break;
    lam_prev = lam;
  }
  res.iterations = sweeps;
  if (res.lambda > lambda) res.converged = false;  // stopped on the path, not at the target
  res.support = top_support(res.w, p.max_nonzeros);
  return res;
}

}  // namespace

LassoCertificate lasso_certificate(const Eigen::MatrixXd& a, const Eigen::VectorXd& f,
                                   const Eigen::VectorXd& w, double lambda) {
  if (a.rows() != f.size() || a.cols() != w.size())
    throw Error("lasso certificate: expected A (N x M), f (N) and w (M)");
  const Eigen::VectorXd r = f - a * w;
  const Eigen::VectorXd g = a.transpose() * r;
  return certificate(r.squaredNorm(), r.dot(f), g.lpNorm<Eigen::Infinity>(), w.lpNorm<1>(), lambda);
}

std::vector<LassoResult> lasso_cd_multi(const Eigen::MatrixXd& a, const Eigen::MatrixXd& f,
                                        const std::vector<double>& lambda,
                                        const LassoParams& params) {
  if (f.rows() != a.rows())
    throw Error(fmt::format("lasso: expected {} right-hand-side rows, got {}", a.rows(), f.rows()));
  if (static_cast<Eigen::Index>(lambda.size()) != f.cols())
    throw Error("lasso: expected one lambda per right-hand side");
  for (double l : lambda)
    if (!(l > 0) || !std::isfinite(l))
      throw Error(fmt::format("lasso: expected lambda > 0, got {}", l));
  if (!a.allFinite() || !f.allFinite()) throw Error("lasso: expected finite A and f");
  if (!(params.gap_tolerance > 0) || params.max_sweeps < 1 || !(params.path_ratio >= 0) ||
      params.path_ratio >= 1 || params.grow_min < 1 || !(params.grow_factor >= 0))
    throw Error(
        "lasso: expected gap_tolerance > 0, max_sweeps >= 1, path_ratio in [0, 1), grow_min >= 1 "
        "and grow_factor >= 0");
  Eigen::MatrixXd atf(a.cols(), f.cols());
  for (Eigen::Index c = 0; c < f.cols(); ++c) {
    Eigen::VectorXd col(a.cols());
    full_gradient(a, f.col(c), col, params.threads);
    atf.col(c) = col;
  }
  std::vector<LassoResult> out;
  for (Eigen::Index c = 0; c < f.cols(); ++c)
    out.push_back(solve_one(a, f.col(c), atf.col(c), lambda[static_cast<std::size_t>(c)], params));
  return out;
}

LassoResult lasso_cd(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, double lambda,
                     const LassoParams& params) {
  if (f.size() != a.rows())
    throw Error(fmt::format("lasso: expected {} right-hand-side rows, got {}", a.rows(), f.size()));
  return std::move(lasso_cd_multi(a, f, {lambda}, params).front());
}

std::vector<L1Fit> solve_l1(L1Solver solver, const Eigen::MatrixXd& a, const Eigen::MatrixXd& f,
                            const std::vector<double>& lambda, const SparsaParams& sparsa,
                            const LassoParams& lasso) {
  std::vector<L1Fit> out;
  if (solver == L1Solver::kCd) {
    for (LassoResult& r : lasso_cd_multi(a, f, lambda, lasso)) {
      L1Fit fit;
      fit.relative_gap = r.objective > 0 ? r.gap / r.objective : 0.0;
      fit.iterations = r.iterations;
      fit.nonzeros = r.nonzeros;
      fit.support = std::move(r.support);
      fit.w = std::move(r.w);
      out.push_back(std::move(fit));
    }
    return out;
  }
  std::vector<SparsaResult> sol = sparsa_multi(a, f, lambda, sparsa);
  for (std::size_t c = 0; c < sol.size(); ++c) {
    L1Fit fit;
    const LassoCertificate cert =
        lasso_certificate(a, f.col(static_cast<Eigen::Index>(c)), sol[c].w, lambda[c]);
    fit.relative_gap = cert.primal > 0 ? cert.gap / cert.primal : 0.0;
    fit.iterations = sol[c].iterations;
    fit.nonzeros = static_cast<int>((sol[c].w.array() != 0.0).count());
    fit.support = std::move(sol[c].support);
    fit.w = std::move(sol[c].w);
    out.push_back(std::move(fit));
  }
  return out;
}

}  // namespace inhap::datadriven
