// Scene files: built-ins, JSON round trip, and clear errors on bad input.
#include <gtest/gtest.h>

#include <cstdio>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/lab/scene.hpp"
#include "support/temp_dir.hpp"

namespace inhap::lab {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "bad.json");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "(no error)";
}

const char* kGood = R"({
  "name": "mine",
  "geometry": {"type": "box", "center": [0, 0, 10], "size": [40, 30, 20]},
  "material": {"k": 0.5, "k_t": 0.4, "mu": 0.9},
  "inclusions": [{"center": [0, 0, 15], "radius": 6, "stiffness_factor": 2}]
})";

TEST(Scene, BuiltinsAreValidAndListed) {
  const auto names = builtin_scene_names();
  ASSERT_EQ(names.size(), 7u);
  for (const auto& n : names) {
    const Scene s = builtin_scene(n);
    EXPECT_EQ(s.name, n);
    EXPECT_EQ(validate_shape(s.object.shape()), "") << n;
    EXPECT_EQ(validate_material(s.object.material()), "") << n;
    EXPECT_FALSE(s.description.empty());
    // The operators' region lies over the object.
    EXPECT_TRUE(s.object.shape().drop(s.region.center.x(), s.region.center.y(), 8).has_value());
  }
  EXPECT_THROW(builtin_scene("nope"), Error);
  EXPECT_EQ(tapping_scene_names().size(), 5u);
}

TEST(Scene, JsonRoundTripKeepsEverything) {
  for (const auto& n : builtin_scene_names()) {
    const Scene a = builtin_scene(n);
    const std::string j = scene_to_json(a);
    const Scene b = parse_scene(j, n + ".json");
    EXPECT_EQ(scene_to_json(b), j) << n;
    for (const Vec3& p : {Vec3(0, 0, 60), Vec3(10, -12, 30), Vec3(-20, 10, 26)}) {
      EXPECT_DOUBLE_EQ(a.object.query(p).distance, b.object.query(p).distance) << n;
      EXPECT_DOUBLE_EQ(a.object.law_at(p).k, b.object.law_at(p).k) << n;
      EXPECT_DOUBLE_EQ(a.object.law_at(p).mu, b.object.law_at(p).mu) << n;
    }
  }
}

TEST(Scene, WriterKeepsStringsIntactAndArraysOnOneLine) {
  Scene s = builtin_scene("planar");
  s.description = "odd [1,  2] \\\"quoted [3,   4]\\\" ends \\\\";
  const std::string j = scene_to_json(s);
  EXPECT_NE(j.find("\"base_center\": [0.0, 0.0, 0.0]"), std::string::npos) << j;
  EXPECT_EQ(parse_scene(j, "x.json").description, s.description);
}

TEST(Scene, ParsesAHandWrittenFileWithDefaults) {
  const Scene s = parse_scene(kGood, "mine.json");
  EXPECT_EQ(s.name, "mine");
  EXPECT_EQ(s.object.shape().type_name(), "box");
  EXPECT_DOUBLE_EQ(s.object.material().exponent, 1.5);  // default
  EXPECT_DOUBLE_EQ(s.object.query(Vec3(0, 0, 30)).distance, 10);
  ASSERT_EQ(s.object.inclusions().size(), 1u);
  // The blob's centre is 5 mm under the top: factor 1 + (2 - 1) exp(-25 / 36) above it.
  EXPECT_NEAR(s.object.law_at(Vec3(0, 0, 40)).k, 0.5 * (1 + std::exp(-25.0 / 36)), 1e-12);
  EXPECT_NEAR(s.region.radius, 0.35 * 30, 1e-12);  // default region: 35 % of the footprint
}

TEST(Scene, BadFilesGiveOneLineErrorsNamingFileLineAndField) {
  EXPECT_EQ(
      error_of("{\n  \"name\": \"x\",\n  oops\n}").rfind("bad.json:3: expected a JSON scene", 0),
      0u)
      << error_of("{\n  \"name\": \"x\",\n  oops\n}");
  auto has = [](const std::string& msg, const std::string& part) {
    EXPECT_NE(msg.find(part), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_EQ(msg.rfind("bad.json", 0), 0u) << msg;
  };
  std::string t = kGood;
  has(error_of(std::string(t).replace(t.find("\"k\": 0.5, "), 10, "")), "material.k: missing");
  has(error_of(std::string(t).replace(t.find("\"box\""), 5, "\"blob\"")),
      "geometry.type: expected geometry type");
  has(error_of(std::string(t).replace(t.find("[40, 30, 20]"), 12, "[40, 30]")),
      "geometry.size: expected an array of 3 numbers");
  has(error_of(std::string(t).replace(t.find("\"mu\": 0.9"), 9, "\"mu\": \"high\"")),
      "material.mu: expected a number");
  has(error_of(std::string(t).replace(t.find("\"radius\": 6"), 11, "\"radius\": -6")),
      "inclusions[0].radius");
  has(error_of(std::string(t).replace(t.find("\"k_t\""), 5, "\"exponent\": 7, \"k_t\"")),
      "material.exponent");
  has(error_of(R"({"geometry": {"type": "ridged-slab", "base_center": [0,0,0], "size_x": 60,
    "size_y": 40, "thickness": 10, "ridges": 6, "ridge_height": 3, "ridge_width": 12},
    "material": {"k": 1, "k_t": 1, "mu": 1}})"),
      "ridge_width");
  has(error_of("[1, 2]"), "expected an object");
}

TEST(Scene, SaveAndLoadThroughFiles) {
  test::TempDir dir;
  const Scene a = builtin_scene("dome");
  save_scene(dir.path("dome.json"), a);
  const Scene b = load_scene(dir.path("dome.json"));
  EXPECT_EQ(scene_to_json(a).substr(0, 200), scene_to_json(b).substr(0, 200));
  EXPECT_EQ(b.source, dir.path("dome.json"));
  try {
    load_scene(dir.path("missing.json"));
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace inhap::lab
