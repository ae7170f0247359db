// User-study protocol (thesis sec. 5.4): sessions, trials, scoring and summaries.
// Units: mm, N, s.
#include "inhap/rendering/experiment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "inhap/core/error.hpp"

namespace inhap::rendering {

const char* to_string(Task t) {
  return t == Task::kShape ? "shape" : "stiffness";
}
const char* to_string(Algorithm a) {
  return a == Algorithm::kTCA ? "tca" : "cba";
}

namespace {

int cell_near(const SceneInfo& scene, const Vec3& hip) {
  int best = -1;
  double best_d2 = scene.highlight_radius_mm * scene.highlight_radius_mm;
  for (std::size_t c = 0; c < scene.cell_centres.size(); ++c) {
    const double d2 = (scene.cell_centres[c] - hip.head<2>()).squaredNorm();
    if (d2 <= best_d2) {
      best_d2 = d2;
      best = static_cast<int>(c);
    }
  }
  return best;
}

// Distortion of one contact episode: HIP height minus true surface height, mean removed.
// Counts only strokes (lateral travel >= min_travel) whose middle lies on a K1-K4 model.
void score_episode(const std::vector<Vec3>& episode, const StudySurface& truth, double min_travel,
                   SessionOutcome& out) {
  if (episode.size() < 2) return;
  double travel = 0;
  for (const Vec3& p : episode)
    travel = std::max(travel, (p.head<2>() - episode.front().head<2>()).norm());
  if (travel < min_travel) return;
  const Vec3& mid = episode[episode.size() / 2];
  const int model = truth.model_at(mid.x(), mid.y());
  if (model < 0 || stiffness_index(model) == 0) return;
  double mean = 0;
  for (const Vec3& p : episode) mean += p.z() - truth.mesh_height(p.x(), p.y());
  mean /= double(episode.size());
  for (const Vec3& p : episode) {
    const double e = p.z() - truth.mesh_height(p.x(), p.y()) - mean;
    out.distortion_sq_sum += e * e;
  }
  out.distortion_samples += static_cast<long>(episode.size());
  ++out.strokes;
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  h ^= h >> 31;
  h *= 0xbf58476d1ce4e5b9ull;
  return h ^ (h >> 29);
}

double sample_sd(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size() - 1));
}

}  // namespace

SessionOutcome run_session(Device& device, JudgementSource& judge, const Model& model,
                           Algorithm algorithm, const SceneInfo& scene, const StudySurface* truth,
                           const SessionConfig& config, TrialObserver* observer) {
  if (scene.cell_centres.empty()) throw Error("run_session: the scene has no models");
  SessionOutcome out;
  out.labels.assign(scene.cell_centres.size(), -1);
  std::size_t labelled = 0;
  State state;
  std::vector<Vec3> episode;
  Vec3 prev_hip = device.position();
  constexpr std::size_t kMaxEpisode = 600000;  // 10 min of contact at 1 kHz
  auto close_episode = [&] {
    if (truth && scene.task == Task::kShape)
      score_episode(episode, *truth, config.min_stroke_travel_mm, out);
    episode.clear();
  };
  judge.begin_trial(scene);
  while (out.ticks < config.max_ticks && !judge.quit()) {
    const Vec3 p = device.position();
    const Vec3 f = step(model, state, p, algorithm);
    device.command_force(f);
    device.tick();
    ++out.ticks;
    if (observer) observer->on_tick(device.time(), p, f, state);
    // A stroke is the part of a contact that slides: pressing down and lifting are left out.
    const double slide_speed = (p - prev_hip).head<2>().norm() * device.info().servo_rate_hz;
    prev_hip = p;
    if (state.collision) {
      if (slide_speed >= config.min_slide_speed_mm_s) episode.push_back(p);
      if (episode.size() >= kMaxEpisode) close_episode();
    } else if (!episode.empty()) {
      close_episode();
    }
    if (const auto label = judge.poll()) {
      const int cell = cell_near(scene, device.position());
      if (cell < 0 || label->task != scene.task) {
        ++out.stray_labels;
      } else {
        if (out.labels[cell] < 0) ++labelled;
        out.labels[cell] = label->value;
        if (labelled == out.labels.size()) {
          out.completed = true;
          break;
        }
      }
    }
  }
  close_episode();
  return out;
}

TrialResult run_trial(Device& device, JudgementSource& judge, const TrialSpec& spec,
                      const ProtocolConfig& config, TrialObserver* observer) {
  TrialResult r;
  r.spec = spec;
  r.layout = shuffled_layout(spec.layout_seed);
  const StudySurface surface(config.dataset, r.layout);
  const Model model(surface.mesh(), config.render);
  SceneInfo scene;
  scene.task = spec.task;
  scene.cell_mm = config.dataset.cell_mm;
  scene.highlight_radius_mm = config.highlight_radius_mm;
  scene.hover_z_mm = config.hover_z_mm;
  for (int c = 0; c < kNumModels; ++c) scene.cell_centres.push_back(surface.cell_centre(c));
  r.session =
      run_session(device, judge, model, spec.algorithm, scene, &surface, config.session, observer);
  r.answer.fill(-1);
  for (int c = 0; c < kNumModels; ++c) r.answer[r.layout.model_at_cell[c]] = r.session.labels[c];
  for (int m = 0; m < kNumModels; ++m) {
    const int truth =
        spec.task == Task::kShape ? int(true_shape_class(m)) : int(true_stiffness_class(m));
    r.correct += r.answer[m] == truth;
  }
  r.time_s = double(r.session.ticks) / device.info().servo_rate_hz;
  return r;
}

std::vector<TrialSpec> participant_schedule(const StudyConfig& config, int participant) {
  std::vector<TrialSpec> specs;
  std::vector<Task> tasks;
  if (config.shape) tasks.push_back(Task::kShape);
  if (config.stiffness) tasks.push_back(Task::kStiffness);
  const Algorithm first = participant % 2 == 0 ? Algorithm::kTCA : Algorithm::kCBA;
  const Algorithm second = first == Algorithm::kTCA ? Algorithm::kCBA : Algorithm::kTCA;
  for (Task task : tasks)
    for (int session = 0; session < 2; ++session)
      for (int trial = 0; trial < config.trials; ++trial) {
        TrialSpec s;
        s.participant = participant;
        s.session = session;
        s.trial = trial;
        s.algorithm = session == 0 ? first : second;
        s.task = task;
        std::uint64_t h = mix(config.seed, 0x5eed);
        h = mix(h, std::uint64_t(participant));
        h = mix(h, std::uint64_t(task == Task::kShape ? 1 : 2));
        h = mix(h, std::uint64_t(session));
        s.layout_seed = mix(h, std::uint64_t(trial));
        specs.push_back(s);
      }
  return specs;
}

const ConditionSummary& StudySummary::get(Algorithm algorithm, Task task) const {
  for (const auto& c : conditions)
    if (c.algorithm == algorithm && c.task == task) return c;
  throw Error(fmt::format("no results for the {} task rendered with {}", to_string(task),
                          to_string(algorithm)));
}

std::vector<int> StudySummary::misjudged_models(Algorithm algorithm, Task task,
                                                double ratio) const {
  const ConditionSummary& c = get(algorithm, task);
  std::vector<int> out;
  for (int m = 0; m < kNumModels; ++m)
    if (c.model_ratio[m] < ratio) out.push_back(m);
  return out;
}

StudySummary summarize(const std::vector<TrialResult>& results) {
  StudySummary s;
  for (Algorithm a : {Algorithm::kTCA, Algorithm::kCBA})
    for (Task t : {Task::kShape, Task::kStiffness}) {
      ConditionSummary c;
      c.algorithm = a;
      c.task = t;
      std::map<int, std::vector<double>> by_participant;
      std::vector<double> all;
      std::array<int, kNumModels> right{};
      double sq = 0;
      for (const TrialResult& r : results) {
        if (r.spec.algorithm != a || r.spec.task != t) continue;
        ++c.trials;
        by_participant[r.spec.participant].push_back(r.correct);
        all.push_back(r.correct);
        for (int m = 0; m < kNumModels; ++m) {
          const int truth =
              t == Task::kShape ? int(true_shape_class(m)) : int(true_stiffness_class(m));
          right[m] += r.answer[m] == truth;
        }
        sq += r.session.distortion_sq_sum;
        c.mean_time_s += r.time_s;
        c.distortion_samples += r.session.distortion_samples;
      }
      if (c.trials == 0) continue;
      c.mean_time_s /= c.trials;
      for (const auto& [p, v] : by_participant)
        c.per_participant.push_back(std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()));
      c.mean = std::accumulate(c.per_participant.begin(), c.per_participant.end(), 0.0) /
               double(c.per_participant.size());
      c.sd_participants = sample_sd(c.per_participant);
      c.sd_trials = sample_sd(all);
      for (int m = 0; m < kNumModels; ++m) c.model_ratio[m] = double(right[m]) / c.trials;
      c.distortion_rms_mm =
          c.distortion_samples > 0 ? std::sqrt(sq / double(c.distortion_samples)) : 0.0;
      s.conditions.push_back(std::move(c));
    }
  return s;
}

}  // namespace inhap::rendering
