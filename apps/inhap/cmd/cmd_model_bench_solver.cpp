// inhap model bench-solver: the l1 solver of the force model (coordinate descent with a
// duality-gap certificate) against the thesis' SpaRSA on seeded problems (issue 19).
// Units: time s; A and f dimensionless (r^3 of unit-cube or standardised coordinates), the force
// model's target in N.
#include <fmt/format.h>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/datadriven/l1_problems.hpp"
#include "inhap/datadriven/lasso.hpp"

namespace inhap::cli {
namespace {

using namespace inhap::dd;
using nlohmann::ordered_json;

struct BenchSolverOptions {
  std::string json;
  std::vector<std::string> problems{"r3_cube", "r3_cube_normalised", "force_model"};
  int points = 20000, centres = 1000, samples = 65000, fm_centres = 300;
  std::uint64_t seed = 1;
  double gap_tolerance = 1e-6;
  double sparsa_tolerance = 1e-5;
  int threads = 2;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

L1Problem make_problem(const std::string& name, const BenchSolverOptions& o) {
  if (name == "force_model") return force_model_problem(o.samples, o.fm_centres, o.seed);
  L1Problem p = r3_cube_problem(o.points, o.centres, o.seed);
  if (name == "r3_cube_normalised") normalise_columns(p);
  return p;
}

ordered_json bench_problem(const std::string& name, const BenchSolverOptions& o) {
  const L1Problem pb = make_problem(name, o);
  LassoParams lp;
  lp.threads = o.threads;
  // The optimum: the same solver driven to a relative gap of 1e-12 (its value is certified to
  // that fraction by the gap).
  LassoParams tight = lp;
  tight.gap_tolerance = 1e-12;
  const LassoResult best = lasso_cd(pb.a, pb.f, pb.lambda, tight);
  lp.gap_tolerance = o.gap_tolerance;
  auto t0 = std::chrono::steady_clock::now();
  const LassoResult cd = lasso_cd(pb.a, pb.f, pb.lambda, lp);
  const double t_cd = seconds_since(t0);
  const LassoCertificate cert = lasso_certificate(pb.a, pb.f, cd.w, pb.lambda);
  SparsaParams sp;
  sp.lambda = pb.lambda;
  sp.max_nonzeros = static_cast<int>(pb.a.cols());  // no early stop on the count
  sp.stop = SparsaStop::kObjective;
  sp.tolerance = o.sparsa_tolerance;
  sp.max_iterations = 1000000;
  t0 = std::chrono::steady_clock::now();
  const SparsaResult base = sparsa(pb.a, pb.f, sp);
  const double t_base = seconds_since(t0);
  const LassoCertificate bcert = lasso_certificate(pb.a, pb.f, base.w, pb.lambda);
  const auto nnz = [](const Eigen::VectorXd& w) { return (w.array() != 0.0).count(); };
  ordered_json j;
  j["name"] = pb.name;
  j["rows"] = pb.a.rows();
  j["columns"] = pb.a.cols();
  j["lambda"] = pb.lambda;
  j["optimum"] = best.objective;
  j["optimum_gap"] = best.gap;
  j["objective"] = cert.primal;
  j["gap"] = cert.gap;
  j["relative_gap"] = cert.gap / cert.primal;
  j["excess"] = (cert.primal - best.objective) / best.objective;
  j["kkt"] = cert.kkt;
  j["nonzeros"] = nnz(cd.w);
  j["sweeps"] = cd.iterations;
  j["passes"] = cd.passes;
  j["time_s"] = t_cd;
  j["baseline"] = {{"solver", "sparsa, relative objective change 1e-5"},
                   {"objective", bcert.primal},
                   {"gap", bcert.gap},
                   {"excess", (bcert.primal - best.objective) / best.objective},
                   {"kkt", bcert.kkt},
                   {"nonzeros", nnz(base.w)},
                   {"iterations", base.iterations},
                   {"time_s", t_base}};
  j["speedup"] = t_base / t_cd;
  fmt::print(
      "{} ({} x {}): optimum {:.6g}; cd {:.6g} (+{:.2e}, gap {:.2e}, {} non-zeros, KKT {:.4f}) in "
      "{:.3f} s; sparsa {:.6g} (+{:.2e}, {} non-zeros, KKT {:.2f}) in {:.3f} s; {:.1f}x\n",
      pb.name, pb.a.rows(), pb.a.cols(), best.objective, cert.primal, j["excess"].get<double>(),
      cert.gap, nnz(cd.w), cert.kkt, t_cd, bcert.primal, j["baseline"]["excess"].get<double>(),
      nnz(base.w), bcert.kkt, t_base, t_base / t_cd);
  return j;
}

void run_bench_solver(const BenchSolverOptions& o) {
  ordered_json out;
  out["units"] = {{"time", "s"}};
  out["seed"] = o.seed;
  out["gap_tolerance"] = o.gap_tolerance;
  out["threads"] = o.threads;
  out["problems"] = ordered_json::array();
  for (const std::string& name : o.problems) out["problems"].push_back(bench_problem(name, o));
  if (!o.json.empty()) write_file_atomic(o.json, out.dump(1) + "\n");
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
