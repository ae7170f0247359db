// A virtual participant for the TCA-MESH user study (thesis sec. 5.4): a simulated person
// holding a simulated impedance-type haptic device. It is a data source like a real person with
// a real device, so it lives in the lab library and plugs into the protocol of
// inhap/rendering/experiment.hpp through two interfaces: inhap::Device (the device it holds)
// and rendering::JudgementSource (the keyboard it types on).
//
// The person explores the way the thesis' participants did: it strokes across each model to
// judge shape, regulating the normal force to a personal level (force constancy, with a
// limited-bandwidth force loop and a slow +-10 % fluctuation), and taps in place (centre and
// surround) to judge stiffness. Judgements use only what a person senses — the probe (HIP)
// position and the rendered force — with a height-difference threshold for shape and a Weber
// fraction for stiffness (values and sources in docs/tca-experiment.md).
//
// Units: positions mm, velocities mm/s, forces N, stiffness N/mm, masses kg, time s.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/rendering/datasets.hpp"
#include "inhap/rendering/experiment.hpp"

namespace inhap::lab {

/// One person's traits and exploration habits.
struct ParticipantProfile {
  std::uint64_t seed = 1;     ///< perceptual noise, stroke directions, aiming
  double force_n = 1.4;       ///< normal force level kept while stroking and tapping, N
  double speed_mm_s = 40;     ///< lateral stroke speed, mm/s
  double fluctuation = 0.10;  ///< bound of the relative force fluctuation (+-10 %)
  std::array<double, 4> fluctuation_hz{0.13, 0.29, 0.47, 0.71};      ///< slow drift components
  std::array<double, 4> fluctuation_weight{0.25, 0.25, 0.25, 0.25};  ///< sum 1
  std::array<double, 4> fluctuation_phase{0, 1.6, 3.1, 4.7};         ///< rad
  int strokes_per_model = 3;  ///< strokes through the centre, in as many directions
  double stroke_half_length_mm = 13.5;
  int taps_per_site = 3;  ///< taps at the centre and at the surround each
  double tap_speed_mm_s = 40;
  double surround_tap_radius_mm = 11;
  double aim_sd_mm = 0.4;            ///< SD of where a stroke or tap lands around the aim
  double weber_fraction = 0.22;      ///< stiffness JND (Jones & Hunter 1990; Tan et al. 1995)
  double lapse_rate = 0.01;          ///< probability of a random answer (attention lapse)
  rendering::ShapePerception shape;  ///< windows and height threshold
};

/// Draws a participant: force level U(0.8, 2.0) N, stroke speed U(20, 60) mm/s, fluctuation
/// frequencies U(0.05, 0.25) Hz with random weights and phases.
ParticipantProfile sample_participant(std::uint64_t seed);

/// The simulated device and the person's arm (impedance-type device, e.g. a PHANToM).
struct HandDeviceParams {
  double mass_kg = 0.1;            ///< apparent mass of device + hand, kg
  double device_damping = 0.001;   ///< N s/mm
  double arm_stiffness = 0.5;      ///< vertical arm stiffness towards the set point, N/mm
  double arm_damping = 0.005;      ///< N s/mm
  double lateral_stiffness = 1.0;  ///< N/mm
  double lateral_damping = 0.01;   ///< N s/mm
  double force_loop_gain = 75;     ///< set-point speed per N of force error, mm/(N s)
  double max_setpoint_speed = 60;  ///< mm/s
  double approach_speed = 30;      ///< descent before contact, mm/s
  double lift_speed = 80;          ///< mm/s
  double transit_speed = 150;      ///< lateral moves in the air, mm/s
  double contact_force_n = 0.05;   ///< a sensed force above this is contact, N
  int substeps = 5;                ///< physics substeps per servo tick
  double servo_rate_hz = 1000;
  double max_force_n = 6.2;  ///< device saturation, N
};

/// What the participant gathered at one model (diagnostics and tests).
struct CellEvidence {
  std::vector<double> stroke_contrast_mm;    ///< centre-minus-surround HIP height per stroke
  std::vector<double> k_centre, k_surround;  ///< force/displacement stiffness per tap, N/mm
  int label = -1;
};

class VirtualParticipant final : public Device, public rendering::JudgementSource {
 public:
  explicit VirtualParticipant(const ParticipantProfile& profile, const HandDeviceParams& hand = {});
  ~VirtualParticipant() override;
  VirtualParticipant(const VirtualParticipant&) = delete;
  VirtualParticipant& operator=(const VirtualParticipant&) = delete;

  // Device: the simulated device the person holds.
  const DeviceInfo& info() const override;
  double time() const override;
  Vec3 position() const override;
  Vec3 force_sensor() const override;
  void command_force(const Vec3& force) override;
  void tick() override;

  // JudgementSource: the person's keyboard.
  void begin_trial(const rendering::SceneInfo& scene) override;
  std::optional<rendering::Label> poll() override;
  bool quit() const override;

  const ParticipantProfile& profile() const;
  /// Evidence per scene cell of the current (or last) trial.
  const std::vector<CellEvidence>& evidence() const;
  /// Places the device (and the hand's set point) at p at rest, e.g. before a first trial.
  void place(const Vec3& p);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace inhap::lab
