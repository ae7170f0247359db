// Adaptive f_T schedule of the palpation sweep, driven by an oracle with a known border.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "inhap/friction/palpation.hpp"

namespace inhap::friction {
namespace {

struct Visit {
  std::size_t level;
  int dir;
  double lattice;
};

// Runs the schedule; a step "slides" (plateau growth 1 mm) when f_T / f_N > border(dir).
std::vector<Visit> run(const PalpationConfig& cfg, double max_force, double (*border)(int)) {
  SweepSchedule s(cfg, max_force);
  std::vector<Visit> v;
  while (!s.done()) {
    if (s.plateau_index() == 0) v.push_back({s.level(), s.direction(), s.lattice()});
    const bool slides = s.f_tangential() / s.f_normal() > border(s.direction()) + 1e-9;
    const double up = (s.plateau_index() == 1 && slides) ? 1.0 : 0.0;
    s.next(up);
  }
  return v;
}

std::vector<double> lattices(const std::vector<Visit>& v, std::size_t level, int dir) {
  std::vector<double> out;
  for (const Visit& x : v)
    if (x.level == level && x.dir == dir) out.push_back(x.lattice);
  return out;
}

TEST(SweepSchedule, FirstDirectionSweepsUpThenLaterOnesStartNearTheBorder) {
  PalpationConfig cfg;
  cfg.normal_forces = {1.0};
  cfg.directions = 3;
  const auto v = run(cfg, 6.2, [](int) { return 0.5; });
  // Direction 0: 0.15, 0.30, 0.45 elastic; 0.60 and 0.75 slide (the first direction of a level
  // takes two sliding steps: growth slope); the half step 0.525 slides too.
  EXPECT_EQ(lattices(v, 0, 0), (std::vector<double>{1, 2, 3, 4, 5, 3.5}));
  // Border seen in [0.45, 0.525] (mid 0.4875): start two lattice points below it.
  EXPECT_EQ(lattices(v, 0, 1), (std::vector<double>{2, 3, 4, 3.5}));
  EXPECT_EQ(lattices(v, 0, 2), (std::vector<double>{2, 3, 4, 3.5}));
}

TEST(SweepSchedule, StartsAgainLowerWhenTheFirstStepSlides) {
  PalpationConfig cfg;
  cfg.normal_forces = {1.0};
  cfg.directions = 2;
  const auto v = run(cfg, 6.2, [](int d) { return d == 0 ? 0.9 : 0.2; });
  EXPECT_EQ(lattices(v, 0, 0), (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 6.5}));
  // Predicted 0.9375: starts at lattice 5 (0.75), which slides -> back to 2 (0.3, slides) and
  // the half step 1.5 (0.225, slides).
  EXPECT_EQ(lattices(v, 0, 1), (std::vector<double>{5, 2, 1.5}));
}

TEST(SweepSchedule, RespectsTheForceCapAndUsesOtherLevels) {
  PalpationConfig cfg;  // 1, 3, 5 N; cap 0.97 * 6.2 N on |f_l|
  cfg.directions = 1;
  const auto v = run(cfg, 6.2, [](int) { return 1.2; });
  // 1 N: up to 1.35 and 1.5 (slide) and the half step 1.275.
  EXPECT_EQ(lattices(v, 0, 0).back(), 8.5);
  EXPECT_EQ(lattices(v, 0, 0).size(), 11u);
  // 3 N: starts below the 1 N border ratio (1.2375) -> lattice 7.
  EXPECT_EQ(lattices(v, 1, 0), (std::vector<double>{7, 8, 9, 10, 8.5}));
  // 5 N: f_T <= sqrt(6.014^2 - 25) = 3.34 N -> lattice <= 4; the last two points are measured.
  EXPECT_EQ(lattices(v, 2, 0), (std::vector<double>{3, 4}));
}

TEST(SweepSchedule, NonAdaptiveAlwaysStartsAtTheFirstStep) {
  PalpationConfig cfg;
  cfg.normal_forces = {1.0};
  cfg.directions = 2;
  cfg.adaptive = false;
  const auto v = run(cfg, 6.2, [](int) { return 0.5; });
  cfg.slope_steps = 1;
  const auto w = run(cfg, 6.2, [](int) { return 0.5; });
  EXPECT_EQ(lattices(w, 0, 0), (std::vector<double>{1, 2, 3, 4, 3.5}));
  EXPECT_EQ(lattices(w, 0, 1), (std::vector<double>{1, 2, 3, 4, 3.5}));
}

}  // namespace
}  // namespace inhap::friction
