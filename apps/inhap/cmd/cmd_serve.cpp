// `inhap serve`: the real-time servo loop against a device that joins over the UDP bridge
// (docs/bridge.md), rendering a mesh with a stiffness map (TCA-MESH or CBA) or a data-driven
// force model. Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "command.hpp"
#include "inhap/contact/compensation.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/haptics/bridge_device.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/haptics/servo_loop.hpp"
#include "inhap/lab/operated_device.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::cli {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_sigint(int) {
  g_interrupted.store(true);
}

struct ServeArgs {
  std::string device = "udp", render = "tca", mesh, model, sys, shape, record, listen = "127.0.0.1",
              key, key_file;
  double seconds = 0, max_force = 6.2, timeout = 0.002, connect = 60, probe_radius = 0;
  double tool_mass = 0, rate = 1000, idle_stop = 0;
  bool no_realtime = false;
  // --device lab:SCENE
  std::string lab_operator = "explore", physics = "builtin";
  std::uint64_t seed = 1;
};

bool is_lab_device(const std::string& d) {
  return d.rfind("lab:", 0) == 0;
}

std::uint16_t parse_device(const std::string& d) {
  if (const auto port = haptics::parse_udp_device(d)) return *port;
  throw Error(fmt::format("--device: expected udp, udp:PORT (PORT 1-65535) or lab:SCENE, got {}",
                          quote_token(d)));
}

std::string read_key(const ServeArgs& a) {
  if (a.key_file.empty()) return a.key;
  std::FILE* f = std::fopen(a.key_file.c_str(), "rb");
  if (!f) throw IoError(a.key_file, "cannot open the key file");
  std::string k(256, '\0');
  const std::size_t n = std::fread(k.data(), 1, k.size(), f);
  std::fclose(f);
  k.resize(n);
  while (!k.empty() && (k.back() == '\n' || k.back() == '\r')) k.pop_back();
  if (k.empty()) throw IoError(a.key_file, "the key file is empty");
  return k;
}

// Everything the chosen renderer needs, kept alive for the loop.
struct RenderSetup {
  std::unique_ptr<rendering::Model> mesh_model;
  std::unique_ptr<datadriven::ForceModel> force;
  std::unique_ptr<friction::SysModel> sys;
  std::unique_ptr<friction::MeshSurface> shape;
  std::unique_ptr<haptics::DataDrivenModel> dd_model;
  std::unique_ptr<haptics::Renderer> renderer;
};

RenderSetup make_renderer(const ServeArgs& a) {
  RenderSetup s;
  if (a.render == "none") {
    s.renderer = std::make_unique<haptics::NullRenderer>();
    return s;
  }
  if (a.render == "tca" || a.render == "cba") {
    if (a.mesh.empty()) throw Error("--render " + a.render + " needs --mesh MESH.ply");
    rendering::Params params;
    s.mesh_model = std::make_unique<rendering::Model>(read_mesh(a.mesh), params);
    s.renderer = std::make_unique<haptics::MeshRenderer>(
        *s.mesh_model, a.render == "tca" ? rendering::Algorithm::kTCA : rendering::Algorithm::kCBA);
    return s;
  }
  if (a.render == "model") {
    if (a.model.empty() || a.sys.empty() || a.shape.empty())
      throw Error("--render model needs --model MODEL.json, --sys SYS.json and --shape MESH.ply");
    s.force = std::make_unique<datadriven::ForceModel>(datadriven::load_force_model(a.model));
    s.sys = std::make_unique<friction::SysModel>(friction::read_sys_json(a.sys));
    s.shape = std::make_unique<friction::MeshSurface>(read_mesh(a.shape), a.probe_radius);
    s.dd_model = std::make_unique<haptics::DataDrivenModel>(*s.sys, *s.shape, *s.force);
    s.renderer = std::make_unique<haptics::DataDrivenRenderer>(*s.dd_model);
    return s;
  }
  throw Error(
      fmt::format("--render: expected tca, cba, model or none, got {}", quote_token(a.render)));
}

// The recorder: drains the observer ring on its own thread into the standard recording CSV
// (t, p, compensated f, raw rf) plus the rendered columns.
class Recorder {
 public:
  Recorder(const std::string& path, const DeviceInfo& info, haptics::ObserverRing& ring)
      : ring_(ring),
        config_(CompensatorConfig::from(info)),
        writer_(path, {"t",   "px",  "py",  "pz",      "fx", "fy", "fz", "rfx", "rfy", "rfz",
                       "cfx", "cfy", "cfz", "contact", "qx", "qy", "qz", "cqx", "cqy", "cqz"},
                comments()) {
    thread_ = std::thread([this] { loop(); });
  }
  void finish() {
    stop_ = true;
    thread_.join();
    writer_.commit();
  }
  std::size_t rows() const { return rows_; }
  double last_t() const { return last_t_; }

 private:
  static std::vector<std::string> comments() {
    return {
        "inhap serve recording: t s; p mm (probe centre); f N (sensor, compensated); rf N (raw "
        "sensor); cf N (force commanded); contact 0/1; q mm (proxy / IHIP); cq mm (CIHIP)"};
  }
  void drain() {
    haptics::LoopSample s;
    while (ring_.pop(s)) {
      // A tick without a new device sample (a silent bridge client) is not a measurement.
      if (rows_ > 0 && !(s.t_s > last_t_)) continue;
      last_t_ = s.t_s;
      const Vec3 f = compensate_step(config_, state_, s.p_mm, s.sensor_force_n);
      const Vec3& q = s.out.ihip_mm;
      const Vec3& c = s.out.cihip_mm;
      writer_.row({s.t_s,
                   s.p_mm.x(),
                   s.p_mm.y(),
                   s.p_mm.z(),
                   f.x(),
                   f.y(),
                   f.z(),
                   s.sensor_force_n.x(),
                   s.sensor_force_n.y(),
                   s.sensor_force_n.z(),
                   s.commanded_n.x(),
                   s.commanded_n.y(),
                   s.commanded_n.z(),
                   s.out.contact ? 1.0 : 0.0,
                   q.x(),
                   q.y(),
                   q.z(),
                   c.x(),
                   c.y(),
                   c.z()});
      ++rows_;
    }
  }
  void loop() {
    while (!stop_) {
      drain();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    drain();
  }

  haptics::ObserverRing& ring_;
  CompensatorConfig config_;
  CompensatorState state_;
  CsvWriter writer_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::size_t rows_ = 0;
  double last_t_ = 0;
};

void print_stats(const haptics::LoopStats& s, const haptics::BridgeStats& b) {
  fmt::print(stderr,
             "ticks {}  step p50/p99 {:.2f}/{:.2f} us  period jitter p50/p99/max {:.0f}/{:.0f}/"
             "{:.0f} us  overruns {}  watchdog trips {}\n"
             "bridge: accepted {}  lost {}  late (time-outs) {}  out of order {}  malformed {}  "
             "bad auth {}  foreign {}\n",
             s.ticks, s.step_p50_us, s.step_p99_us, s.jitter_p50_us, s.jitter_p99_us,
             s.jitter_max_us, s.overruns, s.watchdog_trips, b.accepted, b.lost, b.timeouts,
             b.out_of_order, b.malformed, b.bad_auth, b.foreign_session);
}

// The device of a session: the UDP bridge, or the virtual lab held by a simulated operator.
struct DeviceSetup {
  std::unique_ptr<haptics::BridgeDevice> bridge;
  std::unique_ptr<lab::OperatedDevice> lab;
  Device& device() { return bridge ? static_cast<Device&>(*bridge) : *lab; }
};

DeviceSetup make_device(const ServeArgs& a) {
  if (!(a.max_force > 0.0) || a.max_force > kForceCeilingN)
    throw Error(fmt::format("--max-force: expected a device limit in (0, {:g}] N", kForceCeilingN));
  DeviceSetup d;
  if (is_lab_device(a.device)) {
    const std::string name = a.device.substr(4);
    lab::RecordSpec spec;
    spec.operator_name = a.lab_operator;
    spec.seconds = a.seconds > 0 ? a.seconds : 600.0;  // the operator plans this long
    spec.seed = a.seed;
    spec.physics = lab::physics_from_string(a.physics);
    const lab::Scene scene = lab::builtin_scene(name);
    d.lab = std::make_unique<lab::OperatedDevice>(scene, spec,
                                                  static_cast<std::size_t>(spec.seconds * 1000.0));
    return d;
  }
  haptics::BridgeOptions bo;
  bo.port = parse_device(a.device);
  bo.listen = a.listen;
  bo.key = read_key(a);
  bo.timeout_s = a.timeout;
  if (!(a.rate >= 100.0 && a.rate <= 20000.0)) throw Error("--rate: expected 100-20000 Hz");
  if (!(a.tool_mass >= 0.0 && a.tool_mass <= 1.0)) throw Error("--tool-mass: expected 0-1 kg");
  bo.info.name = "bridge";
  bo.info.max_force_n = a.max_force;
  bo.info.servo_rate_hz = a.rate;
  bo.info.tool_mass_kg = a.tool_mass;
  bo.info.probe_radius_mm = a.probe_radius;
  d.bridge = std::make_unique<haptics::BridgeDevice>(bo);
  return d;
}

void wait_for_device(haptics::BridgeDevice& dev, double connect_s) {
  const auto t_wait = std::chrono::steady_clock::now();
  while (!dev.connect(0.25)) {
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_wait).count();
    if (g_interrupted || waited > connect_s)
      throw Error(fmt::format("no device joined within {:.0f} s", waited));
  }
  fmt::print(stderr, "device joined (session {:08x})\n", dev.session());
}

// Runs the loop until --seconds, Ctrl-C, or (--idle-stop) the bridge device has been silent.
void supervise(haptics::ServoLoop& loop, DeviceSetup& d, const ServeArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  auto last_print = t0, last_alive = t0;
  while (loop.running() && !g_interrupted) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto now = std::chrono::steady_clock::now();
    if (a.seconds > 0 && std::chrono::duration<double>(now - t0).count() >= a.seconds) break;
    if (!d.bridge || !d.bridge->faulted()) last_alive = now;
    if (a.idle_stop > 0 && std::chrono::duration<double>(now - last_alive).count() >= a.idle_stop) {
      fmt::print(stderr, "\nthe device has been silent for {:g} s: stopping\n", a.idle_stop);
      break;
    }
    if (now - last_print > std::chrono::seconds(1)) {
      last_print = now;
      fmt::print(stderr, "\r{} ticks, {} time-outs", loop.ticks(),
                 d.bridge ? d.bridge->stats().timeouts : 0);
    }
  }
}

void run_serve(const ServeArgs& a) {
  DeviceSetup d = make_device(a);  // flag errors first, then the (slower) model files
  RenderSetup setup = make_renderer(a);
  Device& dev = d.device();
  // The recorder opens its temporary file now: a bad output path fails before the session.
  auto ring = std::make_unique<haptics::ObserverRing>();
  std::optional<Recorder> rec;
  if (!a.record.empty()) rec.emplace(a.record, dev.info(), *ring);
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
  if (d.bridge) {
    fmt::print(stderr, "inhap serve: {} on udp {}:{}{}; waiting for a device (Ctrl-C stops)\n",
               setup.renderer->name(), a.listen, d.bridge->port(),
               a.key.empty() && a.key_file.empty() ? "" : " (HMAC key)");
    wait_for_device(*d.bridge, a.connect);
  } else {
    fmt::print(stderr, "inhap serve: {} on the virtual lab ({}, operator {}; Ctrl-C stops)\n",
               setup.renderer->name(), a.device, a.lab_operator);
  }
  haptics::LoopOptions lo;
  lo.realtime = !a.no_realtime;
  haptics::ServoLoop loop(dev, *setup.renderer, lo);
  if (rec) loop.add_observer(*ring);
  loop.start();
  supervise(loop, d, a);
  loop.stop();  // the last tick commands zero force
  if (d.bridge) d.bridge->stop();
  fmt::print(stderr, "\nloop: {}\n", loop.rt_status());
  print_stats(loop.stats(), d.bridge ? d.bridge->stats() : haptics::BridgeStats{});
  if (loop.stats().dropped_samples > 0)
    fmt::print(stderr, "warning: the recorder fell behind; {} ticks are missing from {}\n",
               loop.stats().dropped_samples, a.record);
  if (rec) {
    OutputTransaction tx;  // recording and truth sidecar: both or neither
    rec->finish();
    if (d.lab) {
      lab::LabRecording log = d.lab->take_log();
      // The loop's last tick (zero force, after the last recorded sample) is not in the recording.
      lab::TruthTable& tr = log.truth;
      std::size_t keep = 0;
      while (keep < tr.size() && tr.t[keep] <= rec->last_t()) ++keep;
      tr.t.resize(keep), tr.contact.resize(keep), tr.tap.resize(keep), tr.tc.resize(keep);
      tr.c.resize(keep), tr.anchor.resize(keep), tr.force.resize(keep), tr.k.resize(keep);
      tr.mu.resize(keep);
      lab::truth_writer(lab::truth_path_for(a.record), tr, log.comments)->commit();
    }
    tx.commit();
    fmt::print(stderr, "wrote {} ({} rows){}\n", a.record, rec->rows(),
               d.lab ? " and its truth sidecar" : "");
  }
}

void add_device_options(CLI::App* c, ServeArgs& a) {
  c->add_option("--device", a.device,
                "udp or udp:PORT (the bridge, default port 47110), or lab:SCENE (the virtual lab "
                "with a simulated operator)")
      ->capture_default_str();
  c->add_option("--listen", a.listen,
                "IPv4 address to listen on; other than 127.x needs --key or --key-file")
      ->capture_default_str();
  c->add_option("--key", a.key, "shared secret: every datagram carries an HMAC-SHA256 tag");
  c->add_option("--key-file", a.key_file, "read the shared secret from a file (first line)");
  c->add_option("--seconds", a.seconds, "stop after this many seconds (0: at Ctrl-C)")
      ->capture_default_str();
  c->add_option("--max-force", a.max_force, "device force limit, N (at most 40)")
      ->capture_default_str();
  c->add_option("--rate", a.rate, "the bridge device's servo rate, Hz")->capture_default_str();
  c->add_option("--tool-mass", a.tool_mass,
                "mass of the tool beyond the bridge device's force sensor, kg (compensation of "
                "the recorded f; the virtual lab's is 0.01)")
      ->capture_default_str();
  c->add_option("--probe-radius", a.probe_radius, "probe radius, mm (and for --shape)")
      ->capture_default_str();
  c->add_option("--timeout", a.timeout,
                "no state from the bridge device for this long -> zero force, s (default: two "
                "periods at 1 kHz, one period after the next state was due)")
      ->capture_default_str();
  c->add_option("--connect-timeout", a.connect, "give up if no device joins within this, s")
      ->capture_default_str();
  c->add_option("--operator", a.lab_operator, "lab:SCENE: explore | tap | air")
      ->capture_default_str()
      ->check(CLI::IsMember({"explore", "tap", "air"}));
  c->add_option("--seed", a.seed, "lab:SCENE: seed, as `inhap lab record --seed`")
      ->capture_default_str();
  cli::add_physics_option(*c, a.physics, "lab:SCENE: builtin | mujoco");
  c->add_flag("--no-realtime", a.no_realtime, "do not ask for SCHED_FIFO and mlockall");
}

void register_serve(CLI::App& app) {
  auto a = std::make_shared<ServeArgs>();
  auto* c = app.add_subcommand(
      "serve",
      "Run the 1 kHz servo loop against a device: one that joins over the UDP bridge\n"
      "(docs/bridge.md; clients in clients/c and clients/python; `inhap lab device` is the\n"
      "virtual lab as such a client) or the virtual lab in-process. Units: mm, N, N/mm, s.");
  add_device_options(c, *a);
  c->add_option("--render", a->render,
                "tca, cba (a mesh with a stiffness map), model (data-driven) or none (zero force)")
      ->capture_default_str();
  c->add_option("--mesh", a->mesh, "PLY/OBJ mesh with a 'stiffness' vertex property (N/mm)");
  c->add_option("--model", a->model, "force model JSON (inhap model train)");
  c->add_option("--sys", a->sys, "sliding yield surfaces (sys.json, inhap sys palpate/fit)");
  c->add_option("--shape", a->shape, "shape mesh of the data-driven object (PLY/OBJ, mm)");
  c->add_option("--record", a->record,
                "write the session as a recording CSV (t, p, f, rf, commanded force, q); with "
                "lab:SCENE also its truth sidecar");
  c->add_option("--idle-stop", a->idle_stop,
                "stop when the bridge device has been silent this long, s (0: never)")
      ->capture_default_str();
  c->callback([a] { run_serve(*a); });

  auto r = std::make_shared<ServeArgs>();
  r->render = "none";
  r->idle_stop = 2.0;
  auto* rc = app.add_subcommand(
      "record",
      "Record a device: the servo loop with zero force, writing the standard recording CSV\n"
      "(t s, p mm, f N compensated, rf N raw) for `shape contacts`, `model train`, `sys proxy`.\n"
      "Stops at --seconds, Ctrl-C, or when the device has been silent for --idle-stop s.");
  add_device_options(rc, *r);
  rc->add_option("--out,-o", r->record, "recording CSV to write")->required();
  rc->add_option("--idle-stop", r->idle_stop,
                 "stop when the bridge device has been silent this long, s (0: never)")
      ->capture_default_str();
  rc->callback([r] { run_serve(*r); });
}

INHAP_COMMAND(70, "serve", register_serve);

}  // namespace
}  // namespace inhap::cli
