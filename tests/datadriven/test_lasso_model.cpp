// The force model's l1 solver choice: the certificate per bin and axis, kept by the model file;
// files written before it still load (as SpaRSA-trained, without statistics).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "dd_fixtures.hpp"
#include "inhap/datadriven/model_io.hpp"

namespace inhap::datadriven {
namespace test_lasso_model {

TrainedForceModel trained(L1Solver solver) {
  TrainParams p = test::small_params();
  p.solver = solver;
  return train_with_provenance(test::take(test::synthetic_set(3, 6000), 0, 2), p);
}

TEST(LassoModel, CdCertifiesEveryBinAndAxis) {
  const TrainedForceModel tm = trained(L1Solver::kCd);
  const ForceModel& m = tm.model;
  const ForceModelProvenance& pv = tm.provenance;
  ASSERT_EQ(pv.stats.gap.size(), m.bins.size());
  ASSERT_EQ(pv.stats.nonzeros.size(), m.bins.size());
  for (std::size_t b = 0; b < m.bins.size(); ++b)
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_LE(pv.stats.gap[b][c], pv.params.gap_tolerance) << b << " " << c;
      EXPECT_GT(pv.stats.nonzeros[b][c], 0);
      EXPECT_EQ(pv.stats.support[b][c], std::min(pv.stats.nonzeros[b][c], pv.params.centers));
      EXPECT_EQ(pv.stats.support[b][c], m.bins[b].axes()[c].size());
      EXPECT_GT(pv.stats.sparsa_iterations[b][c], 0);
    }
}

TEST(LassoModel, SparsaStopsShortOfTheOptimum) {
  // The thesis' solver on the same data: its fits are not certified (larger gaps).
  const TrainedForceModel cd = trained(L1Solver::kCd), sp = trained(L1Solver::kSparsa);
  double worst_cd = 0, worst_sp = 0;
  for (std::size_t b = 0; b < cd.model.bins.size(); ++b)
    for (std::size_t c = 0; c < 3; ++c) {
      worst_cd = std::max(worst_cd, cd.provenance.stats.gap[b][c]);
      worst_sp = std::max(worst_sp, sp.provenance.stats.gap[b][c]);
    }
  EXPECT_GT(worst_sp, 10 * worst_cd);
}

TEST(LassoModel, FileKeepsTheStatisticsAndOldFilesLoad) {
  const TrainedForceModel m = trained(L1Solver::kCd);
  const ForceModelProvenance back =
      trained_force_model_from_json(force_model_to_json(m), "m.json").provenance;
  EXPECT_EQ(back.params.solver, L1Solver::kCd);
  EXPECT_EQ(back.stats.gap, m.provenance.stats.gap);
  EXPECT_EQ(back.stats.nonzeros, m.provenance.stats.nonzeros);
  auto j = nlohmann::json::parse(force_model_to_json(m));
  for (const char* k : {"solver", "gap_tolerance", "gap", "l1_nonzeros"}) j["train"].erase(k);
  const TrainedForceModel old = trained_force_model_from_json(j.dump(), "old.json");
  EXPECT_EQ(old.provenance.params.solver, L1Solver::kSparsa);
  EXPECT_TRUE(old.provenance.stats.gap.empty());
  EXPECT_TRUE(old.provenance.stats.nonzeros.empty());
  EXPECT_EQ(old.model.bins.size(), m.model.bins.size());
}

}  // namespace test_lasso_model
}  // namespace inhap::datadriven
