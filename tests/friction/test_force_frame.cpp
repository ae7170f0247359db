// Where the friction cone of a stuck contact lives (ForceFrame): synthetic palpation cycles on
// a sphere whose cone is at the anchor normal n_c, or at the normal under the displaced probe.
// With millimetres of pre-sliding on a 40 mm radius the two frames differ by several degrees;
// the fit must find the frame from the data (kAuto) and recover mu in it. Units: mm, N.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "inhap/core/error.hpp"
#include "inhap/friction/shape_query.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/surface_frame.hpp"

namespace inhap::friction {
namespace {

constexpr double kRadius = 40.0;  // probe-centre sphere, centre at the origin
constexpr double kMu = 0.8;
constexpr double kTangentialStiffness = 0.5;  // N/mm: 4.8 mm of pre-sliding at f_N = 3 N
constexpr double kNormalStiffness = 2.0;      // N/mm

class Sphere final : public ShapeQuery {
 public:
  using ShapeQuery::closest;
  bool closest(const Vec3& p, Vec3& point, Vec3& normal, double) const noexcept override {
    if (!(p.norm() > 0)) return false;
    normal = p.normalized();
    point = kRadius * normal;
    return true;
  }
};

// Unit tangential part of t at the normal n.
Vec3 along(const Vec3& t, const Vec3& n) {
  return (t - t.dot(n) * n).normalized();
}

// One loading cycle at (f_N, f_T) in direction k of the point with normal n0.
CycleRecord cycle(int id, const Vec3& n0, int k, const Vec3& tk, double fn, double ft,
                  double plateau, ForceFrame frame) {
  CycleRecord c;
  c.point = id;
  c.reference = c.pc = kRadius * n0;
  c.nc = n0;
  c.f_normal = fn;
  c.f_tangential = ft;
  c.t_plateau = plateau;
  c.direction = k;
  c.angle = k * std::numbers::pi / 2;
  c.tdir = tk;
  const double limit = kMu * fn;
  const double f_stick = std::min(ft, limit);
  c.u_meas = -fn / kNormalStiffness * n0 + f_stick / kTangentialStiffness * tk;
  const Vec3 n_probe = (c.pc + c.u_meas).normalized();
  const Vec3 n = frame == ForceFrame::kAnchor ? n0 : n_probe;
  c.f_meas = fn * n - f_stick * along(tk, n);  // the cone: |f_t| / f_n <= mu in `frame`
  // Past the limit the probe slides, and creeps on the long plateau in proportion to the excess.
  const double excess = std::max(0.0, ft - limit);
  const double slip = excess > 0 ? 0.3 + 3.0 * excess + (plateau > 0.3 ? 2.0 * excess : 0.0) : 0;
  c.pr = c.pc + slip * tk;
  return c;
}

std::vector<CycleRecord> palpation(ForceFrame frame) {
  std::vector<CycleRecord> all;
  const double deg = std::numbers::pi / 180;
  const Vec3 normals[] = {Vec3::UnitZ(), Vec3(std::sin(25 * deg), 0, std::cos(25 * deg)),
                          Vec3(0, std::sin(25 * deg), std::cos(25 * deg)),
                          Vec3(-std::sin(25 * deg), 0, std::cos(25 * deg))};
  for (int id = 0; id < 4; ++id) {
    const Vec3 n0 = normals[id];
    Vec3 t0, t1;
    tangent_basis(n0, Vec3::UnitX(), t0, t1);
    for (int k = 0; k < 4; ++k) {
      const Vec3 tk =
          std::cos(k * std::numbers::pi / 2) * t0 + std::sin(k * std::numbers::pi / 2) * t1;
      for (double fn : {1.0, 3.0})
        for (int s = 1; s <= 7; ++s) {  // f_T / f_N = 0.15 .. 1.05: the last two slide
          const double ft = 0.15 * s * fn;
          for (double plateau : {0.1, 0.6})
            all.push_back(cycle(id, n0, k, tk, fn, ft, plateau, frame));
        }
    }
  }
  return all;
}

// Largest relative error of the measured (not extrapolated) limits against mu f_N.
double worst_error(const SysModel& m) {
  double worst = 0;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    for (std::size_t j = 0; j < m.f_normal_levels.size(); ++j)
      for (std::size_t k = 0; k < m.angles.size(); ++k) {
        const double truth = kMu * m.f_normal_levels[j];
        worst = std::max(worst, std::abs(m.border(i, j, k).result.f_limit - truth) / truth);
      }
  return worst;
}

SysModel fit(ForceFrame data, ForceFrame asked) {
  static const Sphere sphere;
  FitOptions o;
  o.shape = &sphere;
  o.force_frame = asked;
  return fit_sys(palpation(data), o);
}

TEST(ForceFrame, AutoFindsWhereTheConeIsAndRecoversMu) {
  for (ForceFrame data : {ForceFrame::kAnchor, ForceFrame::kProbe}) {
    const SysModel m = fit(data, ForceFrame::kAuto);
    EXPECT_EQ(m.force_frame, data) << to_string(data);
    EXPECT_LT(worst_error(m), 0.02) << to_string(data);
  }
}

TEST(ForceFrame, TheWrongFrameOverstatesOrUnderstatesTheLimit) {
  // The test above can fail: split at the other normal, the limits at 3 N are off by far more.
  EXPECT_GT(worst_error(fit(ForceFrame::kAnchor, ForceFrame::kProbe)), 0.08);
  EXPECT_GT(worst_error(fit(ForceFrame::kProbe, ForceFrame::kAnchor)), 0.08);
  EXPECT_LT(worst_error(fit(ForceFrame::kAnchor, ForceFrame::kAnchor)), 0.02);
}

TEST(ForceFrame, NamesRoundTripAndBadNamesThrow) {
  for (ForceFrame f : {ForceFrame::kAuto, ForceFrame::kAnchor, ForceFrame::kProbe})
    EXPECT_EQ(force_frame_from_string(to_string(f)), f);
  EXPECT_THROW(force_frame_from_string("contact"), Error);
}

}  // namespace
}  // namespace inhap::friction
