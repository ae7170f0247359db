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
  std::vector<Vec3> f = rec.f;
  if (out.source == ForceSource::kRaw) {
    std::vector<Vec3> raw(rec.size());
    for (std::size_t i = 0; i < rec.size(); ++i) raw[i] = Vec3((*rx)[i], (*ry)[i], (*rz)[i]);
    out.compensation = fit_offline_compensation(rec.t, rec.p, raw);
    f = apply_offline_compensation(raw, estimate_acceleration(rec.t, rec.p, 8), out.compensation);
  }
  out.contacts = detect_contacts(rec.t, rec.p, f, options, &out.notes);
  if (out.contacts.empty())
    out.notes.push_back(
        fmt::format("no contact found: ||f|| never stayed above {} N for {} samples", options.eps_f,
                    options.min_contact));
  return out;
}

}  // namespace inhap
