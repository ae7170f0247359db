// `inhap eval forces` (thesis 4.5 on the lab, forces_lab.hpp): the line it prints per object and
// the head of its report. Units: forces N, times s, step times us.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "inhap/eval/forces_lab.hpp"

namespace inhap::eval {

/// One line: RMSE and median AE per axis (N), RE mean / median, sliding-only RE median with and
/// without the proxy and with the onset proxy, training time, servo step p50 / p99 (us), proxy
/// source and palpation time, the share outside the training range and its SSE shares.
std::string force_lab_summary(const ForceLabResult& d);

/// The report's head: units, physics, proxy and contact sources and what they mean; the caller
/// adds "objects" (force_lab_json per object).
nlohmann::ordered_json forces_report_head(const std::string& physics, const std::string& proxy);

}  // namespace inhap::eval
