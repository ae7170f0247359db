// The l1 solver of the force model (issue 19): coordinate descent to a relative duality gap of
// 1e-6 (lasso_cd, 2 threads) against SpaRSA stopping at a relative objective change of 1e-5, on
// the seeded problems of l1_problems.hpp: r3_cube (20,000 x 1,000), the same with unit-norm
// columns, and one force-model bin (synthetic recording, 300 centres). Counters: objective,
// relative gap, non-zeros. Units: time s.
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "inhap/datadriven/l1_problems.hpp"
#include "inhap/datadriven/lasso.hpp"

namespace {

using namespace inhap::datadriven;

const L1Problem& problem(int which) {
  static std::map<int, L1Problem> cache;
  auto it = cache.find(which);
  if (it != cache.end()) return it->second;
  L1Problem p = which == 2 ? force_model_problem() : r3_cube_problem();
  if (which == 1) normalise_columns(p);
  return cache.emplace(which, std::move(p)).first->second;
}

void report(benchmark::State& state, const L1Problem& p, const Eigen::VectorXd& w) {
  const LassoCertificate c = lasso_certificate(p.a, p.f, w, p.lambda);
  state.counters["objective"] = c.primal;
  state.counters["rel_gap"] = c.gap / c.primal;
  state.counters["kkt"] = c.kkt;
  state.counters["nonzeros"] = static_cast<double>((w.array() != 0.0).count());
  state.SetLabel(p.name);
}

void BM_Cd(benchmark::State& state) {
  const L1Problem& p = problem(static_cast<int>(state.range(0)));
  LassoParams lp;
  lp.threads = 2;
  LassoResult r;
  for (auto _ : state) {
    r = lasso_cd(p.a, p.f, p.lambda, lp);
    benchmark::DoNotOptimize(r.w.data());
  }
  report(state, p, r.w);
}
BENCHMARK(BM_Cd)->DenseRange(0, 2)->Unit(benchmark::kSecond)->Iterations(3);

void BM_Sparsa(benchmark::State& state) {
  const L1Problem& p = problem(static_cast<int>(state.range(0)));
  SparsaParams sp;
  sp.lambda = p.lambda;
  sp.max_nonzeros = static_cast<int>(p.a.cols());
  sp.stop = SparsaStop::kObjective;
  sp.tolerance = 1e-5;
  sp.max_iterations = 1000000;
  SparsaResult r;
  for (auto _ : state) {
    r = sparsa(p.a, p.f, sp);
    benchmark::DoNotOptimize(r.w.data());
  }
  report(state, p, r.w);
}
BENCHMARK(BM_Sparsa)->DenseRange(0, 2)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
