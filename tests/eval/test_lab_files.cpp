// inhap/eval/lab_files.hpp: scene choice, the scene table and the finite-recording check.
#include <gtest/gtest.h>

#include <limits>

#include "inhap/core/error.hpp"
#include "inhap/eval/lab_files.hpp"

namespace inhap::eval {
namespace {

TEST(LabFiles, PickSceneNeedsExactlyOne) {
  EXPECT_EQ(pick_scene("dome", "").name, "dome");
  EXPECT_THROW(pick_scene("dome", "x.json"), Error);
  EXPECT_THROW(pick_scene("", ""), Error);
}

TEST(LabFiles, TableHasEveryBuiltinScene) {
  const std::string t = scenes_table();
  for (const auto& name : lab::builtin_scene_names())
    EXPECT_NE(t.find("\n" + name + " "), std::string::npos) << name;
}

TEST(LabFiles, ANonFiniteRowIsRefusedByNumber) {
  Recording rec;
  for (int i = 0; i < 3; ++i) {
    rec.t.push_back(i * 1e-3);
    rec.p.push_back(Vec3::Zero());
    rec.f.push_back(Vec3::Zero());
  }
  EXPECT_NO_THROW(require_finite_recording(rec, "out.csv"));
  rec.f[1].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    require_finite_recording(rec, "out.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out.csv: refusing to write row 2"), std::string::npos);
  }
}

}  // namespace
}  // namespace inhap::eval
