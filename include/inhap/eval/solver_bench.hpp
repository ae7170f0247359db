// The l1 solver benchmark behind `inhap model bench-solver`: the force model's solver
// (coordinate descent with a duality-gap certificate) against the thesis' SpaRSA on the seeded
// problems of datadriven/l1_problems.hpp. Units: time s; A and f dimensionless (r^3 of unit-cube
// or standardised coordinates), the force model's target in N.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/datadriven/l1_problems.hpp"

namespace inhap::eval {

struct SolverBenchOptions {
  int points = 20000, centres = 1000;     ///< r3_cube: points N in the unit cube, centres M
  int samples = 65000, fm_centres = 300;  ///< force_model: synthetic 1 kHz samples, centres
  std::uint64_t seed = 1;                 ///< seed of the problems
  double gap_tolerance = 1e-6;            ///< cd: relative duality gap that ends a fit
  double sparsa_tolerance = 1e-5;         ///< SpaRSA: relative objective change that ends it
  int threads = 2;                        ///< cd: threads of the passes A^T r
};

/// One solver's fit, certified explicitly (datadriven/lasso.hpp, lasso_certificate).
struct SolverFit {
  double objective = 0, gap = 0, kkt = 0;
  double excess = 0;  ///< (objective - optimum) / optimum
  long nonzeros = 0;
  int iterations = 0;  ///< cd: coordinate sweeps; SpaRSA: accepted iterations
  double time_s = 0;
};

struct SolverBenchResult {
  std::string name;
  long rows = 0, columns = 0;
  double lambda = 0;
  double optimum = 0, optimum_gap = 0;  ///< cd driven to a relative gap of 1e-12, its gap
  SolverFit cd, sparsa;
  int cd_passes = 0;   ///< cd: full passes A^T r
  double speedup = 0;  ///< sparsa.time_s / cd.time_s
};

/// The problem `name`: "r3_cube", "r3_cube_normalised" or "force_model". Throws inhap::Error
/// for another name.
datadriven::L1Problem make_l1_problem(const std::string& name, const SolverBenchOptions& options);

/// Solves problem `name` to its certified optimum, then times cd and SpaRSA on it.
SolverBenchResult bench_l1_solver(const std::string& name, const SolverBenchOptions& options);

/// One problem's result as JSON: size, lambda, optimum, cd's objective, gap, excess, KKT,
/// non-zeros, sweeps, passes and time, SpaRSA's as "baseline", the speed-up.
nlohmann::ordered_json solver_bench_json(const SolverBenchResult& r);
/// The whole `model bench-solver --json` document: units, seed, gap tolerance, threads and one
/// entry per problem (solver_bench_json).
nlohmann::ordered_json solver_bench_report(const SolverBenchOptions& o,
                                           const std::vector<SolverBenchResult>& results);
/// The line `model bench-solver` prints for it.
std::string solver_bench_line(const SolverBenchResult& r);

}  // namespace inhap::eval
