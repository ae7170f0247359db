// The force model's l1 solver choice: the certificate per bin and axis, kept by the model file;
// files written before it still load (as SpaRSA-trained, without statistics).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "dd_fixtures.hpp"
#include "inhap/datadriven/model_io.hpp"

namespace inhap::datadriven {
namespace {

ForceModel trained(L1Solver solver) {
  TrainParams p = test::small_params();
  p.solver = solver;
  return train_force_model(test::take(test::synthetic_set(3, 6000), 0, 2), p);
}

TEST(LassoModel, CdCertifiesEveryBinAndAxis) {
  const ForceModel m = trained(L1Solver::kCd);
  ASSERT_EQ(m.stats.gap.size(), m.bins.size());
  ASSERT_EQ(m.stats.nonzeros.size(), m.bins.size());
  for (std::size_t b = 0; b < m.bins.size(); ++b)
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_LE(m.stats.gap[b][c], m.params.gap_tolerance) << b << " " << c;
      EXPECT_GT(m.stats.nonzeros[b][c], 0);
      EXPECT_EQ(m.stats.support[b][c], std::min(m.stats.nonzeros[b][c], m.params.centers));
      EXPECT_EQ(m.stats.support[b][c], m.bins[b].axes[c].size());
      EXPECT_GT(m.stats.sparsa_iterations[b][c], 0);
    }
}

TEST(LassoModel, SparsaStopsShortOfTheOptimum) {
  // The thesis' solver on the same data: its fits are not certified (larger gaps).
  const ForceModel cd = trained(L1Solver::kCd), sp = trained(L1Solver::kSparsa);
  double worst_cd = 0, worst_sp = 0;
  for (std::size_t b = 0; b < cd.bins.size(); ++b)
    for (std::size_t c = 0; c < 3; ++c) {
      worst_cd = std::max(worst_cd, cd.stats.gap[b][c]);
      worst_sp = std::max(worst_sp, sp.stats.gap[b][c]);
    }
  EXPECT_GT(worst_sp, 10 * worst_cd);
}

TEST(LassoModel, FileKeepsTheStatisticsAndOldFilesLoad) {
  const ForceModel m = trained(L1Solver::kCd);
  const ForceModel back = force_model_from_json(force_model_to_json(m), "m.json");
  EXPECT_EQ(back.params.solver, L1Solver::kCd);
  EXPECT_EQ(back.stats.gap, m.stats.gap);
  EXPECT_EQ(back.stats.nonzeros, m.stats.nonzeros);
  auto j = nlohmann::json::parse(force_model_to_json(m));
  for (const char* k : {"solver", "gap_tolerance", "gap", "l1_nonzeros"}) j["train"].erase(k);
  const ForceModel old = force_model_from_json(j.dump(), "old.json");
  EXPECT_EQ(old.params.solver, L1Solver::kSparsa);
  EXPECT_TRUE(old.stats.gap.empty());
  EXPECT_TRUE(old.stats.nonzeros.empty());
  EXPECT_EQ(old.bins.size(), m.bins.size());
}

}  // namespace
}  // namespace inhap::datadriven
