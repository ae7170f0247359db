// Contact points of a tapping recording; see tapping.hpp.
#include "inhap/contact/tapping.hpp"

#include <fmt/format.h>

#include "inhap/core/error.hpp"

namespace inhap {

TappingResult contacts_from_recording(const Recording& rec, const ContactOptions& options,
                                      ForceSource source) {
  TappingResult out;
  const auto* rx = rec.find_extra("rfx");
  const auto* ry = rec.find_extra("rfy");
  const auto* rz = rec.find_extra("rfz");
  const bool has_raw = rx && ry && rz;
  if (source == ForceSource::kRaw && !has_raw)
    throw Error(
        "recording has no rfx,rfy,rfz columns: expected raw sensor columns for --force raw");
  out.source = source == ForceSource::kAuto ? (has_raw ? ForceSource::kRaw : ForceSource::kRecorded)
                                            : source;
  // Outliers first: a sample no device gives (one at 1e308 moved the fitted tool mass by 13 %
  // and added a tap) is dropped and counted before the compensation sees it.
  constexpr double kMaxPositionMm = 1e4, kMaxForceN = 1e3;
  std::vector<double> t;
  std::vector<Vec3> p, f, raw;
  std::vector<std::size_t> row;  // the recording's row of each kept sample
  std::size_t rejected = 0;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const Vec3 r = has_raw ? Vec3((*rx)[i], (*ry)[i], (*rz)[i]) : Vec3::Zero();
    if (rec.p[i].cwiseAbs().maxCoeff() > kMaxPositionMm ||
        rec.f[i].cwiseAbs().maxCoeff() > kMaxForceN || r.cwiseAbs().maxCoeff() > kMaxForceN) {
      ++rejected;
      continue;
    }
    t.push_back(rec.t[i]), p.push_back(rec.p[i]), f.push_back(rec.f[i]), raw.push_back(r);
    row.push_back(i);
  }
  out.rejected = rejected;
  if (rejected > 0)
    out.notes.push_back(fmt::format(
        "{} samples rejected as outliers before compensation (|p| > {:g} mm or |f| > {:g} N)",
        rejected, kMaxPositionMm, kMaxForceN));
  if (out.source == ForceSource::kRaw) {
    out.compensation = fit_offline_compensation(t, p, raw);
    f = apply_offline_compensation(raw, estimate_acceleration(t, p, 8), out.compensation);
  }
  out.contacts = detect_contacts(t, p, f, options, &out.notes);
  for (Contact& c : out.contacts)
    if (c.detect_index < row.size()) c.detect_index = row[c.detect_index];
  if (out.contacts.empty())
    out.notes.push_back(
        fmt::format("no contact found: ||f|| never stayed above {} N for {} samples", options.eps_f,
                    options.min_contact));
  return out;
}

}  // namespace inhap
