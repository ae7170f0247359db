// From a recording to the model's inputs: proxy tracks, FOAW velocities, training sets and
// replay through the servo renderer.
//
// Units: positions mm, velocities mm/s, forces N, time s.
//
// The proxy q can come from anywhere: a recording's qx,qy,qz columns (written by the
// friction module's proxy estimator), the virtual lab's ground truth, or the pre-thesis
// baseline q = p at contact onset. A ProxyTrack carries q and the contact flag per sample and
// says where they came from.
#pragma once

#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {

struct ProxyTrack {
  std::vector<Vec3> q;        ///< mm (meaningful where contact)
  std::vector<char> contact;  ///< 1 in contact
  /// Outward unit surface normal at q per sample (from the proxy estimator's frame or a shape
  /// mesh); empty when unknown (only FeatureSet::kLocalFrame needs it).
  std::vector<Vec3> n;
  std::string proxy_source;    ///< "columns", "truth", "entry", ...
  std::string contact_source;  ///< "column:contact", "force>0.05N", "truth", ...
  std::size_t size() const { return q.size(); }
};

/// q from the recording's columns <prefix>x, <prefix>y, <prefix>z; contact from the column
/// `contact_column` when present (non-zero = contact), else ||f|| > force_threshold (N).
/// Throws ParseError naming `path` when the q columns are missing.
ProxyTrack proxy_from_columns(const Recording& rec, const std::string& path,
                              const std::string& prefix = "q",
                              const std::string& contact_column = "contact",
                              double force_threshold = 0.05);

/// Pre-thesis baseline "(p, pdot) only": q = p for every sample, so the features carry no
/// elastic displacement and no proxy (one bin; the model sees (0, p, pdot)).
ProxyTrack position_only_track(const Recording& rec, const std::vector<char>& contact,
                               const std::string& contact_source);

/// Pre-thesis baseline: q = probe centre at the onset of each contact, held during it.
ProxyTrack entry_proxy_track(const Recording& rec, const std::vector<char>& contact,
                             const std::string& contact_source);

/// FOAW velocities of a whole position track (mm/s), as the servo filter computes them.
std::vector<Vec3> foaw_velocities(const std::vector<Vec3>& p, const FoawParams& params);

/// Median time step of a recording, s (1e-3 when it has fewer than two samples).
double median_dt(const Recording& rec);

/// In-contact samples (p, FOAW pdot, q, f) of a recording. Throws Error on a size mismatch.
TrainingSet make_training_set(const Recording& rec, const ProxyTrack& proxy,
                              const FoawParams& foaw);

/// Replays a recording through servo_step, one tick per sample: rendered forces (N). With
/// `step_us`, also the wall time of each in-contact step (us, steady clock), in sample order.
std::vector<Vec3> replay(const ForceModel& model, const Recording& rec, const ProxyTrack& proxy,
                         std::vector<double>* step_us = nullptr);

}  // namespace inhap::datadriven
