// The one progress mechanism of the experiments (and the rule for new code; docs/
// architecture.md, "Dialect"): a callback told what is being done, the fraction done in [0, 1]
// and the estimated seconds left (0: unknown). An empty callback means silent. Long library
// calls take it in their options struct as `progress`; the program forwards it to its progress
// line (apps/inhap/command.hpp, cli::progress), the demo to its step progress.
#pragma once

#include <functional>
#include <string>

namespace inhap::eval {

using Progress = std::function<void(const std::string& what, double fraction, double eta_s)>;

}  // namespace inhap::eval
