// Contact points from a tapping recording (thesis sec. 3.2): threshold detection on the contact
// force magnitude, then the true contact time by the knee fit (knee.hpp) over the window of N
// samples before detection, and the contact point p(t_c) interpolated between samples.
// Units: time s, positions mm, forces N.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap {

enum class ContactMethod {
  kEstimate,   ///< knee fit over [t_d - N, t_d]: the thesis' true contact estimation
  kThreshold,  ///< p(t_d): the first sample with ||f|| > eps_f (plain thresholding)
};

struct ContactOptions {
  ContactMethod method = ContactMethod::kEstimate;
  double eps_f = 0.2;             ///< contact threshold on ||f||, N
  std::size_t window = 100;       ///< N: samples before the detection used by the knee fit
  std::size_t post = 0;           ///< extra samples after the detection added to the fit window
  std::size_t min_contact = 5;    ///< ||f|| must stay above eps_f this many samples (noise spikes)
  double release_fraction = 0.5;  ///< a tap ends when ||f|| < release_fraction * eps_f
  std::size_t min_window = 8;     ///< fewer samples before detection: fall back to thresholding
  bool refine = true;             ///< continuous refinement of t_c between samples
};

struct Contact {
  std::size_t tap = 0;             ///< 0-based index of the tap in the recording
  std::size_t detect_index = 0;    ///< first sample with ||f|| > eps_f
  double t_detect = 0;             ///< s
  Vec3 p_detect = Vec3::Zero();    ///< probe position at detection, mm
  double t_contact = 0;            ///< estimated true contact time, s (t_detect for Threshold)
  Vec3 point = Vec3::Zero();       ///< contact point p(t_contact), mm
  Vec3 direction = Vec3::UnitZ();  ///< unit direction of the force at its peak (outward normal)
  double peak_force = 0;           ///< max ||f|| during the tap, N
  bool estimated = false;          ///< false when thresholding was used for this tap
};

/// Magnitudes ||f_i||.
std::vector<double> force_magnitudes(std::span<const Vec3> f);

/// Finds every tap in (t, p, f) (same length, t strictly increasing) and its contact point.
/// Never throws on valid spans: no contact gives an empty vector. `notes` (optional) receives
/// one line per tap that was skipped or fell back to thresholding, and why.
std::vector<Contact> detect_contacts(std::span<const double> t, std::span<const Vec3> p,
                                     std::span<const Vec3> f, const ContactOptions& options,
                                     std::vector<std::string>* notes = nullptr);

/// p(tc) linearly interpolated between the samples around tc (clamped to the ends).
Vec3 position_at(std::span<const double> t, std::span<const Vec3> p, double tc);

}  // namespace inhap
