// inhap studio: one session = the device, the servo loop of the current view and what the views
// edit (tapped samples, the reconstruction, the opened model, the experiment). The server hands
// it every WebSocket message (handle(), on the server's threads); a streamer thread drains the
// servo loop's observer ring, detects taps as they happen (sampling) and broadcasts the state at
// about 125 Hz. The page never reaches the servo thread: the mouse target goes through a seqlock
// (hand_device.hpp), the state comes from the observer ring.
// Units: mm, N, s, N/mm.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "inhap/contact/compensation.hpp"
#include "inhap/contact/detector.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/trimesh.hpp"
#include "inhap/haptics/bridge_device.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/haptics/servo_loop.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/rendering/experiment.hpp"
#include "inhap/studio/hand_device.hpp"
#include "inhap/studio/palpation.hpp"
#include "inhap/studio/protocol.hpp"
#include "inhap/studio/security.hpp"
#include "inhap/studio/session_file.hpp"

namespace inhap::studio {

struct StudioOptions {
  std::string device = "lab:dome";  ///< lab:SCENE or udp[:PORT]
  double speed = 1.0;               ///< lab: simulated seconds per wall second
  std::uint64_t seed = 1;
  bool realtime = false;  ///< ask for SCHED_FIFO + mlockall
  double stream_hz = 125;
  /// udp: mass of the device's tool beyond its force sensor, kg; its weight and inertia are
  /// taken out of the sensed force (recordings, taps, the Model view's object). The lab's is 0.01.
  double tool_mass_kg = 0.0;
  /// Tests only: the n-th file a training writes (counting from 1) fails at its first write, as
  /// an I/O error would (0: off).
  int fail_training_file = 0;
};

/// Finds taps in a stream of (t, p, compensated f), one sample at a time: an episode starts when
/// ||f|| stays above eps_f for min_contact samples and ends when it stays below
/// release_fraction * eps_f for 5 samples; then detect_contacts (the library's knee estimator)
/// runs on that episode with the window before it.
class StreamTapDetector {
 public:
  explicit StreamTapDetector(ContactOptions options = {}) : options_(options) {}
  /// A contact when this sample ended a tap.
  std::optional<Contact> add(double t, const Vec3& p, const Vec3& f);
  const ContactOptions& options() const { return options_; }

 private:
  ContactOptions options_;
  std::vector<double> t_;
  std::vector<Vec3> p_, f_;
  bool in_ = false;
  std::size_t above_ = 0, below_ = 0, start_ = 0;
};

/// A data-driven model for the explore view (thesis 4.4-4.5): the force model, the sliding yield
/// surfaces and the shape, kept together because DataDrivenModel points into them.
struct DataDrivenBundle {
  DataDrivenBundle(datadriven::ForceModel f, friction::SysModel y, const TriMesh& mesh,
                   double probe_radius)
      : force(std::move(f)),
        sys(std::move(y)),
        shape(mesh, probe_radius),
        model(sys, shape, force) {}
  datadriven::ForceModel force;
  friction::SysModel sys;
  friction::MeshSurface shape;
  haptics::DataDrivenModel model;
};

class Session {
 public:
  using Broadcast = std::function<void(const std::string&)>;
  Session(const StudioOptions& options, const Workspace& workspace, Broadcast broadcast);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Starts the first view (sampling). With udp, waits up to connect_s for a device.
  void start(double connect_s = 60);
  void stop();
  /// Median and p90 of the server side of the mouse-to-probe latency, ms ("" when none).
  std::string server_latency() const;
  /// One message from the page: returns the reply (JSON). Never throws; a refused message gets
  /// an error reply and changes nothing.
  std::string handle(std::string_view text);
  std::string mode() const;
  std::size_t live_samples() const;

 private:
  struct Rig;
  std::string dispatch(const Message& m);
  std::string hello() const;
  std::string servo_json() const;
  std::string set_mode(const std::string& mode);
  void start_rig(const std::string& mode);
  void build_rig(Rig& rig, const std::string& mode);
  void stop_rig();
  void stream_loop();
  std::string state_json(const haptics::LoopSample& s) const;
  // sampling
  void on_contact(const Contact& c);
  std::string samples_json() const;
  std::string do_delete(const Message& m);
  std::string do_undo();
  std::string do_reconstruct(const Message& m);
  // outlier filter and jet (quadric) projection previewed, then applied (session_preview.cpp)
  struct Preview {
    std::vector<long> outliers;                // ids the filter would remove
    std::vector<std::pair<long, Vec3>> moves;  // id -> where the jet projection puts it, mm
  };
  Preview compute_preview() const;
  std::string do_preview();
  std::string do_apply_preview();
  std::string do_export(const Message& m);
  std::string do_save_session(const Message& m);
  std::string do_open_session(const Message& m);
  // explore
  std::string do_probe(const Message& m);
  std::string do_open_mesh(const Message& m);
  std::string do_algorithm(const Message& m);
  std::string mesh_json(const TriMesh& mesh, const std::string& role,
                        const std::string& scalar) const;
  // experiment
  std::string do_experiment(const Message& m);
  std::string do_answer(const Message& m);
  std::string do_next_trial();
  std::string trial_json() const;
  std::string progress_json() const;
  void broadcast_trial() const;
  void write_answers() const;
  // palpation (session_palpation.cpp)
  void ensure_palpation_shape();
  std::string do_palpate(const Message& m);
  std::string do_save_sys(const Message& m);
  void stream_palpation(PalpationRenderer& r, bool& fitted);
  void fit_palpation_now(PalpationRenderer& r);

  StudioOptions options_;
  const Workspace& workspace_;
  Broadcast broadcast_;
  lab::Scene scene_;
  bool lab_ = true;
  mutable std::string object_mesh_json_;  // the lab object's top view for the page (cmd_mu_)
  std::unique_ptr<haptics::BridgeDevice> bridge_;

  std::mutex cmd_mu_;           // serialises commands (mode changes, rig rebuilds)
  mutable std::mutex data_mu_;  // samples, latest sample, mesh
  std::unique_ptr<Rig> rig_;
  std::string mode_ = "sampling";
  std::thread streamer_;
  std::atomic<bool> stop_stream_{false};

  // sampling
  std::vector<Sample> samples_;
  struct UndoStep {
    std::vector<long> deleted;                 ///< ids deleted by the step
    std::vector<std::pair<long, Vec3>> moved;  ///< ids moved by the step, with the old point
  };
  std::vector<UndoStep> undo_;
  long next_id_ = 0;
  std::optional<TriMesh> reconstruction_;
  // explore
  TriMesh explore_mesh_;
  std::string explore_name_;
  rendering::Algorithm algorithm_ = rendering::Algorithm::kTCA;
  std::shared_ptr<DataDrivenBundle> data_driven_;  ///< set: explore renders it, not the mesh
  std::uint64_t probe_seq_ = 0;
  // Server side of the page's latency: probe message handled -> state with its seq broadcast.
  std::atomic<std::int64_t> probe_written_ns_{0};
  std::atomic<std::uint64_t> probe_written_seq_{0};
  std::vector<double> server_latency_ms_;  // streamer thread only; printed by stop()
  // experiment
  int participant_ = -1;
  std::vector<rendering::TrialSpec> schedule_;
  std::size_t trial_ = 0;
  std::optional<rendering::StudySurface> surface_;
  struct Answer {
    rendering::TrialSpec spec;
    int cell = 0, model = 0, value = 0, truth = 0;
    double t_s = 0;
  };
  std::vector<Answer> answers_;
  std::array<int, rendering::kNumModels> trial_answers_{};
  haptics::LoopSample latest_;
  bool have_latest_ = false;
  // palpation: the probe-centre shape (lab: the scene's height field, as `sys palpate`; a real
  // device: the sampling view's reconstruction), the points of the run, its cycles and fit
  std::unique_ptr<TriMesh> palp_mesh_;
  std::unique_ptr<friction::MeshSurface> palp_shape_;
  friction::PalpationConfig palp_config_;
  std::vector<Vec3> palp_points_, palp_normals_;
  double palp_speed_ = 1.0;
  std::vector<friction::CycleRecord> palp_cycles_;  // data_mu_
  std::optional<friction::SysModel> sys_;           // data_mu_
  std::string palp_error_;                          // data_mu_
  // the Model view (session_model.cpp): recording, training, feeling the model against the object
  std::string do_model_record(const Message& m);
  std::string do_model_stop();
  std::string do_model_train(const Message& m);
  std::string do_model_cancel();
  std::string do_model_source(const Message& m);
  std::string do_model_blind(const Message& m);
  std::string do_model_answer(const Message& m);
  std::string do_model_stats();
  void build_model_rig(Rig& rig, const std::string& mode);
  void build_bridged_model_rig(Rig& rig, const std::string& mode);
  std::string stop_observed_recording();
  void stream_model(Rig& rig, bool flush);
  /// The proxy of the training: "palpation" (the Palpation view's yield surfaces and shape when
  /// fitted, else the lab scene palpated as `inhap sys palpate`; the recording's proxy then by
  /// `inhap sys proxy`) or "recording" (estimated from the recording, as `inhap model train`
  /// on a recording without proxy columns).
  struct TrainJob {
    std::string recording, out, proxy;
    std::optional<friction::SysModel> sys;  ///< the Palpation view's, when fitted
    std::optional<TriMesh> shape;           ///< its probe-centre shape
  };
  void train_worker(TrainJob job);
  void end_training();
  std::string model_rec_operator_ = "explore", model_rec_path_ = "model-rec.csv";
  double model_rec_seconds_ = 65;
  struct ModelStream;
  std::unique_ptr<ModelStream> model_stream_;  // streamer thread only
  std::thread train_thread_;
  std::atomic<bool> training_{false}, train_cancel_{false};
  std::shared_ptr<DataDrivenBundle> model_bundle_;  // data_mu_
  std::string model_name_;                          // data_mu_
  bool ab_model_ = false;  ///< the compare renderer commands the model (else the object)
  bool ab_blind_ = false;
  bool ab_model_is_b_ = false;  ///< blind trial: which of A/B is the model
  int ab_trial_ = 0, ab_switches_ = 0;
  std::string ab_path_ = "model-ab.csv";
  struct AbAnswer {
    int trial = 0, switches = 0;
    bool model_is_b = false, answer_b = false;
    double t_s = 0;
  };
  std::vector<AbAnswer> ab_answers_;
};

}  // namespace inhap::studio
