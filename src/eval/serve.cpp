#include "inhap/eval/serve.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <vector>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap::eval {

RenderSetup make_renderer(const RendererOptions& a) {
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
    s.shape = std::make_unique<friction::MeshSurface>(read_mesh(a.shape), a.probe_radius_mm);
    s.dd_model = std::make_unique<haptics::DataDrivenModel>(*s.sys, *s.shape, *s.force);
    s.renderer = std::make_unique<haptics::DataDrivenRenderer>(*s.dd_model);
    return s;
  }
  throw Error(
      fmt::format("--render: expected tca, cba, model or none, got {}", quote_token(a.render)));
}

bool is_lab_device(const std::string& d) {
  return d.rfind("lab:", 0) == 0;
}

std::string read_key(const std::string& key, const std::string& key_file) {
  if (key_file.empty()) return key;
  std::FILE* f = std::fopen(key_file.c_str(), "rb");
  if (!f) throw IoError(key_file, "cannot open the key file");
  std::string k(256, '\0');
  const std::size_t n = std::fread(k.data(), 1, k.size(), f);
  std::fclose(f);
  k.resize(n);
  while (!k.empty() && (k.back() == '\n' || k.back() == '\r')) k.pop_back();
  if (k.empty()) throw IoError(key_file, "the key file is empty");
  return k;
}

namespace {

std::unique_ptr<lab::OperatedDevice> make_lab_device(const DeviceOptions& a) {
  lab::RecordSpec spec;
  spec.operator_name = a.lab_operator;
  spec.seconds = a.seconds > 0 ? a.seconds : 600.0;  // the operator plans this long
  spec.seed = a.seed;
  spec.physics = lab::physics_from_string(a.physics);
  const lab::Scene scene = lab::builtin_scene(a.device.substr(4));
  return std::make_unique<lab::OperatedDevice>(scene, spec,
                                               static_cast<std::size_t>(spec.seconds * 1000.0));
}

}  // namespace

DeviceSetup make_device(const DeviceOptions& a) {
  if (!(a.max_force_n > 0.0) || a.max_force_n > kForceCeilingN)
    throw Error(fmt::format("--max-force: expected a device limit in (0, {:g}] N", kForceCeilingN));
  DeviceSetup d;
  if (is_lab_device(a.device)) {
    d.lab = make_lab_device(a);
    return d;
  }
  haptics::BridgeOptions bo;
  const auto port = haptics::parse_udp_device(a.device);
  if (!port)
    throw Error(fmt::format("--device: expected udp, udp:PORT (PORT 1-65535) or lab:SCENE, got {}",
                            quote_token(a.device)));
  bo.port = *port;
  bo.listen = a.listen;
  bo.key = read_key(a.key, a.key_file);
  bo.timeout_s = a.timeout_s;
  if (!(a.rate_hz >= 100.0 && a.rate_hz <= 20000.0)) throw Error("--rate: expected 100-20000 Hz");
  if (!(a.tool_mass_kg >= 0.0 && a.tool_mass_kg <= 1.0))
    throw Error("--tool-mass: expected 0-1 kg");
  bo.info.name = "bridge";
  bo.info.max_force_n = a.max_force_n;
  bo.info.servo_rate_hz = a.rate_hz;
  bo.info.tool_mass_kg = a.tool_mass_kg;
  bo.info.probe_radius_mm = a.probe_radius_mm;
  d.bridge = std::make_unique<haptics::BridgeDevice>(bo);
  return d;
}

LoopRecorder::LoopRecorder(const std::string& path, const DeviceInfo& info,
                           haptics::ObserverRing& ring)
    : ring_(ring),
      config_(CompensatorConfig::from(info)),
      writer_(path, {"t",   "px",  "py",  "pz",      "fx", "fy", "fz", "rfx", "rfy", "rfz",
                     "cfx", "cfy", "cfz", "contact", "qx", "qy", "qz", "cqx", "cqy", "cqz"},
              std::vector<std::string>{
                  "inhap serve recording: t s; p mm (probe centre); f N (sensor, compensated); "
                  "rf N (raw sensor); cf N (force commanded); contact 0/1; q mm (proxy / IHIP); "
                  "cq mm (CIHIP)"}) {
  thread_ = std::thread([this] { loop(); });
}

LoopRecorder::~LoopRecorder() {
  if (thread_.joinable()) {  // not finished (an error): stop, write nothing
    stop_ = true;
    thread_.join();
  }
}

void LoopRecorder::finish() {
  stop_ = true;
  thread_.join();
  writer_.commit();
}

void LoopRecorder::drain() {
  haptics::LoopSample s;
  while (ring_.pop(s)) {
    // A tick without a new device sample (a silent bridge client) is not a measurement; a time
    // that runs backwards (a new device session) is counted and reported, never silent.
    if (rows_ > 0 && !(s.t_s > last_t_)) {
      if (!(s.t_s == last_t_)) ++skipped_;
      continue;
    }
    last_t_ = s.t_s;
    const Vec3 f = compensate_step(config_, state_, s.p_mm, s.sensor_force_n);
    const Vec3& q = s.out.ihip_mm;
    const Vec3& c = s.out.cihip_mm;
    const Vec3& rf = s.sensor_force_n;
    const Vec3& cf = s.commanded_n;
    writer_.row(
        {s.t_s,  s.p_mm.x(), s.p_mm.y(), s.p_mm.z(), f.x(),  f.y(),  f.z(),
         rf.x(), rf.y(),     rf.z(),     cf.x(),     cf.y(), cf.z(), s.out.contact ? 1.0 : 0.0,
         q.x(),  q.y(),      q.z(),      c.x(),      c.y(),  c.z()});
    ++rows_;
  }
}

void LoopRecorder::loop() {
  while (!stop_) {
    drain();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  drain();
}

void trim_truth(lab::TruthTable& tr, double last_t_s) {
  std::size_t keep = 0;
  while (keep < tr.size() && tr.t[keep] <= last_t_s) ++keep;
  tr.t.resize(keep), tr.contact.resize(keep), tr.tap.resize(keep), tr.tc.resize(keep);
  tr.c.resize(keep), tr.anchor.resize(keep), tr.force.resize(keep), tr.k.resize(keep);
  tr.mu.resize(keep);
}

void wait_for_device(haptics::BridgeDevice& dev, double connect_s, const std::atomic<bool>& stop) {
  const auto t_wait = std::chrono::steady_clock::now();
  while (!dev.connect(0.25)) {
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_wait).count();
    if (stop || waited > connect_s)
      throw Error(fmt::format("no device joined within {:.0f} s", waited));
  }
}

void supervise_loop(haptics::ServoLoop& loop, DeviceSetup& d, double seconds, double idle_stop_s,
                    const std::atomic<bool>& stop,
                    const std::function<void(const std::string&)>& print) {
  const auto t0 = std::chrono::steady_clock::now();
  auto last_print = t0, last_alive = t0;
  while (loop.running() && !stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto now = std::chrono::steady_clock::now();
    if (seconds > 0 && std::chrono::duration<double>(now - t0).count() >= seconds) break;
    if (!d.bridge || !d.bridge->faulted()) last_alive = now;
    if (idle_stop_s > 0 && std::chrono::duration<double>(now - last_alive).count() >= idle_stop_s) {
      print(fmt::format("\nthe device has been silent for {:g} s: stopping\n", idle_stop_s));
      break;
    }
    if (now - last_print > std::chrono::seconds(1)) {
      last_print = now;
      print(fmt::format("\r{} ticks, {} time-outs", loop.ticks(),
                        d.bridge ? d.bridge->stats().timeouts : 0));
    }
  }
}

void finish_recording(LoopRecorder& rec, DeviceSetup& d, const std::string& path) {
  OutputTransaction tx;  // recording and truth sidecar: both or neither
  rec.finish();
  if (d.lab) {
    lab::LabRecording log = d.lab->take_log();
    // The loop's last tick (zero force, after the last recorded sample) is not in the recording.
    trim_truth(log.truth, rec.last_t());
    lab::truth_writer(lab::truth_path_for(path), log.truth, log.comments)->commit();
  }
  tx.commit();
}

std::string loop_stats_text(const haptics::LoopStats& s, const haptics::BridgeStats& b) {
  std::string t = fmt::format(
      "ticks {}  step p50/p99 {:.2f}/{:.2f} us  period jitter p50/p99/max {:.0f}/{:.0f}/"
      "{:.0f} us  overruns {}  watchdog trips {}\n"
      "bridge: accepted {}  lost {}  late (time-outs) {}  out of order {}  malformed {}  "
      "bad auth {}  foreign {}  foreign peer {}  out of range {}  bad time {}\n",
      s.ticks, s.step_p50_us, s.step_p99_us, s.jitter_p50_us, s.jitter_p99_us, s.jitter_max_us,
      s.overruns, s.watchdog_trips, b.accepted, b.lost, b.timeouts, b.out_of_order, b.malformed,
      b.bad_auth, b.foreign_session, b.foreign_peer, b.out_of_range, b.bad_time);
  if (s.prefetch_p99_us > 0)  // only renderers that read ahead (the mesh renderers)
    t += fmt::format("read-ahead p50/p99 {:.2f}/{:.2f} us (between ticks, off the force's path)\n",
                     s.prefetch_p50_us, s.prefetch_p99_us);
  return t;
}

std::string serve_banner(const std::string& renderer, const DeviceSetup& d,
                         const DeviceOptions& a) {
  if (d.bridge)
    return fmt::format("inhap serve: {} on udp {}:{}{}; waiting for a device (Ctrl-C stops)\n",
                       renderer, a.listen, d.bridge->port(),
                       a.key.empty() && a.key_file.empty() ? "" : " (HMAC key)");
  return fmt::format("inhap serve: {} on the virtual lab ({}, operator {}; Ctrl-C stops)\n",
                     renderer, a.device, a.lab_operator);
}

std::string session_end_text(const haptics::ServoLoop& loop, const DeviceSetup& d,
                             const std::string& record) {
  const haptics::LoopStats s = loop.stats();
  std::string t = fmt::format("\nloop: {}\n", loop.rt_status());
  t += loop_stats_text(s, d.bridge ? d.bridge->stats() : haptics::BridgeStats{});
  if (s.dropped_samples > 0)
    t += fmt::format("warning: the recorder fell behind; {} ticks are missing from {}\n",
                     s.dropped_samples, record);
  return t;
}

}  // namespace inhap::eval
