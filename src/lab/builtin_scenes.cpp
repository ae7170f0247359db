// Built-in scenes of the virtual lab and where their numbers come from (see also
// docs/virtual-lab.md, "Built-in scenes"). Units: mm, N, s.
#include <fmt/format.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::lab {

namespace {

constexpr double kProbeRadius = 8.0;  // thesis ch. 4 sphere probe (diameter 1.6 cm)

/// Hertz contact of a rigid sphere (radius 8 mm) on an incompressible half-space (nu = 0.5):
/// f = 4/3 E* sqrt(R) delta^1.5 with E* = E / (1 - nu^2). E in MPa = N/mm^2.
double hertz_k(double young_mpa) {
  return 4.0 / 3.0 * young_mpa / 0.75 * std::sqrt(kProbeRadius);
}

/// Law coefficient giving an effective (secant) stiffness k5 (N/mm) at 5 N for exponent e.
double k_for_effective(double k5, double e) {
  return std::pow(k5, e) / std::pow(5.0, e - 1.0);
}

/// Mindlin: initial tangential stiffness = 2 (1 - nu) / (2 - nu) of the normal tangent
/// stiffness (2/3 for nu = 0.5), taken at a 1 N normal load and then kept constant.
double mindlin_kt(const ContactLaw& law) {
  return 2.0 / 3.0 * law.tangent_stiffness(1.0);
}

ContactLaw make_law(double k, double e, double damping, double mu) {
  ContactLaw law;
  law.k = k;
  law.exponent = e;
  law.damping = damping;
  law.mu = mu;
  law.creep = 0.02;  // chosen: |f_T|/f_N within ~1 % of mu at 2 mm/s and 3 N; see docs
  law.k_t = mindlin_kt(law);
  return law;
}

// Smooth-On 100 % moduli (technical bulletins, as quoted by the project brief and recalled
// here; not re-verified): Ecoflex 00-10 55 kPa, 00-30 69 kPa, Dragon Skin 10 152 kPa.
constexpr double kEcoflex0010 = 0.055, kEcoflex0030 = 0.069, kDragonSkin10 = 0.152;
// Silicone on a steel/plastic probe: mu ~ 1.2, from thesis Table 4.1 (elastic border between
// f_T = 1.19 and 1.33 N at f_N = 1 N). Hunt-Crossley damping 0.004 s/mm (chosen: a 2 Hz,
// 2 mm cycle gets ~10 % viscous force, loss tangent of soft silicone ~0.1).
constexpr double kSiliconeMu = 1.2, kSiliconeDamping = 0.004;
constexpr double kFoamExponent = 1.2, kFoamDamping = 0.01;  // chosen: foams stiffen less

/// A scene from its parts; `region_radius` (mm) bounds where operators explore, around the origin.
Scene make_scene(const char* name, std::string description, SoftObject object,
                 double region_radius) {
  Scene s;
  s.name = name;
  s.description = std::move(description);
  s.object = std::move(object);
  s.region = {Vec2::Zero(), region_radius};
  return s;
}

Scene planar() {
  const ContactLaw law = make_law(hertz_k(kEcoflex0030), 1.5, kSiliconeDamping, kSiliconeMu);
  // Thinner-rich pieces: 0.35-0.5 x the stiffness (chosen), 6-8 mm below the top; the
  // tackier thinner-rich silicone gets up to 15 % more friction (chosen).
  std::vector<Inclusion> inc = {{Vec3(-20, 10, 18), 9.0, 0.35, 1.15},
                                {Vec3(18, 14, 17), 8.0, 0.5, 1.1},
                                {Vec3(4, -20, 18), 10.0, 0.4, 1.0}};
  return make_scene("planar",
                    "thesis 4.5.1: Ecoflex 00-30 cylinder, 100 mm diameter x 25 mm, three softer "
                    "thinner-rich inclusions below the top (not protruding)",
                    SoftObject(CylinderShape{Vec3::Zero(), 50.0, 25.0}, law, std::move(inc)), 30.0);
}

Scene dome() {
  const ContactLaw law = make_law(hertz_k(kEcoflex0030), 1.5, kSiliconeDamping, kSiliconeMu);
  // Ball of radius 12 mm centred 14 mm below the apex, 4x stiffer: the apex gets
  // 1 + 3 exp(-(14/12)^2) = 1.77x the shell's stiffness (chosen).
  std::vector<Inclusion> inc = {{Vec3(0, 0, 16), 12.0, 4.0, 1.0}};
  return make_scene(
      "dome",
      "thesis 4.5.2: Ecoflex 00-30 dome, 100 mm diameter x 30 mm high, stiff rubber ball "
      "inside under the top",
      SoftObject(DomeShape{Vec3::Zero(), 50.0, 30.0}, law, std::move(inc)), 25.0);
}

Scene sponge() {
  return make_scene(
      "sponge", "thesis fig. 3.3a: soft sponge block 100 x 70 x 40 mm, 0.3 N/mm at 5 N",
      SoftObject(BoxShape{Vec3(0, 0, 20), Vec3(50, 35, 20)},
                 make_law(k_for_effective(0.3, kFoamExponent), kFoamExponent, kFoamDamping, 0.8)),
      25.0);
}

Scene silicone_hemisphere() {
  return make_scene("silicone-hemisphere",
                    "thesis fig. 3.3b: Ecoflex 00-10 hemisphere, radius 40 mm",
                    SoftObject(HemisphereShape{Vec3::Zero(), 40.0},
                               make_law(hertz_k(kEcoflex0010), 1.5, kSiliconeDamping, kSiliconeMu)),
                    25.0);
}

Scene foam_ball() {
  return make_scene(
      "foam-ball", "thesis fig. 3.3c: firm foam ball, 70 mm diameter, 1.8 N/mm at 5 N",
      SoftObject(SphereShape{Vec3(0, 0, 35), 35.0},
                 make_law(k_for_effective(1.8, kFoamExponent), kFoamExponent, kFoamDamping, 0.9)),
      20.0);
}

Scene ridged_silicone() {
  RidgedSlabShape r;
  r.size_x = 100, r.size_y = 60, r.thickness = 20, r.ridges = 6, r.ridge_height = 6,
  r.ridge_width = 14;
  return make_scene(
      "ridged-silicone",
      "thesis fig. 3.3d: Dragon Skin 10 slab 100 x 60 x 20 mm with six 6 mm triangular ridges",
      SoftObject(r, make_law(hertz_k(kDragonSkin10), 1.5, kSiliconeDamping, 1.0)), 30.0);
}

Scene silicone_block() {
  // 3 N/mm at 5 N needs E ~ 0.46 MPa (between Dragon Skin 20 and 30; chosen).
  return make_scene("silicone-block",
                    "thesis fig. 3.3e: stiff silicone block 80 x 60 x 30 mm, 3 N/mm at 5 N",
                    SoftObject(BoxShape{Vec3(0, 0, 15), Vec3(40, 30, 15)},
                               make_law(k_for_effective(3.0, 1.5), 1.5, kSiliconeDamping, 1.0)),
                    20.0);
}

struct Entry {
  const char* name;
  Scene (*make)();
};
constexpr Entry kScenes[] = {{"planar", planar},
                             {"dome", dome},
                             {"sponge", sponge},
                             {"silicone-hemisphere", silicone_hemisphere},
                             {"foam-ball", foam_ball},
                             {"ridged-silicone", ridged_silicone},
                             {"silicone-block", silicone_block}};

}  // namespace

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> out;
  for (const auto& e : kScenes) out.emplace_back(e.name);
  return out;
}

std::vector<std::string> tapping_scene_names() {
  return {"sponge", "silicone-hemisphere", "foam-ball", "ridged-silicone", "silicone-block"};
}

Scene builtin_scene(std::string_view name) {
  for (const auto& e : kScenes)
    if (name == e.name) return e.make();
  std::string names;
  for (const auto& e : kScenes) names += (names.empty() ? "" : ", ") + std::string(e.name);
  throw Error(fmt::format("unknown scene '{}': expected one of {}", name, names));
}

}  // namespace inhap::lab
