// Flags shared by `inhap model train` and `inhap eval forces`: the local-frame training options
// (tangent mirror, stiffness and shear priors, friction cone) and the l1 solver of
// datadriven::TrainParams. Units: mm, N.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "command.hpp"

#include "inhap/datadriven/force_model.hpp"

namespace inhap::cli {

/// Adds --[no-]tangent-mirror, --[no-]stiffness-prior, --[no-]shear-prior,
/// --[no-]friction-cone, --[no-]sliding-floor, --[no-]fallback, --[no-]isotropic-positions,
/// --[no-]envelope and --solver cd|sparsa bound to `p`; `defaults` ends each help line, e.g.
/// "default on" (the command sets the defaults in `p`).
inline void add_local_training_flags(CLI::App& cmd, datadriven::TrainParams& p,
                                     const std::string& defaults) {
  struct Flag {
    const char* name;  // --NAME and --no-NAME
    bool datadriven::TrainParams::*value;
    const char* help;  // completed by defaults + ")"
  };
  static constexpr Flag kFlags[] = {
      {"tangent-mirror", &datadriven::TrainParams::tangent_mirror,
       "Local features: also train on every sample turned 180 deg about the normal (assumes a "
       "tangentially isotropic material; "},
      {"stiffness-prior", &datadriven::TrainParams::stiffness_prior,
       "Local features: fit a local stiffness prior f_n = k(q) d^alpha (N, mm) first and let the "
       "RBFs learn the rest; carries shallow stiffness to deep pushes ("},
      {"shear-prior", &datadriven::TrainParams::shear_prior,
       "Local features: fit a local shear prior f_t = -k_t(q) |u_t|^beta u_t/|u_t| (N, mm; u_t = "
       "tangential part of p - q) first and let the RBFs learn the rest ("},
      {"friction-cone", &datadriven::TrainParams::friction_cone,
       "Local features: keep the rendered force inside the training data's friction cone, "
       "|f_t| <= c max(f_n, 0.3 N) ("},
      {"sliding-floor", &datadriven::TrainParams::sliding_floor,
       "Local features: while the proxy slides (it moved since the last tick in contact) render "
       "at least the Coulomb force |f_t| >= mu_s f_n along the proxy's lag, mu_s = the 10 % "
       "quantile of |f_t| / f_n over the training samples whose proxy slid ("},
      {"fallback", &datadriven::TrainParams::fallback,
       "Local features: far from every training proxy blend towards the recording's own "
       "monotone depth-force law f_n(d) (plus the shear prior) ("},
      {"isotropic-positions", &datadriven::TrainParams::isotropic_positions,
       "Any features: standardise a position (mm) with one scale for its three coordinates, the "
       "RMS of their spreads, not one per coordinate (a flat object's proxy height, spread "
       "0.1 mm, would otherwise weigh as much as its 10 mm spread across; "},
      {"envelope", &datadriven::TrainParams::envelope,
       "Any features: cap every rendered |f| at the training data's largest |f| near the state "
       "(within an 8 mm cell of q and 0.5 mm of ||q - p|| deeper) x 1.25 + 0.25 N (on in every "
       "preset; "},
  };
  for (const Flag& f : kFlags) add_switch(cmd, f.name, p.*f.value, f.help + defaults + ")", false);
  cmd.add_option_function<std::string>(
         "--solver",
         [&p](const std::string& s) { p.solver = datadriven::l1_solver_from_string(s); },
         "l1 solver of the RBF weights: cd = coordinate descent to the optimum with a "
         "duality-gap certificate, sparsa = SpaRSA, the thesis' solver, which stops on slow "
         "progress (default: cd in preset best, which eval forces uses; sparsa in world and "
         "thesis)")
      ->check(CLI::IsMember({"cd", "sparsa"}));
  struct Distance {
    const char* name;
    double datadriven::TrainParams::*value;
    const char* help;
    bool positive;  // > 0, else >= 0
  };
  static constexpr Distance kDistances[] = {
      {"--fallback-near", &datadriven::TrainParams::fallback_near_mm,
       "Fallback: within this distance of a training proxy the model renders as trained, mm",
       false},
      {"--fallback-far", &datadriven::TrainParams::fallback_far_mm,
       "Fallback: beyond this distance from every training proxy the law alone renders, mm", true},
      {"--fallback-normal-near", &datadriven::TrainParams::fallback_normal_near_mm,
       "Fallback: from this distance of the nearest training proxy the normal force blends "
       "towards the model's with the probe on the proxy's normal line at the same depth (the "
       "tangential displacement's effect is not extrapolated between training spots), mm",
       false},
      {"--fallback-normal-far", &datadriven::TrainParams::fallback_normal_far_mm,
       "Fallback: from this distance on the normal force is the normal line's alone, mm "
       "(--fallback-normal-near 0 --fallback-normal-far 0: off)",
       false},
  };
  for (const Distance& d : kDistances)
    cmd.add_option(d.name, p.*d.value, d.help)
        ->capture_default_str()
        ->check(d.positive ? CLI::Validator(CLI::PositiveNumber)
                           : CLI::Validator(CLI::NonNegativeNumber));
}

}  // namespace inhap::cli
