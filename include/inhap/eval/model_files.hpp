// The data-driven force model (thesis 4.4-4.5) on recording files: what `inhap model train`,
// `model eval` and `model render` do between reading their flags and writing their outputs.
// Units: positions mm, forces N, times s.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/datadriven/dataset.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/datadriven/metrics.hpp"
#include "inhap/eval/progress.hpp"
#include "inhap/eval/recordings.hpp"

namespace inhap::eval {

/// Where a recording keeps its proxy: columns <prefix>x,y,z (mm) and a contact column, or
/// |f| above `contact_threshold_n` when that column is absent.
struct ProxyColumnsSpec {
  std::string prefix = "q", contact_column = "contact";
  double contact_threshold_n = 0.05;
};

/// The proxy track of a recording read from `path` (ParseError naming it when q is missing).
datadriven::ProxyTrack track_of(const Recording& rec, const std::string& path,
                                const ProxyColumnsSpec& o);

/// True when the recording has the normal columns nx,ny,nz.
bool has_normal_columns(const Recording& rec);

/// Normals at q for local-frame models: columns nx,ny,nz when the recording has them, else the
/// outward normal of the shape mesh file `mesh` (probe-centre surface) closest to q. ParseError
/// naming `path` when there are neither.
void add_normals(datadriven::ProxyTrack& t, const Recording& rec, const std::string& path,
                 const std::string& mesh);
/// The same with the shape mesh in memory (normal columns ignored): the outward normal of `mesh`
/// closest to q in contact, +z elsewhere.
void add_normals(datadriven::ProxyTrack& t, const TriMesh& mesh);

/// What `model train` was asked: a preset, and every option given explicitly (by long name,
/// "--bins", ...; the values in `params`, `design`, `features`, `above_range`).
struct TrainRequest {
  std::string preset = "best", above_range = "keep";
  std::string design = to_string(datadriven::preset_params("best").design), features = "local";
  datadriven::TrainParams params = datadriven::preset_params("best");
  std::set<std::string> given;
};

/// The preset's settings, overridden by every option given explicitly. Without normals the
/// default local-frame pipeline cannot run: the "world" preset is used instead unless local
/// features were asked for explicitly; `note` then says so (else it is left alone).
datadriven::TrainParams resolve_train_params(const TrainRequest& r, bool have_normals,
                                             std::string* note);

/// One line on the forces above the modeling range and above the render clamp.
std::string range_note(const datadriven::ForceModelProvenance& m,
                       const datadriven::TrainingSet& set, double force_limit_n);

/// Writes where the recording covered the object (coverage file `path`) and says it: one line,
/// and one more with the largest unvisited gaps when there are any.
std::vector<std::string> write_training_coverage(const datadriven::TrainingSet& set,
                                                 const std::string& path);

struct TrainFileOptions {
  std::string recording, sys, mesh;  ///< files; sys and mesh optional (referenced in the model)
  RecordingUnits units;              ///< of the recording's t and p columns
  TrainRequest request;
  datadriven::FoawParams foaw;  ///< max_window is set from velocity_window_s unless given
  /// FOAW window cap in seconds (samples = window / median dt): the same filter at any rate.
  double velocity_window_s = 0.016;
  /// Used when the recording has no proxy columns: the surface, proxy and friction are
  /// estimated from it (estimate.hpp).
  datadriven::EstimateParams estimate;
  double force_limit_n = kDeviceForceLimitN;
  ProxyColumnsSpec proxy;
  Progress progress;  ///< "train", fraction, eta s
  /// Told each note as it arises (before the long training), e.g. to print it; may be empty.
  std::function<void(const std::string&)> on_note;
};

struct TrainFileResult {
  datadriven::TrainedForceModel model;  ///< with its provenance (references, proxy source)
  datadriven::TrainingSet set;
  /// With an estimated proxy, the samples the baselines are fitted on: the recording's samples
  /// pressing with |f| above the contact threshold, the rule a test recording is scored by (the
  /// model's set keeps those in contact with the estimated surface; the baselines should not
  /// depend on it). Empty otherwise: the baselines use `set`.
  std::optional<datadriven::TrainingSet> baseline_set;
  /// The samples the baselines are fitted on.
  const datadriven::TrainingSet& baselines() const { return baseline_set ? *baseline_set : set; }
  std::vector<std::string> notes;  ///< what the program says on stderr, in order
  /// What was estimated when the recording had no proxy (the caller writes its surface mesh and
  /// yield surfaces beside the model and references them).
  std::optional<datadriven::RecordingEstimate> estimate;
};

/// Writes the estimate's surface mesh (<model stem>.surface.ply) and yield surfaces
/// (<model stem>.sys.json) beside the model file `model_path` and makes the model reference them
/// (by file name, found beside the model). Returns the two paths.
std::vector<std::string> write_estimate_files(const std::string& model_path,
                                              const datadriven::RecordingEstimate& e,
                                              datadriven::ForceModelProvenance& m);

/// Reads the recording, builds the training set and trains (the model is not written).
TrainFileResult train_from_file(const TrainFileOptions& o);

/// The same on a recording in memory, its t and p already in s and mm (convert_units; `o.units`
/// are recorded as the source's): `o.recording` only names it in messages, and the model's
/// provenance names no training file.
TrainFileResult train_from_recording(const Recording& rec, const TrainFileOptions& o);

/// The model's training report: samples, features, bins, design, non-zeros per axis, then the
/// l1 fit's certificate per bin and axis (and the CPU time per stage when `verbose`).
std::string train_summary(const datadriven::TrainedForceModel& m, bool verbose);

/// The mesh a local-frame model needs: `mesh_flag`, else the model's reference (its provenance),
/// taken as written (relative to the current folder) or relative to the model file's folder.
/// Error otherwise.
std::string model_mesh(const std::string& model_path, const std::string& mesh_flag,
                       const datadriven::ForceModelProvenance& m);

struct ReplayedFile {
  Recording rec;
  datadriven::ProxyTrack track;
  std::vector<Vec3> forces;  ///< rendered, N
};

/// A model and where what its replay and evaluation need besides itself comes from: the files
/// its provenance names (found beside the model file `path`), or what a training in memory
/// kept (`estimate`, `set`), or a shape mesh given by the caller (`mesh`, else `mesh_flag`).
struct ModelSource {
  const datadriven::TrainedForceModel* model = nullptr;
  std::string path;  ///< the model file; empty for a model in memory
  /// The estimated surface and yield surfaces of a training in memory (estimated proxy).
  const datadriven::RecordingEstimate* estimate = nullptr;
  /// The training samples of a training in memory: the training support (and the baselines
  /// unless baseline_set is given).
  const datadriven::TrainingSet* set = nullptr;
  const datadriven::TrainingSet* baseline_set = nullptr;  ///< TrainFileResult::baseline_set
  std::string mesh_flag;          ///< a shape mesh file given explicitly (--mesh)
  const TriMesh* mesh = nullptr;  ///< a shape mesh in memory (before mesh_flag)
};

/// replay_track for any model source; `recording` names `rec` in messages.
datadriven::ProxyTrack replay_track(const ModelSource& m, const Recording& rec,
                                    const std::string& recording, const ProxyColumnsSpec& proxy);

/// Replays a recording in memory (t s, p mm) through the servo renderer.
ReplayedFile replay_recording(const ModelSource& m, Recording rec, const std::string& recording,
                              const ProxyColumnsSpec& proxy);

/// The proxy track a model is replayed with: the probe itself for prefix "p"; the estimated proxy
/// (the model's surface mesh and yield surfaces) when the model was trained on one; else the
/// recording's proxy columns (normals from its columns or the model's mesh for local features).
datadriven::ProxyTrack replay_track(const std::string& model_path,
                                    const datadriven::TrainedForceModel& m, const Recording& rec,
                                    const std::string& recording, const ProxyColumnsSpec& proxy,
                                    const std::string& mesh_flag);

/// The samples a replay is scored on: measured contact (|f| above the threshold) for an
/// estimated proxy, else the track's contact.
std::vector<char> scored_samples(const Recording& rec, const datadriven::ProxyTrack& t,
                                 const ProxyColumnsSpec& proxy);

/// The samples the baselines are fitted on, from a training recording and its proxy track: those
/// of scored_samples (with an estimated proxy, |f| above the contact threshold, not the contact
/// with the estimated surface), p, FOAW velocity and f.
datadriven::TrainingSet baseline_samples(const Recording& rec, datadriven::ProxyTrack track,
                                         const datadriven::FoawParams& foaw,
                                         const ProxyColumnsSpec& proxy);

/// Replays a recording file through the servo renderer (normals from its columns, else from the
/// model's mesh or `mesh_flag`).
ReplayedFile replay_file(const std::string& model_path, const datadriven::TrainedForceModel& m,
                         const std::string& recording, const ProxyColumnsSpec& proxy,
                         const std::string& mesh_flag, const RecordingUnits& units = {});

/// Shares of the in-contact samples outside the training support of the coverage file beside the
/// model (unknown when there is none).
struct SupportShare {
  bool known = false;
  std::string file;
  double outside_share = 0, outside_position_share = 0;
};
SupportShare support_share(const std::string& model_path, const ReplayedFile& r);
/// The same for any model source: the training samples in memory (file empty), else the coverage
/// file beside the model file.
SupportShare support_share(const ModelSource& m, const ReplayedFile& r);
/// The line the program prints about it.
std::string support_note(const SupportShare& s);

/// `model eval`: errors of the in-contact samples (eq. 4.27-4.31) and the report JSON.
struct ModelEvalResult {
  datadriven::ForceErrors errors;
  std::size_t contact_samples = 0, above_force_limit = 0;
  double force_limit_n = 0;  ///< the model's render clamp
  SupportShare support;
  std::optional<BaselineReport> baselines;  ///< when the training recording was found
  std::string baselines_note;               ///< why there are none
  nlohmann::ordered_json json;
};
/// With `train` (a recording file; default: the training recording the model names, when it is
/// found) the baselines fitted on it are scored on the same samples.
ModelEvalResult evaluate_model_file(const std::string& model_path, const std::string& recording,
                                    const ProxyColumnsSpec& proxy, const std::string& mesh_flag,
                                    const RecordingUnits& units = {},
                                    const std::string& train = {});
/// `model eval` of a replay `r` of the recording named `recording`. The baselines are fitted on
/// `train` (a recording in memory, t s and p mm, named `train_name`) when given, else on the
/// training samples in memory (`m.set`), else on the training recording the model file names.
ModelEvalResult evaluate_model(const ModelSource& m, const ReplayedFile& r,
                               const std::string& recording, const ProxyColumnsSpec& proxy,
                               const Recording* train = nullptr,
                               const std::string& train_name = {});
/// The lines `model eval` prints: RMSE, median AE and RE of the contact samples, and how many
/// were measured above the render clamp.
std::string model_eval_text(const ModelEvalResult& r);

/// `model render`'s CSV: t, p, the rendered force f, the measured force mf, contact (0/1);
/// comments name the recording and the model file.
void write_rendered_csv(const std::string& out, const ReplayedFile& r, const std::string& recording,
                        const std::string& model_path);

}  // namespace inhap::eval
