// inhap/eval/shape_files.hpp: the reports of `inhap shape contacts | reconstruct | compare`, on
// inputs whose numbers are known (a plane against the same plane lifted by 0.5 mm).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "inhap/eval/shape_files.hpp"
#include "support/meshes.hpp"

namespace inhap::eval {
namespace {

TEST(ShapeFiles, ContactsSummaryCountsBothMethods) {
  TappingResult r;
  r.contacts.resize(3);
  r.contacts[0].estimated = true;
  r.contacts[2].estimated = true;
  EXPECT_EQ(contacts_summary(r),
            "3 taps (2 by true-contact estimation, 1 by thresholding); force: recorded contact "
            "force");
}

TEST(ShapeFiles, ReconstructSummarySaysWhatWasGiven) {
  ReconstructReport rep;
  rep.points_in = 100;
  rep.outliers = 2;
  rep.alpha = 3.25;
  rep.vertices = 50;
  rep.faces = 96;
  ReconstructOptions o;
  o.mode = SurfaceMode::kSolid;
  o.alpha = 3.25;
  EXPECT_EQ(reconstruct_summary(rep, o, "solid", false),
            "100 points (2 outliers removed), solid mode, alpha 3.250 mm (given)\n"
            "mesh: 50 vertices, 96 faces");
}

TEST(ShapeFiles, ComparingAPlaneWithItsLiftedCopy) {
  const TriMesh a = test::make_grid_mesh(11, 11, 1.0);
  const TriMesh b = test::make_grid_mesh(11, 11, 1.0, [](double, double) { return 0.5; });
  CompareReport r;
  r.a = "a.ply";
  r.b = "b.ply";
  r.cropped = cropped_sides(r.options);
  r.result = compare_surfaces(a, b, r.options);
  const std::string t = compare_text(r);
  EXPECT_EQ(t.rfind("hausdorff 0.5000 mm, mean 0.5000 mm, rms 0.5000 mm\n", 0), 0u) << t;
  EXPECT_NE(t.find("  a.ply -> b.ply: max 0.5000"), std::string::npos) << t;
  const nlohmann::json j = nlohmann::json::parse(compare_json(r));
  EXPECT_NEAR(j["hausdorff_mm"].get<double>(), 0.5, 1e-9);
  EXPECT_NEAR(j["b_to_a"]["mean_mm"].get<double>(), 0.5, 1e-9);
  EXPECT_EQ(j["a"], "a.ply");
  EXPECT_EQ(j["units"], "mm");
}

}  // namespace
}  // namespace inhap::eval
