// The one progress mechanism of long library calls (docs/architecture.md, "Dialect"): a callback
// told what is being done, the fraction done in [0, 1] and the estimated seconds left (0:
// unknown). An empty callback means silent. Long calls take it as `progress` (in their options
// struct, or as a parameter); the program forwards it to its progress line, the demo to its
// step progress. Called from the calling thread unless the call says otherwise.
#pragma once

#include <functional>
#include <string>

namespace inhap {

using Progress = std::function<void(const std::string& what, double fraction, double eta_s)>;

}  // namespace inhap
