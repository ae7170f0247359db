// SpaRSA with Barzilai-Borwein steps, safeguarded acceptance and continuation, plus CGLS
// debiasing (see include/inhap/datadriven/sparsa.hpp).
#include "inhap/datadriven/sparsa.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>

#include "inhap/core/cancel.hpp"
#include "inhap/core/error.hpp"

namespace inhap::datadriven {

double lasso_objective(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, const Eigen::VectorXd& w,
                       double lambda) {
  return lambda * w.lpNorm<1>() + 0.5 * (a * w - f).squaredNorm();
}

namespace {

struct Column {
  Eigen::VectorXd x, r;  // iterate (N) and residual A x - f (M)
  double alpha = 1, lam = 0, target = 0;
  std::deque<double> hist;
  bool done = false;
  bool reinit_alpha = false;  // new continuation stage: restart alpha from a Rayleigh quotient
  SparsaResult res;
};

double sparsa_soft(double u, double t) {
  return u > t ? u - t : (u < -t ? u + t : 0.0);
}

int count_nonzeros(const Eigen::VectorXd& x) {
  return static_cast<int>((x.array() != 0.0).count());
}

std::vector<int> sparsa_top_support(const Eigen::VectorXd& x, int k) {
  std::vector<int> idx;
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (x[i] != 0.0) idx.push_back(static_cast<int>(i));
  if (static_cast<int>(idx.size()) > k) {
    std::stable_sort(idx.begin(), idx.end(),
                     [&](int p, int q) { return std::fabs(x[p]) > std::fabs(x[q]); });
    idx.resize(static_cast<std::size_t>(k));
    std::sort(idx.begin(), idx.end());
  }
  return idx;
}

double objective(const Column& c, double lam) {
  return 0.5 * c.r.squaredNorm() + lam * c.x.lpNorm<1>();
}

void push_hist(Column& c, double phi, int memory) {
  c.hist.push_back(phi);
  while (static_cast<int>(c.hist.size()) > memory + 1) c.hist.pop_front();
}

// Rayleigh quotient ||A g||^2 / ||g||^2 (a safe curvature estimate for the first step).
double rayleigh(const Eigen::MatrixXd& a, const Eigen::VectorXd& g, const SparsaParams& p) {
  const double gg = g.squaredNorm();
  return gg > 0 ? std::clamp((a * g).squaredNorm() / gg, p.alpha_min, p.alpha_max) : 1.0;
}

// One accepted SpaRSA iteration of column c given its gradient g; advances the continuation
// stage and sets c.done when it stops.
void iterate(const Eigen::MatrixXd& a, Column& c, const Eigen::VectorXd& g, const SparsaParams& p,
             Eigen::VectorXd& xn, Eigen::VectorXd& adx, std::vector<int>& nz) {
  const Eigen::Index n = a.cols();
  double dx2 = 0, phi = 0;
  if (c.reinit_alpha) {
    c.alpha = rayleigh(a, g, p);
    c.reinit_alpha = false;
  }
  for (;;) {
    const double inv = 1.0 / c.alpha, thr = c.lam * inv;
    nz.clear();
    dx2 = 0;
    for (Eigen::Index j = 0; j < n; ++j) {
      xn[j] = sparsa_soft(c.x[j] - g[j] * inv, thr);
      const double d = xn[j] - c.x[j];
      if (d != 0.0) {
        nz.push_back(static_cast<int>(j));
        dx2 += d * d;
      }
    }
    adx.setZero();
    for (int j : nz) adx.noalias() += (xn[j] - c.x[j]) * a.col(j);
    phi = 0.5 * (c.r + adx).squaredNorm() + c.lam * xn.lpNorm<1>();
    const double ref = *std::max_element(c.hist.begin(), c.hist.end());
    if (nz.empty() || phi <= ref - 0.5 * p.sigma * c.alpha * dx2 || c.alpha >= p.alpha_max) break;
    c.alpha = std::min(p.alpha_max, c.alpha * p.eta);
    ++c.res.rejections;
  }
  ++c.res.iterations;
  const double adx2 = adx.squaredNorm();
  const double phi_prev = c.hist.back();
  c.x.swap(xn);
  c.r += adx;
  push_hist(c, phi, p.memory);
  if (dx2 > 0) c.alpha = std::clamp(adx2 / dx2, p.alpha_min, p.alpha_max);
  const double change = p.stop == SparsaStop::kObjective
                            ? std::fabs(phi_prev - phi) / std::max(phi, 1e-300)
                            : std::sqrt(dx2) / std::max(c.x.norm(), 1e-300);
  const bool stage_done = nz.empty() || change <= p.tolerance;
  if (stage_done) {
    // The wanted number of non-zeros is checked on stage solutions only: transient iterates of
    // a BB method can be dense for a few steps.
    if (count_nonzeros(c.x) >= p.max_nonzeros) {
      c.res.reached_nonzeros = true;
      c.done = true;
    } else if (c.lam <= c.target) {
      c.res.converged = true;
      c.done = true;
    } else {  // next continuation stage
      c.lam = std::max(c.target, p.continuation_ratio * c.lam);
      ++c.res.stages;
      c.reinit_alpha = true;
      c.hist.clear();
      push_hist(c, objective(c, c.lam), p.memory);
    }
  }
  if (c.res.iterations >= p.max_iterations) c.done = true;
}

}  // namespace

std::vector<SparsaResult> sparsa_multi(const Eigen::MatrixXd& a, const Eigen::MatrixXd& f,
                                       const std::vector<double>& lambda, const SparsaParams& p) {
  const Eigen::Index m = a.rows(), n = a.cols(), nc = f.cols();
  if (f.rows() != m)
    throw Error(fmt::format("SpaRSA: expected {} right-hand-side rows, got {}", m, f.rows()));
  if (static_cast<Eigen::Index>(lambda.size()) != nc)
    throw Error("SpaRSA: expected one lambda per right-hand side");
  for (double l : lambda)
    if (!(l > 0) || !std::isfinite(l))
      throw Error(fmt::format("SpaRSA: expected lambda > 0, got {}", l));
  if (p.max_nonzeros < 1) throw Error("SpaRSA: expected max_nonzeros >= 1");
  std::vector<Column> cols(static_cast<std::size_t>(nc));
  const Eigen::MatrixXd g0 = -(a.transpose() * f);  // gradient at w = 0
  for (Eigen::Index k = 0; k < nc; ++k) {
    Column& c = cols[static_cast<std::size_t>(k)];
    c.x = Eigen::VectorXd::Zero(n);
    c.r = -f.col(k);
    c.target = lambda[static_cast<std::size_t>(k)];
    const double gmax = g0.col(k).lpNorm<Eigen::Infinity>();
    c.lam = p.continuation ? std::max(c.target, p.continuation_start * gmax) : c.target;
    c.res.stages = 1;
    c.reinit_alpha = true;  // alpha from the first gradient
    push_hist(c, objective(c, c.lam), p.memory);
    if (gmax <= c.target) {  // w = 0 is optimal
      c.done = true;
      c.res.converged = true;
    }
  }
  Eigen::VectorXd xn(n), adx(m);
  std::vector<int> nz, active;
  Eigen::MatrixXd r, g;
  for (;;) {
    check_cancel();
    active.clear();
    for (Eigen::Index k = 0; k < nc; ++k)
      if (!cols[static_cast<std::size_t>(k)].done) active.push_back(static_cast<int>(k));
    if (active.empty()) break;
    r.resize(m, static_cast<Eigen::Index>(active.size()));
    for (std::size_t i = 0; i < active.size(); ++i)
      r.col(static_cast<Eigen::Index>(i)) = cols[static_cast<std::size_t>(active[i])].r;
    g.noalias() = a.transpose() * r;  // one pass over A for every active problem
    for (std::size_t i = 0; i < active.size(); ++i)
      iterate(a, cols[static_cast<std::size_t>(active[i])], g.col(static_cast<Eigen::Index>(i)), p,
              xn, adx, nz);
  }
  std::vector<SparsaResult> out;
  for (auto& c : cols) {
    c.res.w = std::move(c.x);
    c.res.support = sparsa_top_support(c.res.w, p.max_nonzeros);
    c.res.objective = 0.5 * c.r.squaredNorm() + c.target * c.res.w.lpNorm<1>();
    out.push_back(std::move(c.res));
  }
  return out;
}

SparsaResult sparsa(const Eigen::MatrixXd& a, const Eigen::VectorXd& f, const SparsaParams& p) {
  if (f.size() != a.rows())
    throw Error(
        fmt::format("SpaRSA: expected {} right-hand-side rows, got {}", a.rows(), f.size()));
  return std::move(sparsa_multi(a, f, {p.lambda}, p).front());
}

CgResult cg_least_squares(const Eigen::MatrixXd& b, const Eigen::VectorXd& f,
                          const Eigen::VectorXd& x0, double tolerance, int max_iterations,
                          double ridge) {
  if (f.size() != b.rows()) throw Error("CG least squares: expected one right-hand side per row");
  if (x0.size() != 0 && x0.size() != b.cols())
    throw Error("CG least squares: expected a start vector with one entry per column");
  if (max_iterations <= 0) max_iterations = 50 * static_cast<int>(b.cols()) + 100;
  CgResult res;
  res.x = x0.size() ? x0 : Eigen::VectorXd::Zero(b.cols());
  // Normal equations G x = c with G = B^T B formed once (B has at most a few hundred columns,
  // so each CG iteration costs a small dense product instead of two passes over B).
  Eigen::MatrixXd g = b.transpose() * b;
  if (ridge > 0) g.diagonal() *= 1.0 + ridge;
  const Eigen::VectorXd c = b.transpose() * f;
  const double cnorm = c.norm();
  if (cnorm == 0) {
    res.x.setZero();
    res.converged = true;
    return res;
  }
  // Jacobi preconditioner: r^3 columns differ in norm by orders of magnitude.
  Eigen::VectorXd dinv = g.diagonal();
  for (Eigen::Index j = 0; j < dinv.size(); ++j) dinv[j] = dinv[j] > 0 ? 1.0 / dinv[j] : 1.0;
  Eigen::VectorXd r = c - g * res.x;
  Eigen::VectorXd z = dinv.cwiseProduct(r);
  Eigen::VectorXd dir = z, q(b.cols());
  double rz = r.dot(z);
  while (res.iterations < max_iterations) {
    if (r.norm() <= tolerance * cnorm) break;
    q.noalias() = g * dir;
    const double dq = dir.dot(q);
    if (!(dq > 0)) break;
    const double step = rz / dq;
    res.x += step * dir;
    r -= step * q;
    z = dinv.cwiseProduct(r);
    const double rz_new = r.dot(z);
    dir = z + (rz_new / rz) * dir;
    rz = rz_new;
    ++res.iterations;
  }
  res.relative_residual = (c - g * res.x).norm() / cnorm;  // true, not recursive, residual
  res.converged = res.relative_residual <= tolerance;
  return res;
}

}  // namespace inhap::datadriven
