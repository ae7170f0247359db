// `inhap serve`: the real-time servo loop against a device that joins over the UDP bridge
// (docs/bridge.md), rendering a mesh with a stiffness map (TCA-MESH or CBA) or a data-driven
// force model. Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/serve.hpp"
#include "inhap/lab/recorder.hpp"

namespace inhap::cli {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_sigint(int) {
  g_interrupted.store(true);
}

struct ServeArgs {
  eval::DeviceOptions dev;
  eval::RendererOptions ren;
  std::string record;
  double connect = 60, idle_stop = 0;
  bool no_realtime = false;
};

void run_serve(const ServeArgs& a) {
  eval::DeviceSetup d = eval::make_device(a.dev);  // flag errors first, then the model files
  eval::RendererOptions ro = a.ren;
  ro.probe_radius_mm = a.dev.probe_radius_mm;
  eval::RenderSetup setup = eval::make_renderer(ro);
  Device& dev = d.device();
  // The recorder opens its temporary file now: a bad output path fails before the session.
  auto ring = std::make_unique<haptics::ObserverRing>();
  std::optional<eval::LoopRecorder> rec;
  if (!a.record.empty()) rec.emplace(a.record, dev.info(), *ring);
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
  fmt::print(stderr, "{}", eval::serve_banner(setup.renderer->name(), d, a.dev));
  if (d.bridge) {
    eval::wait_for_device(*d.bridge, a.connect, g_interrupted);
    fmt::print(stderr, "device joined (session {:08x})\n", d.bridge->session());
  }
  haptics::LoopOptions lo;
  lo.realtime = !a.no_realtime;
  haptics::ServoLoop loop(dev, *setup.renderer, lo);
  if (rec) loop.add_observer(*ring);
  loop.start();
  eval::supervise_loop(loop, d, a.dev.seconds, a.idle_stop, g_interrupted,
                       [](const std::string& s) { fmt::print(stderr, "{}", s); });
  loop.stop();  // the last tick commands zero force
  if (d.bridge) d.bridge->stop();
  fmt::print(stderr, "{}", eval::session_end_text(loop, d, a.record));
  if (rec) {
    eval::finish_recording(*rec, d, a.record);
    fmt::print(stderr, "wrote {} ({} rows){}\n", a.record, rec->rows(),
               d.lab ? " and its truth sidecar" : "");
    if (rec->skipped() > 0)
      fmt::print(stderr,
                 "warning: {} samples of the device were left out of {}: their time ran "
                 "backwards (t {:g} s at the last row)\n",
                 rec->skipped(), a.record, rec->last_t());
  }
}

void add_device_options(CLI::App* c, ServeArgs& s) {
  eval::DeviceOptions& a = s.dev;
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
  c->add_option("--max-force", a.max_force_n, "device force limit, N (at most 40)")
      ->capture_default_str();
  c->add_option("--rate", a.rate_hz, "the bridge device's servo rate, Hz")->capture_default_str();
  c->add_option("--tool-mass", a.tool_mass_kg,
                "mass of the tool beyond the bridge device's force sensor, kg (compensation of "
                "the recorded f; the virtual lab's is 0.01)")
      ->capture_default_str();
  c->add_option("--probe-radius", a.probe_radius_mm, "probe radius, mm (and for --shape)")
      ->capture_default_str();
  c->add_option("--timeout", a.timeout_s,
                "no state from the bridge device for this long -> zero force, s (default: two "
                "periods at 1 kHz, one period after the next state was due)")
      ->capture_default_str();
  c->add_option("--connect-timeout", s.connect, "give up if no device joins within this, s")
      ->capture_default_str();
  c->add_option("--operator", a.lab_operator, "lab:SCENE: explore | tap | air")
      ->capture_default_str()
      ->check(CLI::IsMember({"explore", "tap", "air"}));
  c->add_option("--seed", a.seed, "lab:SCENE: seed, as `inhap lab record --seed`")
      ->capture_default_str();
  cli::add_physics_option(*c, a.physics, "lab:SCENE: builtin | mujoco");
  c->add_flag("--no-realtime", s.no_realtime, "do not ask for SCHED_FIFO and mlockall");
}

void register_serve(CLI::App& app) {
  auto a = std::make_shared<ServeArgs>();
  auto* c = app.add_subcommand(
      "serve",
      "Run the 1 kHz servo loop against a device: one that joins over the UDP bridge\n"
      "(docs/bridge.md; clients in clients/c and clients/python; `inhap lab device` is the\n"
      "virtual lab as such a client) or the virtual lab in-process. Units: mm, N, N/mm, s.");
  add_device_options(c, *a);
  c->add_option("--render", a->ren.render,
                "tca, cba (a mesh with a stiffness map), model (data-driven) or none (zero force)")
      ->capture_default_str();
  c->add_option("--mesh", a->ren.mesh, "PLY/OBJ mesh with a 'stiffness' vertex property (N/mm)");
  c->add_option("--model", a->ren.model, "force model JSON (inhap model train)");
  c->add_option("--sys", a->ren.sys, "sliding yield surfaces (sys.json, inhap sys palpate/fit)");
  c->add_option("--shape", a->ren.shape, "shape mesh of the data-driven object (PLY/OBJ, mm)");
  c->add_option("--record", a->record,
                "write the session as a recording CSV (t, p, f, rf, commanded force, q); with "
                "lab:SCENE also its truth sidecar");
  c->add_option("--idle-stop", a->idle_stop,
                "stop when the bridge device has been silent this long, s (0: never)")
      ->capture_default_str();
  c->callback([a] { run_serve(*a); });

  auto r = std::make_shared<ServeArgs>();
  r->ren.render = "none";
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
