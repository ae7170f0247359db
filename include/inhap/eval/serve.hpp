// The device, renderer and session recorder behind `inhap serve` and `inhap record`: built from
// typed options (the flag values), so a program or a test gets the same wiring as the command.
//
// Units: mm, N, N/mm, s.
//
// Error messages name the flags of `inhap serve` (--device, --render, --max-force, ...), which
// carry these options one to one.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "inhap/contact/compensation.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/device.hpp"
#include "inhap/datadriven/force_model.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/haptics/bridge_device.hpp"
#include "inhap/haptics/data_driven.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/haptics/servo_loop.hpp"
#include "inhap/lab/operated_device.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/rendering/renderer.hpp"

namespace inhap::eval {

/// What to render (the flags --render, --mesh, --model, --sys, --shape, --probe-radius).
struct RendererOptions {
  std::string render = "tca";     ///< tca | cba (mesh with stiffness) | model (data-driven) | none
  std::string mesh;               ///< tca, cba: PLY/OBJ with a 'stiffness' vertex property (N/mm)
  std::string model, sys, shape;  ///< model: force model JSON, sys.json, shape mesh
  double probe_radius_mm = 0;     ///< model: probe radius of the shape surface, mm
};

/// The chosen renderer and everything it refers to (kept alive as long as the renderer).
struct RenderSetup {
  std::unique_ptr<rendering::Model> mesh_model;
  std::unique_ptr<datadriven::ForceModel> force;
  std::unique_ptr<friction::SysModel> sys;
  std::unique_ptr<friction::MeshSurface> shape;
  std::unique_ptr<haptics::DataDrivenModel> dd_model;
  std::unique_ptr<haptics::Renderer> renderer;
};

/// Reads the files the renderer needs and builds it. Throws inhap::Error on a missing file flag
/// or an unknown renderer, ParseError / IoError on a bad file.
RenderSetup make_renderer(const RendererOptions& options);

/// Which device (the flags --device, --listen, --key, --key-file, --max-force, --rate,
/// --tool-mass, --probe-radius, --timeout, --seconds, --operator, --seed, --physics).
struct DeviceOptions {
  std::string device = "udp";  ///< udp, udp:PORT (the bridge) or lab:SCENE (the virtual lab)
  std::string listen = "127.0.0.1";
  std::string key, key_file;  ///< shared secret, or the file whose first line is it
  double max_force_n = 6.2;   ///< device force limit, N (at most kForceCeilingN)
  double rate_hz = 1000;      ///< bridge: servo rate
  double tool_mass_kg = 0;    ///< bridge: tool mass beyond the force sensor
  double probe_radius_mm = 0;
  double timeout_s = 0.002;              ///< bridge: no state this long -> zero force
  double seconds = 0;                    ///< lab: the operator plans this long (0: 600 s)
  std::string lab_operator = "explore";  ///< lab: explore | tap | air
  std::string physics = "builtin";       ///< lab: builtin | mujoco
  std::uint64_t seed = 1;                ///< lab: as `inhap lab record --seed`
};

/// True for "lab:SCENE".
bool is_lab_device(const std::string& device);

/// The device of a session: the UDP bridge, or the virtual lab held by a simulated operator.
struct DeviceSetup {
  std::unique_ptr<haptics::BridgeDevice> bridge;
  std::unique_ptr<lab::OperatedDevice> lab;
  Device& device() { return bridge ? static_cast<Device&>(*bridge) : *lab; }
};

/// Checks the options and opens the device (the bridge socket, or the lab scene). Throws
/// inhap::Error naming the flag on a bad value.
DeviceSetup make_device(const DeviceOptions& options);

/// The shared secret: `key`, or the first line of `key_file` (trailing CR/LF removed; at most
/// 256 bytes read). Throws IoError when the file cannot be read or is empty.
std::string read_key(const std::string& key, const std::string& key_file);

/// Drains a servo loop's observer ring on its own thread into the standard recording CSV (t, p,
/// compensated f, raw rf) plus the rendered columns (commanded force, contact, q = IHIP, cq =
/// CIHIP). A tick without a new device sample (a silent bridge client) is not written. The CSV's
/// temporary file is opened by the constructor (a bad path fails before the session); finish()
/// stops the thread and commits the file.
class LoopRecorder {
 public:
  LoopRecorder(const std::string& path, const DeviceInfo& info, haptics::ObserverRing& ring);
  LoopRecorder(const LoopRecorder&) = delete;
  LoopRecorder& operator=(const LoopRecorder&) = delete;
  ~LoopRecorder();
  void finish();
  std::size_t rows() const { return rows_; }
  double last_t() const { return last_t_; }  ///< time of the last row written, s
  /// Samples left out because their time ran backwards (not a repeat of the last row).
  std::size_t skipped() const { return skipped_; }

 private:
  void drain();
  void loop();

  haptics::ObserverRing& ring_;
  CompensatorConfig config_;
  CompensatorState state_;
  CsvWriter writer_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::size_t rows_ = 0, skipped_ = 0;
  double last_t_ = 0;
};

/// Drops the truth rows after `last_t_s` (the loop's last tick, zero force after the last
/// recorded sample, is not in the recording).
void trim_truth(lab::TruthTable& truth, double last_t_s);

/// Waits until a device joins the bridge (polling every 0.25 s). Throws inhap::Error "no device
/// joined within N s" after `connect_s`, or at once when `stop` is set.
void wait_for_device(haptics::BridgeDevice& device, double connect_s,
                     const std::atomic<bool>& stop);

/// Lets the running loop run until `seconds` have passed (0: no limit), `stop` is set, the loop
/// stops, or (idle_stop_s > 0) the bridge device has been silent that long. `print` gets the
/// status line once a second ("\r<ticks> ticks, <n> time-outs") and the idle-stop message.
void supervise_loop(haptics::ServoLoop& loop, DeviceSetup& device, double seconds,
                    double idle_stop_s, const std::atomic<bool>& stop,
                    const std::function<void(const std::string&)>& print);

/// Finishes the recorder and writes its recording and, on the lab device, the truth sidecar
/// (trim_truth() to the recording) in one transaction: both or neither.
void finish_recording(LoopRecorder& recorder, DeviceSetup& device, const std::string& path);

/// The line `inhap serve` prints when the session starts (renderer, where the device is).
std::string serve_banner(const std::string& renderer, const DeviceSetup& device,
                         const DeviceOptions& options);

/// What `inhap serve` prints after the loop stopped: its real-time status, the counters
/// (loop_stats_text) and, when the recorder fell behind, how many ticks `record` misses.
std::string session_end_text(const haptics::ServoLoop& loop, const DeviceSetup& device,
                             const std::string& record);

/// The loop's and the bridge's counters as `inhap serve` prints them at the end (two lines, a third
/// with the read-ahead timings when the renderer reads ahead).
std::string loop_stats_text(const haptics::LoopStats& loop, const haptics::BridgeStats& bridge);

}  // namespace inhap::eval
