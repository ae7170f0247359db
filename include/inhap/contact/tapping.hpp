// Contact points of a whole tapping recording (CSV, see core/csv.hpp): drops outliers (counted),
// chooses the contact force, then runs the detector (detector.hpp). Units: time s, positions mm,
// forces N.
#pragma once

#include <string>
#include <vector>

#include "inhap/contact/detector.hpp"
#include "inhap/contact/offline_compensation.hpp"
#include "inhap/core/csv.hpp"

namespace inhap {

enum class ForceSource {
  kAuto,      ///< Raw when the recording has rfx,rfy,rfz columns, else Recorded
  kRecorded,  ///< the fx,fy,fz columns as the contact force (already compensated)
  kRaw,       ///< rfx,rfy,rfz compensated offline (offline_compensation.hpp); Error if absent
};

struct TappingResult {
  std::vector<Contact> contacts;
  std::vector<std::string> notes;               ///< skipped taps, fallbacks, "no contact found"
  ForceSource source = ForceSource::kRecorded;  ///< what was used
  OfflineCompensation compensation;             ///< when source == Raw
  /// Samples dropped as outliers before compensation (|p| > 1e4 mm or |f| > 1e3 N; a note says
  /// how many).
  std::size_t rejected = 0;
};

TappingResult contacts_from_recording(const Recording& rec, const ContactOptions& options,
                                      ForceSource source = ForceSource::kAuto);

}  // namespace inhap
