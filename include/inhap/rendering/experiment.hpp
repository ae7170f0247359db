// The user-study protocol of thesis sec. 5.4: trials on the 25-model surface with the layout
// reshuffled per trial, rendering with CBA or TCA-MESH at every servo tick, labels routed to the
// model the participant is at, scoring, mean +- SD over participants and per-model ratios.
//
// Written against abstract interfaces only — an inhap::Device (core/device.hpp) and a
// JudgementSource below — so the same code drives the virtual participant of the lab or a real
// haptic device with a keyboard.
//
// Units: positions mm, forces N, stiffness N/mm, time s.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "inhap/core/device.hpp"
#include "inhap/rendering/datasets.hpp"
#include "inhap/rendering/renderer.hpp"

namespace inhap::rendering {

enum class Task { kShape, kStiffness };
const char* to_string(Task t);
const char* to_string(Algorithm a);

/// What the participant is shown (thesis fig. 5.9b): circles where the models are, never which
/// model is where. Heights are not shown (orthographic top view without shading).
struct SceneInfo {
  Task task = Task::kShape;
  std::vector<Vec2> cell_centres;  ///< mm, one circle per model
  double cell_mm = 28.0;
  double highlight_radius_mm = 8.0;  ///< HIP (xy) this close to a centre: that model is current
  double hover_z_mm = 6.0;           ///< a safe height above the whole surface, mm
};

/// A label typed by the participant; it applies to the model the HIP is at when it arrives.
struct Label {
  Task task = Task::kShape;
  int value = 0;  ///< int(ShapeClass) for the shape task, int(StiffnessClass) for stiffness
};

/// Where judgements come from: the virtual participant, or a keyboard beside a real device.
class JudgementSource {
 public:
  virtual ~JudgementSource() = default;
  virtual void begin_trial(const SceneInfo& scene) = 0;
  /// Polled once per servo tick (after Device::tick); a label entered since the last poll.
  virtual std::optional<Label> poll() = 0;
  /// The participant abandons the trial (Esc on a keyboard; a virtual program that ended).
  virtual bool quit() const { return false; }
};

/// Optional per-tick hook (progress display, trajectory logging).
class TrialObserver {
 public:
  virtual ~TrialObserver() = default;
  virtual void on_tick(double time_s, const Vec3& hip, const Vec3& force, const State& state) = 0;
};

/// One rendered session on a fixed model: what run_session returns.
struct SessionOutcome {
  std::vector<int> labels;  ///< per cell: the last label value given there, -1 if none
  long ticks = 0;
  long stray_labels = 0;   ///< labels given away from every model or for the other task
  bool completed = false;  ///< every cell labelled
  // Shape distortion over strokes on K1-K4 models (needs ground truth): sum of squared HIP
  // height minus true surface height, each stroke's mean removed, and the sample count. A
  // stroke is a contact's sliding part (lateral speed >= min_slide_speed_mm_s).
  double distortion_sq_sum = 0;
  long distortion_samples = 0;
  long strokes = 0;
};

struct SessionConfig {
  long max_ticks = 30L * 60 * 1000;  ///< give up after 30 min at 1 kHz
  double min_stroke_travel_mm = 10;  ///< contact episodes with less lateral travel are taps
  double min_slide_speed_mm_s = 5;   ///< contact samples moving slower are pressing or lifting
};

/// Runs until every cell is labelled, the source quits or max_ticks: each tick reads the HIP,
/// renders, commands the force, ticks the device, polls the source. `truth` (optional) is the
/// ground truth for the distortion metric.
SessionOutcome run_session(Device& device, JudgementSource& judge, const Model& model,
                           Algorithm algorithm, const SceneInfo& scene,
                           const StudySurface* truth = nullptr, const SessionConfig& config = {},
                           TrialObserver* observer = nullptr);

// ---------------------------------------------------------------------------------------------
struct TrialSpec {
  int participant = 0;
  int session = 0;  ///< 0 or 1: the two main sessions of one experiment (one per algorithm)
  int trial = 0;    ///< 0..trials-1 within the session
  Algorithm algorithm = Algorithm::kTCA;
  Task task = Task::kShape;
  std::uint64_t layout_seed = 1;
};

struct TrialResult {
  TrialSpec spec;
  Layout layout;
  std::array<int, kNumModels> answer{};  ///< by model id: the label value, -1 if none
  int correct = 0;                       ///< out of 25
  double time_s = 0;
  SessionOutcome session;
};

struct ProtocolConfig {
  DatasetParams dataset;
  Params render;  ///< a_s = 0.05, a_t = 0.5 as in the thesis
  double highlight_radius_mm = 8.0;
  double hover_z_mm = 6.0;
  SessionConfig session;
};

/// One trial: builds the surface for the spec's layout, renders it with the spec's algorithm,
/// scores the answers against Table 5.1.
TrialResult run_trial(Device& device, JudgementSource& judge, const TrialSpec& spec,
                      const ProtocolConfig& config = {}, TrialObserver* observer = nullptr);

struct StudyConfig {
  int participants = 16;
  int trials = 5;  ///< per session
  std::uint64_t seed = 1;
  bool shape = true, stiffness = true;
};

/// The thesis order for one participant: the shape experiment, then the stiffness experiment;
/// each has two main sessions (TCA-MESH and CBA, order balanced: even participants start with
/// TCA-MESH) of `trials` trials, each trial with its own layout seed derived from
/// (seed, participant, task, session, trial). The training sessions are not simulated.
std::vector<TrialSpec> participant_schedule(const StudyConfig& config, int participant);

// ---------------------------------------------------------------------------------------------
struct ConditionSummary {
  Algorithm algorithm = Algorithm::kTCA;
  Task task = Task::kShape;
  int trials = 0;
  double mean = 0;             ///< mean over participants of their mean correct count (of 25)
  double sd_participants = 0;  ///< SD of the participants' means
  double sd_trials = 0;        ///< SD over all trials
  std::vector<double> per_participant;
  std::array<double, kNumModels> model_ratio{};  ///< fraction of trials model M was right
  double mean_time_s = 0;                        ///< mean trial completion time (simulated), s
  double distortion_rms_mm = 0;                  ///< shape task: RMS over strokes on K1-K4 models
  long distortion_samples = 0;
};

struct StudySummary {
  std::vector<ConditionSummary> conditions;
  /// Throws Error when the condition was not run.
  const ConditionSummary& get(Algorithm algorithm, Task task) const;
  /// Models whose correct ratio under (algorithm, task) is below `ratio`.
  std::vector<int> misjudged_models(Algorithm algorithm, Task task, double ratio = 0.5) const;
};

StudySummary summarize(const std::vector<TrialResult>& results);

}  // namespace inhap::rendering
