// inhap model bench-solver: the l1 solver of the force model (coordinate descent with a
// duality-gap certificate) against the thesis' SpaRSA on seeded problems (the benchmark:
// eval/solver_bench.hpp).
// Units: time s; A and f dimensionless (r^3 of unit-cube or standardised coordinates), the force
// model's target in N.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/solver_bench.hpp"

namespace inhap::cli {
namespace {

using nlohmann::ordered_json;

struct BenchSolverOptions : eval::SolverBenchOptions {
  std::string json;
  std::vector<std::string> problems{"r3_cube", "r3_cube_normalised", "force_model"};
};

void run_bench_solver(const BenchSolverOptions& o) {
  std::vector<eval::SolverBenchResult> results;
  for (const std::string& name : o.problems) {
    results.push_back(eval::bench_l1_solver(name, o));
    fmt::print("{}\n", eval::solver_bench_line(results.back()));
  }
  if (!o.json.empty())
    write_file_atomic(o.json, eval::solver_bench_report(o, results).dump(1) + "\n");
}

void register_bench_solver(CLI::App& app) {
  CLI::App* model = subcommand_group(app, "model", "Data-driven force model");
  auto o = std::make_shared<BenchSolverOptions>();
  auto* c = model->add_subcommand(
      "bench-solver",
      "l1 solver benchmark on seeded problems: coordinate descent to a certified optimum against "
      "SpaRSA stopping at a relative objective change of 1e-5 (time in s)");
  c->add_option("--json", o->json,
                "Write {\"problems\": [{name, optimum, objective, gap, time_s, baseline: "
                "{objective, time_s}}]} here");
  c->add_option("--problems", o->problems, "Problems: r3_cube, r3_cube_normalised, force_model")
      ->capture_default_str()
      ->check(CLI::IsMember({"r3_cube", "r3_cube_normalised", "force_model"}));
  c->add_option("--points", o->points, "r3_cube: points N in the unit cube")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000000));
  c->add_option("--centres", o->centres, "r3_cube: centres M")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  c->add_option("--samples", o->samples, "force_model: synthetic 1 kHz samples")
      ->capture_default_str()
      ->check(CLI::Range(1000, 10000000));
  c->add_option("--seed", o->seed, "Seed of the problems")->capture_default_str();
  c->add_option("--gap-tolerance", o->gap_tolerance, "cd: relative duality gap that ends a fit")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  c->add_option("--threads", o->threads, "cd: threads of the passes A^T r")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  c->callback([o] { run_bench_solver(*o); });
}

}  // namespace

INHAP_COMMAND(41, "model bench-solver", register_bench_solver);

}  // namespace inhap::cli
