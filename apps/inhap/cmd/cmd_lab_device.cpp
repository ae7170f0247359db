// `inhap lab device`: the virtual lab as a bridge device client (docs/bridge.md), so `inhap
// serve`, `inhap record` and `inhap sys palpate --device udp` run without hardware, across a
// process boundary. Units: mm, N, s.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "command.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/eval/lab_device.hpp"

namespace inhap::cli {
namespace {

struct LabDeviceArgs {
  eval::LabDeviceOptions o;
  std::string probe = "sphere", place;
  int port = 47110;
};

void run_lab_device(LabDeviceArgs a) {
  if (a.port < 1 || a.port > 65535) throw Error("--port: expected 1-65535");
  a.o.port = static_cast<std::uint16_t>(a.port);
  a.o.probe = a.probe == "tip" ? lab::ProbeSpec::tip() : lab::ProbeSpec::sphere();
  if (Vec3 p; !a.place.empty()) {
    if (!parse_number_list(a.place, 3, p.data()))
      throw Error(fmt::format("--place: expected X,Y,Z in mm, got {}", quote_token(a.place)));
    a.o.place = p;
  }
  a.o.progress = [](const std::string& what, double f, double eta) { progress(what, f, eta); };
  fmt::print(stderr, "{}", eval::lab_device_banner(a.o));
  fmt::print(stderr, "{}", eval::lab_device_summary(eval::run_lab_device(a.o)));
}

void register_lab_device(CLI::App& app) {
  CLI::App* lab = subcommand_group(app, "lab", "Virtual lab");
  auto a = std::make_shared<LabDeviceArgs>();
  auto* c = lab->add_subcommand(
      "device",
      "Run the virtual lab as a device client of the UDP bridge (docs/bridge.md): each tick it\n"
      "sends the simulated probe's state (t s, p mm, raw sensor N) to inhap and applies the force\n"
      "(N) it gets back. Start `inhap serve`, `inhap record` or `inhap sys palpate --device udp`\n"
      "first. With an operator and the same scene and seed, its samples are those of\n"
      "`inhap lab record`.");
  c->add_option("--scene", a->o.scene, "built-in scene")->capture_default_str();
  c->add_option("--scene-file", a->o.scene_file, "scene JSON file");
  c->add_option("--operator", a->o.operator_name,
                "tap | explore | air | none (hand detached: the probe only moves under inhap's "
                "forces, e.g. for sys palpate)")
      ->capture_default_str()
      ->check(CLI::IsMember({"tap", "explore", "air", "none"}));
  c->add_option("--seconds", a->o.seconds, "simulated seconds to run")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 86400.0));
  c->add_option("--seed", a->o.seed, "seed, as `inhap lab record --seed`")->capture_default_str();
  cli::add_physics_option(*c, a->o.physics, "builtin | mujoco");
  c->add_option("--probe", a->probe, "sphere (8 mm radius) | tip")
      ->capture_default_str()
      ->check(CLI::IsMember({"sphere", "tip"}));
  c->add_option("--place", a->place,
                "start position X,Y,Z of the probe centre, mm (operator none)");
  c->add_option("--host", a->o.host, "IPv4 address inhap listens on")->capture_default_str();
  c->add_option("--port", a->port, "UDP port inhap listens on")->capture_default_str();
  c->add_option("--key", a->o.key, "shared secret (HMAC-SHA256), as given to inhap");
  c->add_flag("--lockstep", a->o.lockstep,
              "wait for every answer and run as fast as the exchange allows (deterministic; for "
              "tests): a real device cannot wait");
  c->add_option("--answer-timeout", a->o.answer_timeout_s,
                "no answer within this -> zero force for the tick, s (lockstep: 2 s)")
      ->capture_default_str();
  c->add_option("--connect-timeout", a->o.connect_timeout_s,
                "give up if inhap does not answer within this, s")
      ->capture_default_str();
  c->add_option("--silence-stop", a->o.silence_stop_s,
                "after the join, stop when inhap has not answered for this long (it crashed, or "
                "its 'stopping' was lost), s; 0: run all --seconds")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  c->add_option("--out,-o", a->o.out,
                "also write the device side's own recording and truth (OUT.truth.csv)");
  c->callback([a] { run_lab_device(*a); });
}

INHAP_COMMAND(61, "lab device", register_lab_device);

}  // namespace
}  // namespace inhap::cli
