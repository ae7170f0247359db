// Forces above the modeling range: training counts them, keeps or excludes them on request and
// never clips a target; `inhap model train` reports them (a recording with 10 N pushes).
// Units: mm, N.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <algorithm>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/synthetic.hpp"
#include "support/temp_dir.hpp"

namespace inhap::datadriven {
namespace {

// A synthetic recording pushed deep enough that its forces reach about 10 N and more.
Recording deep_recording(std::uint64_t seed, std::size_t samples) {
  SyntheticParams sp;
  sp.samples = samples;
  sp.seed = seed;
  sp.max_depth = 6.5;
  return synthetic_recording(sp);
}

TrainingSet set_of(const Recording& rec) {
  return make_training_set(rec, proxy_from_columns(rec, "deep"), FoawParams{});
}

std::size_t count_over(const std::vector<Vec3>& f, double limit) {
  std::size_t n = 0;
  for (const Vec3& x : f) n += x.norm() > limit ? 1 : 0;
  return n;
}

TEST(AboveRange, TrainingNeverClipsTargetsAndCountsThem) {
  const TrainingSet set = set_of(deep_recording(1, 9000));
  const std::size_t over_range = count_over(set.f, 5.0), over_limit = count_over(set.f, 6.2);
  ASSERT_GT(over_limit, 200u) << "the recording must reach well beyond 6.2 N";
  double max_f = 0;
  for (const Vec3& f : set.f) max_f = std::max(max_f, f.norm());
  ASSERT_GT(max_f, 9.0);

  TrainParams p;
  p.centers = 60;
  const TrainedForceModel trained = train_with_provenance(set, p);
  const ForceModel& kept = trained.model;
  const TrainStats& st = trained.provenance.stats;
  EXPECT_EQ(st.offered, set.size());
  EXPECT_EQ(st.above_range, over_range);
  EXPECT_EQ(st.excluded, 0u);
  EXPECT_EQ(st.samples, set.size());
  EXPECT_DOUBLE_EQ(st.max_force_n, max_f);

  // The model reproduces the deep pushes up to the device's clamp: a model trained on targets
  // clipped at the 5 N modeling range could not be learnt back above it. (The clamp itself is
  // the device profile's 6.2 N, which no model can raise; the targets' maximum is checked above.)
  std::vector<double> rendered;
  for (std::size_t i = 0; i < set.size(); ++i)
    if (set.f[i].norm() > 8.0)
      rendered.push_back(model_force(kept, set.p[i], set.v[i], set.q[i]).norm());
  ASSERT_GT(rendered.size(), 20u);
  std::nth_element(rendered.begin(), rendered.begin() + static_cast<long>(rendered.size() / 2),
                   rendered.end());
  EXPECT_NEAR(rendered[rendered.size() / 2], inhap::kDeviceForceLimitN, 1e-9);

  // Excluded on request: the samples above the range are left out and counted.
  p.above_range = AboveRange::kExclude;
  const TrainStats excl = train_with_provenance(set, p).provenance.stats;
  EXPECT_EQ(excl.above_range, over_range);
  EXPECT_EQ(excl.excluded, over_range);
  EXPECT_EQ(excl.samples, set.size() - over_range);
}

TEST(AboveRange, PresetsAreTheDocumentedPipelines) {
  const TrainParams best = preset_params("best");
  EXPECT_EQ(best.features, FeatureSet::kLocalFrame);
  EXPECT_TRUE(best.tangent_mirror && best.stiffness_prior && best.shear_prior &&
              best.friction_cone && best.fallback);
  EXPECT_EQ(best.feature_weights, (std::array<double, 3>{1.0, 5.0, 0.5}));
  EXPECT_EQ(best.bin_blend, 1.0);
  const TrainParams thesis = preset_params("thesis");
  EXPECT_EQ(thesis.bins, 5);
  EXPECT_FALSE(thesis.linear_tail);
  EXPECT_EQ(thesis.design, Design::kThesis);
  EXPECT_THROW(preset_params("fastest"), Error);
  EXPECT_THROW(above_range_from_string("clip"), Error);
}

int run(const std::string& args, const std::string& log) {
  const std::string cmd = std::string(INHAP_CLI) + " " + args + " > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(AboveRange, ModelTrainReportsTenNewtonPushes) {
  inhap::test::TempDir dir;
  const Recording rec = deep_recording(3, 9000);
  write_recording(dir.path("deep.csv"), rec);
  const TrainingSet set = set_of(rec);
  const std::size_t over_range = count_over(set.f, 5.0), over_limit = count_over(set.f, 6.2);
  ASSERT_GT(over_limit, 200u);
  const std::string log = dir.path("log.txt");
  const std::string common = " --centers 40 --recording " + dir.path("deep.csv");

  ASSERT_EQ(run("model train" + common + " --out " + dir.path("k.json"), log), 0) << read_file(log);
  const std::string text = read_file(log);
  EXPECT_NE(text.find(fmt::format("{} of {} samples", over_range, set.size())), std::string::npos)
      << text;
  EXPECT_NE(text.find(fmt::format("{} above the 6.20 N render clamp", over_limit)),
            std::string::npos)
      << text;
  const auto k = nlohmann::json::parse(read_file(dir.path("k.json")));
  EXPECT_EQ(k["train"]["samples_above_range"].get<std::size_t>(), over_range);
  EXPECT_EQ(k["train"]["samples"].get<std::size_t>(), set.size());
  EXPECT_EQ(k["train"]["above_range"], "keep");

  ASSERT_EQ(run("model train" + common + " --above-range exclude --out " + dir.path("x.json"), log),
            0)
      << read_file(log);
  const auto x = nlohmann::json::parse(read_file(dir.path("x.json")));
  EXPECT_EQ(x["train"]["samples_excluded"].get<std::size_t>(), over_range);
  EXPECT_EQ(x["train"]["samples"].get<std::size_t>(), set.size() - over_range);

  // Replayed, the capped samples are counted too.
  ASSERT_EQ(run("model eval --model " + dir.path("k.json") + " --recording " +
                    dir.path("deep.csv") + " --json " + dir.path("e.json"),
                log),
            0)
      << read_file(log);
  const auto e = nlohmann::json::parse(read_file(dir.path("e.json")));
  EXPECT_EQ(e["measured_above_force_limit"].get<std::size_t>(), over_limit);
}

}  // namespace
}  // namespace inhap::datadriven
