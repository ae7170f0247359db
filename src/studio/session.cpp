// inhap studio session: device, servo loop per view, streamer (see session.hpp).
#include "inhap/studio/session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "inhap/core/error.hpp"
#include "inhap/rendering/datasets.hpp"
#include "inhap/studio/display.hpp"
#include "inhap/studio/experiment_summary.hpp"
#include "session_rig.hpp"

namespace inhap::studio {

std::optional<Contact> StreamTapDetector::add(double t, const Vec3& p, const Vec3& f) {
  t_.push_back(t), p_.push_back(p), f_.push_back(f);
  const std::size_t i = t_.size() - 1;
  const double mag = f.norm();
  if (!in_) {
    above_ = mag > options_.eps_f ? above_ + 1 : 0;
    if (above_ >= options_.min_contact) in_ = true, start_ = i + 1 - above_, below_ = 0;
    // Keep the buffer short between taps (the window before a detection is all the knee needs).
    const std::size_t keep = options_.window + 64;
    if (!in_ && t_.size() > 8 * keep) {
      const auto cut = static_cast<std::ptrdiff_t>(t_.size() - keep);
      t_.erase(t_.begin(), t_.begin() + cut);
      p_.erase(p_.begin(), p_.begin() + cut);
      f_.erase(f_.begin(), f_.begin() + cut);
    }
    return std::nullopt;
  }
  below_ = mag < options_.release_fraction * options_.eps_f ? below_ + 1 : 0;
  if (below_ < 5) return std::nullopt;
  in_ = false, above_ = 0, below_ = 0;
  const std::size_t from = start_ > options_.window + 32 ? start_ - options_.window - 32 : 0;
  const std::size_t n = t_.size() - from;
  const auto c = detect_contacts(std::span<const double>(t_.data() + from, n),
                                 std::span<const Vec3>(p_.data() + from, n),
                                 std::span<const Vec3>(f_.data() + from, n), options_);
  if (c.empty()) return std::nullopt;
  return c.back();
}

Session::Session(const StudioOptions& options, const Workspace& workspace, Broadcast broadcast)
    : options_(options), workspace_(workspace), broadcast_(std::move(broadcast)) {
  if (options_.device.rfind("lab:", 0) == 0) {
    scene_ = lab::builtin_scene(options_.device.substr(4));
  } else {
    const auto port = haptics::parse_udp_device(options_.device);
    if (!port)
      throw Error(
          fmt::format("--device: expected lab:SCENE, udp or udp:PORT (PORT 1-65535), got \"{}\"",
                      options_.device));
    lab_ = false;
    if (!(options_.tool_mass_kg >= 0 && options_.tool_mass_kg <= 10))
      throw Error(fmt::format("--tool-mass: expected 0-10 kg, got {}", options_.tool_mass_kg));
    haptics::BridgeOptions bo;
    bo.port = *port;
    bo.info.tool_mass_kg = options_.tool_mass_kg;
    bridge_ = std::make_unique<haptics::BridgeDevice>(bo);
  }
  if (!(options_.speed >= 0.1 && options_.speed <= 20))
    throw Error("--speed: expected 0.1-20 simulated seconds per second");
  explore_name_ = "study25";
  explore_mesh_ =
      rendering::StudySurface(rendering::DatasetParams{}, rendering::identity_layout()).mesh();
}

Session::~Session() {
  stop();
}

void Session::start(double connect_s) {
  if (bridge_) {
    fmt::print(stderr, "inhap studio: waiting for a device on udp port {}\n", bridge_->port());
    if (!bridge_->connect(connect_s))
      throw Error(fmt::format("no device joined within {:g} s", connect_s));
  }
  std::lock_guard cmd(cmd_mu_);
  if (lab_ && object_mesh_json_.empty())  // before any page can say hello
    object_mesh_json_ = mesh_json(top_view_mesh(scene_.object.shape()), "object", "");
  start_rig(mode_);
}

void Session::stop() {
  end_training();  // before the lock: the worker's last message may wait for nothing else
  std::lock_guard cmd(cmd_mu_);
  stop_rig();
  if (bridge_) bridge_->stop();
}

std::string Session::server_latency() const {
  std::vector<double> v = server_latency_ms_;
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  return fmt::format("median {:.1f} ms, p90 {:.1f} ms, max {:.1f} ms ({} targets)", v[v.size() / 2],
                     v[v.size() * 9 / 10], v.back(), v.size());
}

std::string Session::mode() const {
  std::lock_guard lock(data_mu_);
  return mode_;
}

void Session::start_rig(const std::string& mode) {
  auto rig = std::make_unique<Rig>();
  if (mode == "model" || mode == "model_record") {
    build_model_rig(*rig, mode);
  } else {
    build_rig(*rig, mode);
  }
  haptics::LoopOptions lo;
  lo.realtime = options_.realtime;
  // The lab's time is simulated and there is no arm to protect: a wall-clock deadline missed
  // under load changes nothing it computes, while a watchdog zero force would spoil a palpation
  // cycle and show a pressed probe with no force. A real device (udp) keeps the watchdog.
  if (lab_) lo.watchdog_misses = std::numeric_limits<int>::max();
  rig->loop = std::make_unique<haptics::ServoLoop>(*rig->device, *rig->renderer, lo);
  rig->loop->add_observer(rig->ring);
  {
    std::lock_guard lock(data_mu_);
    mode_ = mode;
    have_latest_ = false;
  }
  rig_ = std::move(rig);
  rig_->loop->start();
  stop_stream_ = false;
  streamer_ = std::thread([this] { stream_loop(); });
}

void Session::build_rig(Rig& rig_ref, const std::string& mode) {
  Rig* rig = &rig_ref;
  const bool palp = mode == "palpation" || mode == "palpating";
  const bool mouse = mode != "sampling" && !palp;
  if (lab_) {
    lab::DeviceParams dp;
    dp.seed = options_.seed;
    // The palpation keeps the lab's default ball probe, as `sys palpate` does.
    if (!palp) dp.probe = lab::ProbeSpec::tip();
    std::unique_ptr<lab::HandOperator> op;
    if (palp) {
      const Box3 b = palp_mesh_->bbox();
      const Vec3 start =
          mode == "palpating"
              ? Vec3(palp_points_.front() + (palp_config_.hover + 3.0) * palp_normals_.front())
              : Vec3(b.center().x(), b.center().y(), b.max.z() + 10);
      op = std::make_unique<DetachedOperator>(start);
    } else if (mouse) {
      const Box3 b = explore_mesh_.bbox();
      const Vec3 start = mode == "experiment" && surface_
                             ? Vec3(surface_->cell_centre(12).x(), surface_->cell_centre(12).y(), 6)
                             : Vec3(b.center().x(), b.center().y(), b.max.z() + 10);
      auto m = std::make_unique<MouseOperator>(rig->mailbox, start);
      rig->mouse = m.get();
      op = std::move(m);
    } else {
      op = lab::make_tap_operator(scene_, options_.seed + 1);
    }
    rig->lab_device = std::make_unique<LabHandDevice>(
        mouse ? out_of_the_way_object() : scene_.object, dp, std::move(op),
        mode == "palpating" ? palp_speed_ : options_.speed);
    rig->device = rig->lab_device.get();
    rig->comp = CompensatorConfig::from(rig->lab_device->device_info());
  } else {
    rig->device = bridge_.get();
    rig->comp = CompensatorConfig::from(bridge_->info());
  }
  if (mode == "sampling" || mode == "palpation") {
    rig->renderer = std::make_unique<haptics::NullRenderer>();
  } else if (mode == "palpating") {
    auto r = std::make_unique<PalpationRenderer>(
        palp_config_, lab_ ? rig->lab_device->device_info() : bridge_->info(), palp_points_,
        palp_normals_, *palp_shape_);
    rig->palp = r.get();
    rig->renderer = std::move(r);
  } else {
    const TriMesh& mesh = mode == "experiment" && surface_ ? surface_->mesh() : explore_mesh_;
    rig->model = std::make_unique<rendering::Model>(mesh, rendering::Params{});
    const rendering::Algorithm alg = mode == "experiment" && trial_ < schedule_.size()
                                         ? schedule_[trial_].algorithm
                                         : algorithm_;
    rig->renderer = std::make_unique<haptics::MeshRenderer>(*rig->model, alg);
    if (mode == "explore" && data_driven_)
      rig->renderer = std::make_unique<haptics::DataDrivenRenderer>(data_driven_->model);
  }
}

void Session::stop_rig() {
  if (!rig_) return;
  stop_stream_ = true;
  if (streamer_.joinable()) streamer_.join();
  rig_->loop->stop();
  rig_.reset();
}

void Session::stream_loop() {
  // Polls the ring every 2 ms; broadcasts the newest sample every 1/stream_hz, or at once when
  // the servo thread has just applied a new mouse target (the page's latency).
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<clock::duration>(
      std::chrono::duration<double>(1.0 / options_.stream_hz));
  const auto poll = std::chrono::milliseconds(2);
  auto next = clock::now(), last_sent = next;
  std::uint64_t sent_seq = 0;
  const bool sampling = mode() == "sampling";
  bool have = false, fitted = false;
  haptics::LoopSample last;
  while (!stop_stream_) {
    next += poll;
    std::this_thread::sleep_until(next);
    haptics::LoopSample s;
    std::vector<Contact> found;
    while (rig_->ring.pop(s)) {
      have = true;
      last = s;
      if (rig_->observed) {  // the Model view recording a bridged device
        TickPoint p;
        if (model_stream_->observed.add(s, p)) model_stream_->coverage.add(p);
      }
      if (!sampling) continue;
      const Vec3 f = compensate_step(rig_->comp, rig_->comp_state, s.p_mm, s.sensor_force_n);
      if (auto c = rig_->taps.add(s.t_s, s.p_mm, f)) found.push_back(*c);
    }
    for (const Contact& c : found) on_contact(c);
    if (rig_->palp) stream_palpation(*rig_->palp, fitted);
    if (rig_->recorder || rig_->observed || rig_->compare) stream_model(*rig_, false);
    const std::uint64_t seq = rig_->mouse ? rig_->mouse->applied_seq() : 0;
    const auto now = clock::now();
    if (!have || (now - last_sent < period && seq == sent_seq)) continue;
    {
      std::lock_guard lock(data_mu_);
      latest_ = last;
      have_latest_ = true;
    }
    broadcast_(state_json(last));
    if (seq != sent_seq && seq == probe_written_seq_ && server_latency_ms_.size() < 100000)
      server_latency_ms_.push_back(
          1e-6 * double(clock::now().time_since_epoch().count() - probe_written_ns_));
    last_sent = now;
    sent_seq = seq;
  }
  if (rig_->recorder || rig_->observed || rig_->compare) stream_model(*rig_, true);
}

std::string Session::state_json(const haptics::LoopSample& s) const {
  const auto v = [](const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
  nlohmann::json j{{"type", "state"},
                   {"tick", s.tick},
                   {"t", s.t_s},
                   {"p", v(s.p_mm)},
                   {"hip", v(s.out.hip_mm)},
                   {"ihip", v(s.out.ihip_mm)},
                   {"cihip", v(s.out.cihip_mm)},
                   {"f", v(s.commanded_n)},
                   {"fs", v(s.sensor_force_n)},
                   {"contact", s.out.contact},
                   {"watchdog", s.watchdog},
                   {"seq", rig_ && rig_->mouse ? rig_->mouse->applied_seq() : 0}};
  if (rig_ && rig_->palp) {
    j["palp_progress"] = rig_->palp->progress();
    j["palp_point"] = rig_->palp->point();
  }
  return j.dump();
}

std::string Session::handle(std::string_view text) {
  // The boundary of every handler: nothing thrown below gets past it.
  std::string request = "?";
  try {
    const Message m = parse_message(text);
    request = m.type;
    std::lock_guard cmd(cmd_mu_);
    return dispatch(m);
  } catch (const std::exception& e) {
    return error_reply(request, e.what());
  } catch (...) {
    return error_reply(request, "internal error");
  }
}

std::string Session::dispatch(const Message& m) {
  if (m.type == "hello") {
    broadcast_(samples_json());  // the taps made before this page connected
    return hello();
  }
  if (m.type == "mode")
    return set_mode(
        get_choice(m, "mode", {"sampling", "idle", "explore", "experiment", "palpation", "model"}));
  if (m.type == "probe") return do_probe(m);
  if (m.type == "delete") return do_delete(m);
  if (m.type == "undo") return do_undo();
  if (m.type == "reconstruct") return do_reconstruct(m);
  if (m.type == "preview") return do_preview();
  if (m.type == "apply_preview") return do_apply_preview();
  if (m.type == "export") return do_export(m);
  if (m.type == "save_session") return do_save_session(m);
  if (m.type == "open_session") return do_open_session(m);
  if (m.type == "open_mesh") return do_open_mesh(m);
  if (m.type == "algorithm") return do_algorithm(m);
  if (m.type == "experiment") return do_experiment(m);
  if (m.type == "answer") return do_answer(m);
  if (m.type == "next_trial") return do_next_trial();
  if (m.type == "progress") return progress_json();
  if (m.type == "palpate") return do_palpate(m);
  if (m.type == "save_sys") return do_save_sys(m);
  if (m.type == "summary") return dump_safe(summarize_answers(workspace_));
  if (m.type == "model_record") return do_model_record(m);
  if (m.type == "model_stop") return do_model_stop();
  if (m.type == "model_train") return do_model_train(m);
  if (m.type == "model_cancel") return do_model_cancel();
  if (m.type == "model_source") return do_model_source(m);
  if (m.type == "model_blind") return do_model_blind(m);
  if (m.type == "model_answer") return do_model_answer(m);
  if (m.type == "model_stats") return do_model_stats();
  if (m.type == "servo") return servo_json();
  if (m.type == "stats") {
    // The raw text, quoted and capped (the body was checked for depth before parsing).
    fmt::print(stderr, "page: {}\n", quote_input(dump_safe(m.body), 2000));
    return nlohmann::json{{"type", "ok"}, {"request", "stats"}}.dump();
  }
  throw ProtocolError("unhandled message type " + m.type);
}

std::string Session::hello() const {
  if (lab_) {  // the scene's object as the operator sees it from above, drawn under the samples
    // Built once, by start() (the scene never changes): 4096 drops and a 258 KB JSON message
    // took ~25 ms per hello.
    if (object_mesh_json_.empty())
      object_mesh_json_ = mesh_json(top_view_mesh(scene_.object.shape()), "object", "");
    broadcast_(object_mesh_json_);
  }
  nlohmann::json j{{"type", "hello"},
                   {"mode", mode()},
                   {"device", options_.device},
                   {"lab", lab_},
                   {"scene", lab_ ? scene_.name : std::string()},
                   {"speed", options_.speed},
                   {"workspace", workspace_.root().string()},
                   {"stream_hz", options_.stream_hz}};
  return j.dump();
}

std::string Session::servo_json() const {
  // The current view's loop (a new view starts a new loop, and new counts).
  nlohmann::json j{{"type", "servo"}, {"mode", mode()}, {"running", false}};
  if (rig_ && rig_->loop) {
    const haptics::LoopStats st = rig_->loop->stats();
    j.update({{"running", rig_->loop->running()},
              {"ticks", st.ticks},
              {"overruns", st.overruns},
              {"watchdog_trips", st.watchdog_trips},
              {"watchdog_ticks", st.watchdog_ticks},
              {"period_us", st.period_us},
              {"rt", rig_->loop->rt_status()}});
  }
  return j.dump();
}

std::string Session::set_mode(const std::string& mode) {
  if (mode == "experiment" && !surface_)
    throw ProtocolError("mode: start an experiment first ({\"type\":\"experiment\",...})");
  if (mode == "palpation" && !lab_ && !reconstruction_)
    throw ProtocolError(
        "mode: palpation needs a shape: reconstruct one in the sampling view first (a real "
        "device has no lab scene)");
  stop_rig();  // before the shape changes: a running palpation reads it
  if (mode == "palpation") ensure_palpation_shape();
  if (mode == "idle") {  // sampling with the operator paused: no loop, the samples stay
    std::lock_guard lock(data_mu_);
    mode_ = mode;
  } else {
    start_rig(mode);
  }
  nlohmann::json j{{"type", "ok"}, {"request", "mode"}, {"mode", mode}};
  return j.dump();
}

std::string Session::do_probe(const Message& m) {
  const double x = get_number(m, "x", -1e4, 1e4), y = get_number(m, "y", -1e4, 1e4),
               z = get_number(m, "z", -1e4, 1e4);
  const double nx = get_number_or(m, "nx", -1, 1, 0), ny = get_number_or(m, "ny", -1, 1, 0),
               nz = get_number_or(m, "nz", -1, 1, 1);
  const double press = get_number_or(m, "press", 0, 1, 0);
  const long seq = get_integer(m, "seq", 0, 1L << 52);
  Vec3 n(nx, ny, nz);
  if (!(n.norm() > 0.1)) throw ProtocolError("probe: expected a normal (nx, ny, nz) of length 1");
  n.normalize();
  if (!rig_ || !rig_->mouse) return nlohmann::json{{"type", "ok"}, {"request", "probe"}}.dump();
  // Hover 3 mm above the point; pressed, up to 12 mm into the surface: the hand's spring
  // (0.6 N/mm) against the rendered surface sets the force.
  // The Model view's lab probe is the 8 mm ball: its centre rides that much higher.
  const double lift = mode_.rfind("model", 0) == 0 ? lab::DeviceParams{}.probe.radius_mm : 0.0;
  rig_->mailbox.write(Vec3(x, y, z) + n * (lift + 3.0 - 15.0 * press),
                      static_cast<std::uint64_t>(seq));
  probe_written_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
  probe_written_seq_ = static_cast<std::uint64_t>(seq);
  return {};  // no reply: the state stream shows the probe
}

}  // namespace inhap::studio
