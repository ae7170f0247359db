// The proxy estimator over a whole recording (thesis 4.3.1): one proxy_step per sample, in
// order, dt = t[i] - t[i-1] (0 for the first sample). Units: mm, s.
//
// This is the batch form of the servo loop, for training sets, `inhap sys proxy` and the
// evaluations; it gives the same numbers tick for tick as running proxy_step (or
// haptics::step) live on the same samples.
#pragma once

#include <cstddef>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/types.hpp"
#include "inhap/friction/proxy_estimator.hpp"

namespace inhap::friction {

/// Per-sample output of proxy_track (all vectors have the recording's length).
struct ProxyColumns {
  std::vector<Vec3> q;        ///< ProxyOutput::q: the proxy in contact, else p, mm
  std::vector<Vec3> n;        ///< ProxyOutput::n: outward unit normal at q (+z out of contact)
  std::vector<char> contact;  ///< 1 in (geometric) contact
  std::vector<char> sliding;  ///< 1 when the proxy moved at that sample
  std::size_t contact_count = 0, sliding_count = 0;
  std::size_t size() const { return q.size(); }
};

/// Runs a fresh ProxyState through the recording's positions (rec.t, rec.p).
ProxyColumns proxy_track(const ProxyModel& model, const Recording& rec);

}  // namespace inhap::friction
