// inhap studio: a tapped sample and the session file save_session writes and open_session reads
// (JSON: {"format": "inhap-studio-session", "version": 1, "units": "mm, N, s", "samples": [...]}).
// Units: mm, N, s.
#pragma once

#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "inhap/core/types.hpp"

namespace inhap::studio {

/// A tapped sample with its provenance.
struct Sample {
  long id = 0;
  Vec3 point = Vec3::Zero();      ///< knee-estimated contact point p(t_c), mm
  Vec3 threshold = Vec3::Zero();  ///< p(t_d), the plain threshold point, mm (for comparison)
  Vec3 direction = Vec3::UnitZ();
  double t_contact = 0, peak_force = 0;
  bool estimated = false, deleted = false;
};

/// A sample as the page and the session file see it (without "deleted").
nlohmann::json sample_json(const Sample& s);

/// The samples of a session file's text (any bytes: the file comes from the workspace). Throws
/// ProtocolError naming `name` (quoted as given) and what was expected: not a session file, a
/// sample without an integer id in 0..2^52, a point, threshold or direction not three finite
/// numbers. Ids are unique.
std::vector<Sample> parse_session_file(std::string_view text, std::string_view name);

}  // namespace inhap::studio
