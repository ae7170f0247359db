// The virtual lab behind the C bridge client. See include/inhap/eval/lab_device.hpp.
#include "inhap/eval/lab_device.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include "inhap/core/error.hpp"
#include "inhap/lab/operators.hpp"
#include "inhap/lab/recorder.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap_bridge.h"

namespace inhap::eval {
namespace {

struct Client {
  inhap_bridge b{};
  bool open = false;
  ~Client() {
    if (open) inhap_bridge_close(&b);
  }
};

struct Lab {
  lab::Scene scene;
  lab::RecordSpec spec;
  lab::RecordSetup setup;  // device + operator (operator null for "none")
};

Lab make_lab(const LabDeviceOptions& o) {
  Lab l;
  if (!o.scene_file.empty() && o.scene != "planar" && !o.scene.empty())
    throw Error("give either a scene or a scene file, not both");
  l.scene = !o.scene_file.empty() ? lab::load_scene(o.scene_file) : lab::builtin_scene(o.scene);
  l.spec.operator_name = o.operator_name;
  l.spec.seconds = o.seconds;
  l.spec.seed = o.seed;
  l.spec.probe = o.probe;
  l.spec.physics = lab::physics_from_string(o.physics);
  if (o.operator_name == "none") {
    // As eval::palpate_scene sets up the lab device: the seed is the noise seed, no hand.
    l.setup.params.seed = o.seed;
    l.setup.params.probe = o.probe;
    l.setup.params.physics = l.spec.physics;
    l.setup.device = std::make_unique<lab::SimDevice>(l.scene.object, l.setup.params);
    l.setup.device->detach_hand();
    if (o.place) l.setup.device->place(*o.place);
  } else {
    l.setup = lab::make_record_setup(l.scene, l.spec);
  }
  return l;
}

// Join: sends the device's first state until inhap answers it (its force and status land in f
// and status); throws after connect_timeout_s.
void join(Client& c, const lab::SimDevice& dev, const LabDeviceOptions& o, double f[3],
          std::uint32_t& status) {
  const Vec3 p = dev.position(), s = dev.force_sensor();
  const double pp[3] = {p.x(), p.y(), p.z()}, ss[3] = {s.x(), s.y(), s.z()};
  const auto t0 = std::chrono::steady_clock::now();
  while (inhap_bridge_exchange(&c.b, dev.time(), pp, ss, 0, f, &status, 100000) != 1) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
        o.connect_timeout_s)
      throw Error(fmt::format("lab device: no inhap answered on {}:{} within {:g} s", o.host,
                              o.port, o.connect_timeout_s));
  }
}

}  // namespace

LabDeviceResult run_lab_device(const LabDeviceOptions& o) {
  if (!(o.seconds > 0.0) || o.seconds > 86400.0)
    throw Error("lab device: --seconds must be in (0, 86400]");
  if (!(o.silence_stop_s >= 0.0) || !std::isfinite(o.silence_stop_s))
    throw Error("lab device: --silence-stop must be a finite number of seconds >= 0");
  Lab l = make_lab(o);
  lab::SimDevice& dev = *l.setup.device;
  const double rate = dev.info().servo_rate_hz;
  const long ticks = std::lround(o.seconds * rate);
  const double answer_s = o.lockstep && o.answer_timeout_s == 0.002 ? 2.0 : o.answer_timeout_s;
  const long answer_us = std::max(1L, std::lround(answer_s * 1e6));

  Client c;
  if (inhap_bridge_open(&c.b, o.host.c_str(), o.port, o.key.empty() ? nullptr : o.key.c_str()) != 0)
    throw Error(fmt::format("lab device: cannot open a UDP socket towards {}:{}", o.host, o.port));
  c.open = true;

  // As lab::record: the logger first, then the operator takes the stylus.
  std::unique_ptr<lab::TickLogger> log;
  if (!o.out.empty()) log = std::make_unique<lab::TickLogger>(dev, static_cast<std::size_t>(ticks));
  if (l.setup.op) l.setup.op->begin(dev);

  LabDeviceResult res;
  double f[3] = {0, 0, 0};
  std::uint32_t status = 0;
  join(c, dev, o, f, status);
  const auto start = std::chrono::steady_clock::now();
  auto last_answer = start;
  const long every = std::max(1L, static_cast<long>(rate));
  for (long i = 0; i < ticks; ++i) {
    if (i > 0) {
      const Vec3 p = dev.position(), s = dev.force_sensor();
      const double pp[3] = {p.x(), p.y(), p.z()}, ss[3] = {s.x(), s.y(), s.z()};
      if (inhap_bridge_exchange(&c.b, dev.time(), pp, ss, 0, f, &status, answer_us) == 1) {
        ++res.answered;
        last_answer = std::chrono::steady_clock::now();
      } else {
        ++res.timeouts;
        f[0] = f[1] = f[2] = 0.0;
        const double quiet =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - last_answer).count();
        if (o.silence_stop_s > 0 && quiet >= o.silence_stop_s) {
          res.silent = true;  // inhap is gone (crashed, or its "stopping" was lost)
          break;
        }
      }
    } else {
      ++res.answered;  // the join exchange answered tick 0
    }
    if (status & INHAP_BRIDGE_STATUS_STOPPING) {
      res.stopped = true;
      break;
    }
    const Vec3 force(f[0], f[1], f[2]);
    res.max_force_n = std::max(res.max_force_n, force.norm());
    if (log) log->sample();
    dev.command_force(force);
    if (l.setup.op) l.setup.op->step(dev);
    dev.tick();
    ++res.ticks;
    if (!o.lockstep) {  // keep the device's pace with the wall clock
      std::this_thread::sleep_until(start + std::chrono::duration<double>((i + 1) / rate));
    }
    if (o.progress && (i + 1) % every == 0)
      o.progress("lab device", double(i + 1) / double(ticks), 0);
  }
  if (log) {
    lab::LabRecording rec = log->take();
    rec.comments = l.setup.op ? lab::record_comments(l.scene, l.spec, l.setup)
                              : std::vector<std::string>{fmt::format(
                                    "inhap virtual lab behind the bridge: scene {}, no operator, "
                                    "seed {}, physics {}",
                                    l.scene.name, o.seed, o.physics)};
    lab::write_lab_recording(o.out, rec);
  }
  return res;
}

std::string lab_device_banner(const LabDeviceOptions& o) {
  // The raw sensed force carries the tool's weight: inhap compensates it when told the mass.
  return fmt::format(
      "inhap lab device: scene {}, operator {}, joining inhap on {}:{} (tool mass {:g} kg: give "
      "inhap --tool-mass {:g})\n",
      o.scene_file.empty() ? o.scene : o.scene_file, o.operator_name, o.host, o.port,
      lab::DeviceParams{}.tool_mass_kg, lab::DeviceParams{}.tool_mass_kg);
}

std::string lab_device_summary(const LabDeviceResult& r) {
  return fmt::format(
      "\n{} ticks, {} answered, {} time-outs (zero force){}; largest force {:.3f} N\n", r.ticks,
      r.answered, r.timeouts,
      r.stopped  ? ", inhap stopped the session"
      : r.silent ? ", stopped: inhap went silent"
                 : "",
      r.max_force_n);
}

}  // namespace inhap::eval
