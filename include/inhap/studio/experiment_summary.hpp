// inhap studio: the experimenter's view of the saved answers (thesis fig. 5.10-5.11). The
// participant CSVs the Experiment view writes are read back into rendering::TrialResult and scored
// by rendering::summarize, the code that scores the virtual study (eval tca, the demo).
// Units: none (counts of correct models out of 25, ratios).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/rendering/experiment.hpp"
#include "inhap/studio/security.hpp"

namespace inhap::studio {

/// One TrialResult per (participant, task, session, trial) found in a participant CSV
/// (participant,session,trial,algorithm,task,layout_seed,cell,model,label,truth,correct,t).
/// `correct` counts the models whose last label equals the truth (unanswered models are wrong).
/// Throws ParseError (file, line, what was expected) on a malformed row.
std::vector<rendering::TrialResult> read_answers(const std::filesystem::path& csv);

/// Every participant-*.csv in `folder`, summarised: per condition (algorithm x task) the trials,
/// the mean correct count and its SDs (fig. 5.10), the per-model correct ratio (fig. 5.11), and
/// the models below 0.5.
nlohmann::json summarize_answers(const std::filesystem::path& folder);
/// The same for the workspace, every file opened through its guard (a symlink is refused).
nlohmann::json summarize_answers(const Workspace& workspace);

}  // namespace inhap::studio
