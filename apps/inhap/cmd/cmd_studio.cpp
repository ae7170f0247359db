// `inhap studio`: the servo loop plus a local web page (docs/studio.md): sampling by tapping,
// palpation, exploring a model, the thesis 5.4 participant screen and experimenter window, and
// the Model view (record, train, feel the model against the object).
// Units: mm, N, N/mm, s.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "command.hpp"
#include "inhap/studio/security.hpp"
#include "inhap/studio/server.hpp"
#include "inhap/studio/session.hpp"

namespace inhap::cli {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_studio_signal(int) {
  g_stop.store(true);
}

struct StudioArgs {
  studio::StudioOptions session;
  std::string workspace = "studio-workspace", web_dir;
  int port = 8765;
  double seconds = 0, connect = 60;
  bool port_given = false;
};

void run_studio(const StudioArgs& a) {
  const studio::Workspace workspace(a.workspace);
  const std::string web = studio::find_studio_web_dir(a.web_dir);
  // The session first: a bad --device or --speed fails before anything listens.
  std::atomic<studio::Server*> listening{nullptr};
  studio::Session session(a.session, workspace, [&listening](const std::string& text) {
    if (studio::Server* s = listening.load()) s->broadcast(text);
  });
  // The default port, when taken, moves on to the next free one; a port asked for does not.
  const std::unique_ptr<studio::Server> owned =
      studio::listen_on(a.port, !a.port_given, web, studio::make_token());
  studio::Server& server = *owned;
  listening = owned.get();
  if (!a.port_given && server.port() != a.port)
    fmt::print(stderr, "inhap studio: port {} is in use; listening on {}\n", a.port, server.port());
  std::signal(SIGINT, on_studio_signal);
  std::signal(SIGTERM, on_studio_signal);
  session.start(a.connect);
  server.set_handler([&session](const std::string& text) { return session.handle(text); });
  // stdout: the URL alone on its line (scripts and the browser test read it).
  fmt::print("{}\n", server.url());
  std::fflush(stdout);
  fmt::print(stderr, "inhap studio: {} ({}), workspace {}; open the URL above (Ctrl-C stops)\n",
             a.session.device, session.mode(), workspace.root().string());
  const auto t0 = std::chrono::steady_clock::now();
  while (!g_stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (a.seconds > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >= a.seconds)
      break;
  }
  server.stop_handling();  // no message runs on the session from here on
  session.stop();
  fmt::print(stderr, "inhap studio: stopped ({} samples)\n", session.live_samples());
  if (const std::string l = session.server_latency(); !l.empty())
    fmt::print(stderr, "mouse target handled -> its state sent: {}\n", l);
}

void register_studio(CLI::App& app) {
  auto a = std::make_shared<StudioArgs>();
  auto* c = app.add_subcommand(
      "studio",
      "The servo loop plus a local web page (docs/studio.md): sample an object by tapping and\n"
      "reconstruct it, palpate reference points and fit the sliding yield surfaces (sys.json),\n"
      "explore a model with a stiffness map (TCA-MESH / CBA), run the thesis 5.4 participant\n"
      "screen with an experimenter window, record a free exploration, train the data-driven force\n"
      "model on it and feel it against the object (Model view, lab only). Listens on 127.0.0.1\n"
      "only and prints the URL with its access token. Units: mm, N, N/mm, s.");
  c->add_option("--device", a->session.device,
                "lab:SCENE (the virtual lab: a simulated operator taps for sampling, the mouse "
                "moves the probe through a simulated hand elsewhere) or udp / udp:PORT (a device "
                "over the bridge, docs/bridge.md)")
      ->capture_default_str();
  c->add_option("--workspace", a->workspace,
                "folder the page may read and write in (exports, sessions, answers; created)")
      ->capture_default_str();
  auto* port = c->add_option("--port", a->port,
                             "TCP port on 127.0.0.1 (0: any free port; the default moves on to "
                             "the next free port when taken)")
                   ->capture_default_str()
                   ->check(CLI::Range(0, 65535));
  c->add_option("--speed", a->session.speed,
                "lab:SCENE: simulated seconds per wall-clock second (0.1-20)")
      ->capture_default_str();
  c->add_option("--seed", a->session.seed, "lab:SCENE: seed of the operator and the device noise")
      ->capture_default_str();
  c->add_option("--tool-mass", a->session.tool_mass_kg,
                "udp: mass of the tool beyond the force sensor, kg; its weight and inertia are "
                "removed from the sensed force (`inhap lab device`'s is 0.01)")
      ->capture_default_str();
  c->add_option("--web-dir", a->web_dir,
                "folder with studio/ and node_modules (default: web/ of the source tree, or "
                "INHAP_WEB_DIR)");
  c->add_option("--seconds", a->seconds, "stop after this many seconds (0: at Ctrl-C)")
      ->capture_default_str();
  c->add_option("--connect-timeout", a->connect, "udp: give up if no device joins within this, s")
      ->capture_default_str();
  c->add_flag("--realtime", a->session.realtime, "ask for SCHED_FIFO and mlockall for the loop");
  c->callback([a, port] {
    a->port_given = port->count() > 0;
    run_studio(*a);
  });
}

INHAP_COMMAND(75, "studio", register_studio);

}  // namespace
}  // namespace inhap::cli
