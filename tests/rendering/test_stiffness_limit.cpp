// A stiffness map beyond what a device renders is refused: 1e5 N/mm sent the first 182 ms of
// every contact of a stroke to the 6.2 N clamp.
#include <gtest/gtest.h>

#include <string>

#include "inhap/core/error.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/rendering/renderer.hpp"

TEST(StiffnessLimit, AModelRefusesStiffnessAboveTwentyNewtonsPerMillimetre) {
  inhap::TriMesh m;
  m.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}};
  m.triangles = {{0, 1, 2}};
  m.set_property("stiffness", {0.5, 1e5, 0.5});
  try {
    inhap::rendering::Model model(m, inhap::rendering::Params{});
    FAIL() << "1e5 N/mm accepted";
  } catch (const inhap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 1"), std::string::npos) << e.what();
  }
  m.set_property("stiffness", {0.5, 20.0, 0.5});
  EXPECT_NO_THROW(inhap::rendering::Model(m, inhap::rendering::Params{}));
}
