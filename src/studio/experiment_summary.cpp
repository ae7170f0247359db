#include "inhap/studio/experiment_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "inhap/core/error.hpp"

namespace fs = std::filesystem;

namespace inhap::studio {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(f);
  return out;
}

long to_long(const std::string& s, const std::string& file, std::size_t line, const char* what) {
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size())
    throw ParseError(file, line,
                     fmt::format("expected an integer {}, got \"{}\"", what, s.substr(0, 40)));
  return v;
}

}  // namespace

std::vector<rendering::TrialResult> read_answers(const fs::path& csv) {
  const std::string file = csv.string();
  std::ifstream in(csv);
  if (!in) throw IoError(file, "cannot open");
  using Key = std::tuple<int, int, int, int>;  // participant, task, session, trial
  std::map<Key, rendering::TrialResult> trials;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#' || line.rfind("participant,", 0) == 0) continue;
    const auto f = split(line);
    if (f.size() != 12)
      throw ParseError(file, n,
                       fmt::format("expected 12 comma-separated fields, got {}", f.size()));
    rendering::TrialSpec spec;
    spec.participant = int(to_long(f[0], file, n, "participant"));
    spec.session = int(to_long(f[1], file, n, "session"));
    spec.trial = int(to_long(f[2], file, n, "trial"));
    if (f[3] != rendering::to_string(rendering::Algorithm::kTCA) &&
        f[3] != rendering::to_string(rendering::Algorithm::kCBA))
      throw ParseError(file, n,
                       fmt::format("expected an algorithm name, got \"{}\"", f[3].substr(0, 40)));
    spec.algorithm = f[3] == rendering::to_string(rendering::Algorithm::kTCA)
                         ? rendering::Algorithm::kTCA
                         : rendering::Algorithm::kCBA;
    if (f[4] != rendering::to_string(rendering::Task::kShape) &&
        f[4] != rendering::to_string(rendering::Task::kStiffness))
      throw ParseError(file, n,
                       fmt::format("expected a task name, got \"{}\"", f[4].substr(0, 40)));
    spec.task = f[4] == rendering::to_string(rendering::Task::kShape) ? rendering::Task::kShape
                                                                      : rendering::Task::kStiffness;
    const long model = to_long(f[7], file, n, "model");
    const long label = to_long(f[8], file, n, "label");
    if (model < 1 || model > rendering::kNumModels)
      throw ParseError(file, n,
                       fmt::format("expected a model 1-{}, got {}", rendering::kNumModels, model));
    if (label < 0 || label > 2)
      throw ParseError(file, n, fmt::format("expected a label 0-2, got {}", label));
    const Key key{spec.participant, int(spec.task), spec.session, spec.trial};
    auto [it, fresh] = trials.try_emplace(key);
    if (fresh) {
      it->second.spec = spec;
      it->second.answer.fill(-1);
    }
    it->second.answer[static_cast<std::size_t>(model - 1)] = int(label);  // the last label counts
  }
  std::vector<rendering::TrialResult> out;
  for (auto& [key, r] : trials) {
    r.correct = 0;
    for (int m = 0; m < rendering::kNumModels; ++m) {
      const int truth = r.spec.task == rendering::Task::kShape
                            ? int(rendering::true_shape_class(m))
                            : int(rendering::true_stiffness_class(m));
      r.correct += r.answer[static_cast<std::size_t>(m)] == truth;
    }
    out.push_back(r);
  }
  return out;
}

namespace {

bool answers_file(const std::string& name) {
  return name.rfind("participant-", 0) == 0 && fs::path(name).extension() == ".csv";
}

nlohmann::json score(const std::vector<rendering::TrialResult>& all,
                     std::vector<std::string> files);

}  // namespace

nlohmann::json summarize_answers(const fs::path& folder) {
  std::vector<rendering::TrialResult> all;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || !answers_file(name)) continue;
    files.push_back(name);
    for (auto& r : read_answers(e.path())) all.push_back(std::move(r));
  }
  return score(all, std::move(files));
}

nlohmann::json summarize_answers(const Workspace& workspace) {
  // Every read through the workspace guard: a participant file that is a symlink is refused
  // (an error naming it), not followed.
  std::vector<rendering::TrialResult> all;
  std::vector<std::string> files;
  for (const std::string& name : workspace.list()) {
    if (!answers_file(name)) continue;
    files.push_back(name);
    const WorkspacePath in = workspace.input(name);
    for (auto& r : with_names({&in}, [&] { return read_answers(in.path()); }))
      all.push_back(std::move(r));
  }
  return score(all, std::move(files));
}

namespace {

nlohmann::json score(const std::vector<rendering::TrialResult>& all,
                     std::vector<std::string> files) {
  std::sort(files.begin(), files.end());
  const rendering::StudySummary s = rendering::summarize(all);
  nlohmann::json conditions = nlohmann::json::array();
  for (const auto& c : s.conditions) {
    std::vector<int> below;
    for (int m = 0; m < rendering::kNumModels; ++m)
      if (c.model_ratio[static_cast<std::size_t>(m)] < 0.5) below.push_back(m + 1);
    conditions.push_back({{"algorithm", rendering::to_string(c.algorithm)},
                          {"task", rendering::to_string(c.task)},
                          {"trials", c.trials},
                          {"mean", c.mean},
                          {"sd_participants", c.sd_participants},
                          {"sd_trials", c.sd_trials},
                          {"model_ratio", c.model_ratio},
                          {"below_half", below}});
  }
  return {
      {"type", "summary"}, {"files", files}, {"trials", all.size()}, {"conditions", conditions}};
}

}  // namespace

}  // namespace inhap::studio
