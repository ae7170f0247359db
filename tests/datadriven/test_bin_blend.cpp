// Blending of neighbouring bins near their edge (TrainParams::bin_blend): the rendered force is
// continuous across the edge (a hard switch jumps), equals the mean of the two bins' forces at
// the edge, is unchanged away from edges, and survives a save/load round trip bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "dd_fixtures.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "support/temp_dir.hpp"

namespace inhap::datadriven {
namespace {

const ForceModel& hard_model() {
  static const ForceModel m = [] {
    TrainParams p = test::small_params();  // 3 bins
    return train_force_model(test::synthetic_set(4, 6000), p);
  }();
  return m;
}

/// Input with ||q - p|| = key: q on the surface, p pressed in along -z and displaced along x.
void input_at(double key, Vec3& p, Vec3& q) {
  q = Vec3(3.0, -2.0, 0.0);
  const Vec3 dir = Vec3(0.4, 0.0, -1.0).normalized();
  p = q + key * dir;
}

TEST(BinBlend, ForceIsContinuousAcrossTheEdgeAndTheMeanAtIt) {
  ForceModel hard = hard_model();
  ASSERT_GE(hard.edges.size(), 1u);
  ForceModel soft = hard;
  soft.bin_blend = 0.3;
  const Vec3 v(5.0, -3.0, 1.0);
  const double e = hard.edges[0];
  Vec3 p1, q1, p2, q2;
  input_at(e - 1e-9, p1, q1);
  input_at(e + 1e-9, p2, q2);
  const double jump_hard = (model_force(hard, p1, v, q1) - model_force(hard, p2, v, q2)).norm();
  const double jump_soft = (model_force(soft, p1, v, q1) - model_force(soft, p2, v, q2)).norm();
  std::printf("force jump at the edge: %.3g N hard, %.3g N blended\n", jump_hard, jump_soft);
  EXPECT_GT(jump_hard, 1e-3);
  EXPECT_LT(jump_soft, 1e-6);
  // At the edge: the mean of both bins' forces (the hard model gives each side).
  Vec3 pe, qe;
  input_at(e, pe, qe);
  ForceModel only_lower = hard, only_upper = hard;
  only_lower.edges[0] = e + 1.0;  // same bins, the edge moved: bin 0 evaluated at key e
  only_upper.edges[0] = e - 1.0;  // bin 1 evaluated at key e
  if (only_upper.edges.size() > 1) {
    ASSERT_GT(only_upper.edges[1], e + 1.0);
  }
  const Vec3 mean = 0.5 * (model_force(only_lower, pe, v, qe) + model_force(only_upper, pe, v, qe));
  EXPECT_LT((model_force(soft, pe, v, qe) - mean).norm(), 1e-9);
  // Away from every edge: unchanged.
  Vec3 pf, qf;
  input_at(0.5 * e, pf, qf);
  ASSERT_GT(e - 0.5 * e, soft.bin_blend);
  EXPECT_EQ(model_force(soft, pf, v, qf), model_force(hard, pf, v, qf));
}

TEST(BinBlend, SurvivesSaveAndLoadBitForBit) {
  ForceModel soft = hard_model();
  soft.bin_blend = 0.3;
  inhap::test::TempDir dir;
  const std::string path = dir.path("m.json");
  save_force_model(path, soft);
  const ForceModel back = load_force_model(path);
  EXPECT_EQ(back.bin_blend, 0.3);
  const Vec3 v(1.0, 2.0, -1.0);
  for (double k = 0.0; k < 6.0; k += 0.05) {
    Vec3 p, q;
    input_at(k, p, q);
    EXPECT_EQ(model_force(back, p, v, q), model_force(soft, p, v, q)) << k;
  }
}

}  // namespace
}  // namespace inhap::datadriven
