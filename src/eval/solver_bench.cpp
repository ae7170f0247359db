// The l1 solver benchmark (eval/solver_bench.hpp). Units: time s.
#include "inhap/eval/solver_bench.hpp"

#include <fmt/format.h>

#include <chrono>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/lasso.hpp"
#include "inhap/datadriven/sparsa.hpp"

namespace inhap::eval {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

SolverFit certified(const datadriven::L1Problem& pb, const Eigen::VectorXd& w, double optimum) {
  const datadriven::LassoCertificate c = datadriven::lasso_certificate(pb.a, pb.f, w, pb.lambda);
  SolverFit s;
  s.objective = c.primal;
  s.gap = c.gap;
  s.kkt = c.kkt;
  s.excess = (c.primal - optimum) / optimum;
  s.nonzeros = static_cast<long>((w.array() != 0.0).count());
  return s;
}

}  // namespace

datadriven::L1Problem make_l1_problem(const std::string& name, const SolverBenchOptions& o) {
  if (name == "force_model")
    return datadriven::force_model_problem(o.samples, o.fm_centres, o.seed);
  if (name != "r3_cube" && name != "r3_cube_normalised")
    throw Error(fmt::format(
        "unknown l1 problem '{}' (expected r3_cube, r3_cube_normalised or force_model)", name));
  datadriven::L1Problem p = datadriven::r3_cube_problem(o.points, o.centres, o.seed);
  if (name == "r3_cube_normalised") datadriven::normalise_columns(p);
  return p;
}

SolverBenchResult bench_l1_solver(const std::string& name, const SolverBenchOptions& o) {
  const datadriven::L1Problem pb = make_l1_problem(name, o);
  SolverBenchResult r;
  r.name = pb.name;
  r.rows = static_cast<long>(pb.a.rows());
  r.columns = static_cast<long>(pb.a.cols());
  r.lambda = pb.lambda;
  datadriven::LassoParams lp;
  lp.threads = o.threads;
  // The optimum: the same solver driven to a relative gap of 1e-12 (its value is certified to
  // that fraction by the gap).
  datadriven::LassoParams tight = lp;
  tight.gap_tolerance = 1e-12;
  const datadriven::LassoResult best = datadriven::lasso_cd(pb.a, pb.f, pb.lambda, tight);
  r.optimum = best.objective;
  r.optimum_gap = best.gap;
  lp.gap_tolerance = o.gap_tolerance;
  auto t0 = std::chrono::steady_clock::now();
  const datadriven::LassoResult cd = datadriven::lasso_cd(pb.a, pb.f, pb.lambda, lp);
  const double t_cd = seconds_since(t0);
  r.cd = certified(pb, cd.w, best.objective);
  r.cd.iterations = cd.iterations;
  r.cd.time_s = t_cd;
  r.cd_passes = cd.passes;
  datadriven::SparsaParams sp;
  sp.lambda = pb.lambda;
  sp.max_nonzeros = static_cast<int>(pb.a.cols());  // no early stop on the count
  sp.stop = datadriven::SparsaStop::kObjective;
  sp.tolerance = o.sparsa_tolerance;
  sp.max_iterations = 1000000;
  t0 = std::chrono::steady_clock::now();
  const datadriven::SparsaResult base = datadriven::sparsa(pb.a, pb.f, sp);
  const double t_base = seconds_since(t0);
  r.sparsa = certified(pb, base.w, best.objective);
  r.sparsa.iterations = base.iterations;
  r.sparsa.time_s = t_base;
  r.speedup = t_base / t_cd;
  return r;
}

nlohmann::ordered_json solver_bench_json(const SolverBenchResult& r) {
  nlohmann::ordered_json j;
  j["name"] = r.name;
  j["rows"] = r.rows;
  j["columns"] = r.columns;
  j["lambda"] = r.lambda;
  j["optimum"] = r.optimum;
  j["optimum_gap"] = r.optimum_gap;
  j["objective"] = r.cd.objective;
  j["gap"] = r.cd.gap;
  j["relative_gap"] = r.cd.gap / r.cd.objective;
  j["excess"] = r.cd.excess;
  j["kkt"] = r.cd.kkt;
  j["nonzeros"] = r.cd.nonzeros;
  j["sweeps"] = r.cd.iterations;
  j["passes"] = r.cd_passes;
  j["time_s"] = r.cd.time_s;
  j["baseline"] = {{"solver", "sparsa, relative objective change 1e-5"},
                   {"objective", r.sparsa.objective},
                   {"gap", r.sparsa.gap},
                   {"excess", r.sparsa.excess},
                   {"kkt", r.sparsa.kkt},
                   {"nonzeros", r.sparsa.nonzeros},
                   {"iterations", r.sparsa.iterations},
                   {"time_s", r.sparsa.time_s}};
  j["speedup"] = r.speedup;
  return j;
}

std::string solver_bench_line(const SolverBenchResult& r) {
  return fmt::format(
      "{} ({} x {}): optimum {:.6g}; cd {:.6g} (+{:.2e}, gap {:.2e}, {} non-zeros, KKT {:.4f}) in "
      "{:.3f} s; sparsa {:.6g} (+{:.2e}, {} non-zeros, KKT {:.2f}) in {:.3f} s; {:.1f}x",
      r.name, r.rows, r.columns, r.optimum, r.cd.objective, r.cd.excess, r.cd.gap, r.cd.nonzeros,
      r.cd.kkt, r.cd.time_s, r.sparsa.objective, r.sparsa.excess, r.sparsa.nonzeros, r.sparsa.kkt,
      r.sparsa.time_s, r.speedup);
}

nlohmann::ordered_json solver_bench_report(const SolverBenchOptions& o,
                                           const std::vector<SolverBenchResult>& results) {
  nlohmann::ordered_json out;
  out["units"] = {{"time", "s"}};
  out["seed"] = o.seed;
  out["gap_tolerance"] = o.gap_tolerance;
  out["threads"] = o.threads;
  out["problems"] = nlohmann::ordered_json::array();
  for (const SolverBenchResult& r : results) out["problems"].push_back(solver_bench_json(r));
  return out;
}

}  // namespace inhap::eval
