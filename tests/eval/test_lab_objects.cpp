// inhap/eval/lab_objects.hpp: the object lists and JSON of `eval contacts` / `eval shape`.
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/eval/lab_objects.hpp"

namespace inhap::eval {
namespace {

TEST(LabObjects, ShapeTargetsAndTheirTaps) {
  const auto all = shape_targets(false, {}, 0, false);  // Table 3.1's counts
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[0].name, "foam-ball");
  EXPECT_EQ(all[0].taps, 1000u);
  EXPECT_EQ(all[1].taps, 950u);
  EXPECT_EQ(all[2].taps, 300u);
  EXPECT_EQ(all[3].name, "bunny");
  EXPECT_EQ(all[3].taps, kBunnyTaps);
  const auto quick = shape_targets(false, {}, 0, true);  // a fifth, at least 60
  EXPECT_EQ(quick[0].taps, 200u);
  EXPECT_EQ(quick[1].taps, 190u);
  EXPECT_EQ(quick[2].taps, 60u);
  const auto top = shape_targets(true, {}, 0, false);  // no bunny in the top-cap protocol
  ASSERT_EQ(top.size(), 3u);
  EXPECT_EQ(top.back().name, "silicone-hemisphere");
  const auto some = shape_targets(false, {"bunny", "foam-ball"}, 77, true);  // table order
  ASSERT_EQ(some.size(), 2u);
  EXPECT_EQ(some[0].name, "foam-ball");
  EXPECT_EQ(some[1].name, "bunny");
  EXPECT_EQ(some[1].taps, 77u);  // --taps wins over --quick
  EXPECT_TRUE(shape_targets(true, {"bunny"}, 0, false).empty());
}

TEST(LabObjects, SceneOfATarget) {
  EXPECT_EQ(shape_target_scene("foam-ball", "").name, "foam-ball");
  EXPECT_THROW(shape_target_scene("bunny", "/nonexistent/bun_zipper.ply"), Error);
}

TEST(LabObjects, OptionsFollowTheProtocol) {
  ShapeEvalSettings s;
  s.seed = 7;
  s.region_mm = 4;
  s.quick = true;
  ShapeObjectOptions o = shape_object_options(123, s);
  EXPECT_EQ(o.taps, 123u);
  EXPECT_EQ(o.seed, 7u);
  EXPECT_TRUE(o.tap.whole_object);
  EXPECT_TRUE(o.compare.uncropped_reconstruction);
  EXPECT_TRUE(o.score_reachable_part);
  EXPECT_TRUE(o.compare.normal_overlap);
  EXPECT_EQ(o.compare.region_mm, 4.0);
  EXPECT_EQ(o.coverage_samples, 5000u);
  EXPECT_TRUE(o.count_entry_sides);
  s.top_only = true;
  s.no_normal_overlap = true;
  s.quick = false;
  o = shape_object_options(1, s);
  EXPECT_FALSE(o.tap.whole_object);
  EXPECT_FALSE(o.compare.uncropped_reconstruction);
  EXPECT_FALSE(o.score_reachable_part);
  EXPECT_FALSE(o.compare.normal_overlap);
  EXPECT_EQ(o.coverage_samples, 20000u);
}

TEST(LabObjects, Json) {
  ContactObjectResult c;
  c.name = "sponge";
  c.taps = 20;
  c.estimate = {0.1, 0.2, 0.3};
  const nlohmann::json j = contact_object_json(c);
  EXPECT_EQ(j["name"], "sponge");
  EXPECT_EQ(j["taps"], 20);
  EXPECT_EQ(j["estimate_mm"]["p95"], 0.2);
  const nlohmann::json run = contacts_run_json(nlohmann::json::array({j}), 0.2, 100, 3);
  EXPECT_EQ(run["objects"].size(), 1u);
  EXPECT_EQ(run["eps_f_n"], 0.2);
  EXPECT_EQ(run["window_samples"], 100);
  EXPECT_EQ(run["seed"], 3);

  ShapeObjectResult r;
  r.estimate.points = 5;
  r.estimate.cmp.hausdorff = 1.5;
  r.threshold.cmp.hausdorff = 2.5;
  r.coverage = 0.75;
  r.sides.episodes = 9;
  const nlohmann::json sj = shape_object_json("foam-ball", r);
  EXPECT_EQ(sj["points"], 5);
  EXPECT_EQ(sj["hausdorff_mm"]["threshold"], 2.5);
  EXPECT_EQ(sj["coverage"], 0.75);
  EXPECT_EQ(sj["episodes"], 9);
  ShapeEvalSettings s;
  s.top_only = true;
  const nlohmann::json sr = shape_run_json(nlohmann::json::array(), s);
  EXPECT_EQ(sr["protocol"], "top caps (region seen from above)");
  EXPECT_EQ(sr["common_region"],
            "reference within 5 mm of the true contact points, overlap only; the reconstruction "
            "cropped likewise");
}

}  // namespace
}  // namespace inhap::eval
