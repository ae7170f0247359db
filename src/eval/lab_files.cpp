// The virtual lab from the command line. Units: mm, N, s, N/mm.
#include "inhap/eval/lab_files.hpp"

#include <fmt/format.h>

#include <cmath>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"

namespace inhap::eval {

lab::Scene pick_scene(const std::string& name, const std::string& file) {
  if (!name.empty() && !file.empty()) throw Error("give either --scene or --scene-file, not both");
  if (!file.empty()) return lab::load_scene(file);
  if (name.empty())
    throw Error("expected --scene NAME or --scene-file FILE.json (see `inhap lab scenes`)");
  return lab::builtin_scene(name);
}

std::string scenes_table() {
  std::string s = fmt::format("{:<21} {:>12}  {}\n", "scene", "k@5N (N/mm)", "description");
  for (const auto& name : lab::builtin_scene_names()) {
    const lab::Scene scene = lab::builtin_scene(name);
    const Vec2 c = scene.region.center;
    const double k = scene.object.stiffness_at(Vec3(c.x(), c.y(), 1e3), 5.0);
    s += fmt::format("{:<21} {:>12.2f}  {}\n", name, k, scene.description);
  }
  return s;
}

void require_finite_recording(const Recording& rec, const std::string& out) {
  for (std::size_t i = 0; i < rec.size(); ++i)
    if (!std::isfinite(rec.t[i]) || !rec.p[i].allFinite() || !rec.f[i].allFinite())
      throw Error(fmt::format(
          "{}: refusing to write row {} (t = {} s): a position or force is not finite (the "
          "scene's sizes or positions are out of range?)",
          out, i + 1, rec.t[i]));
}

lab::RecordSpec lab_record_spec(const LabRecordRequest& a) {
  lab::RecordSpec spec;
  spec.operator_name = a.op;
  spec.seconds = a.seconds;
  spec.seed = a.seed;
  if (a.probe == "tip")
    spec.probe = lab::ProbeSpec::tip();
  else if (a.probe == "sphere")
    spec.probe = lab::ProbeSpec::sphere();
  else
    throw Error(fmt::format("--probe: expected sphere or tip, got '{}'", a.probe));
  spec.noise = !a.no_noise;
  spec.gravity = !a.no_gravity;
  spec.inertia = !a.no_inertia;
  if (a.region != "reachable" && a.region != "top")
    throw Error(fmt::format("--region: expected reachable or top, got '{}'", a.region));
  if (a.whole_object && a.region == "top")
    throw Error(
        "--whole-object asks for the reachable surface (now the default) but --region top for "
        "the top cap: give one of them");
  spec.tap.whole_object = a.region == "reachable";
  if (a.coverage && a.op != "explore")
    throw Error(fmt::format("--coverage: expected --operator explore, got '{}'", a.op));
  spec.explore.coverage = a.coverage;
  spec.physics = lab::physics_from_string(a.physics);
  return spec;
}

std::string long_recording_note(double seconds) {
  if (!(seconds > kLongRecordingS)) return {};
  return fmt::format(
      "note: {:g} s at 1 kHz is {:.0f} rows, about {:.1f} GB of CSV (recording and "
      "truth)\n",
      seconds, seconds * 1000.0, seconds * 1000.0 * kBytesPerTick / 1e9);
}

lab::LabRecording downsample_recording(const lab::LabRecording& in, double rate_hz,
                                       std::uint64_t seed) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz))
    throw Error(fmt::format("--rate: expected a positive rate in Hz, got {}", rate_hz));
  const std::size_t n = in.rec.size();
  if (rate_hz >= 1000.0 || n < 2) return in;
  Rng rng(seed ^ 0x5eedull);
  std::vector<std::size_t> keep;
  const double t0 = in.rec.t.front(), period = 1.0 / rate_hz;
  std::size_t i = 0;
  for (long k = 0;; ++k) {
    const double want = t0 + (static_cast<double>(k) + 0.2 * (2.0 * rng.uniform() - 1.0)) * period;
    while (i + 1 < n && std::abs(in.rec.t[i + 1] - want) <= std::abs(in.rec.t[i] - want)) ++i;
    if (keep.empty() || i > keep.back()) keep.push_back(i);
    if (i + 1 >= n || want > in.rec.t.back()) break;
  }
  lab::LabRecording out;
  out.comments = in.comments;
  out.comments.push_back(
      fmt::format("logged at {:g} Hz (the tick nearest each jittered instant of "
                  "a {:g} Hz logger; servo and physics at 1 kHz)",
                  rate_hz, rate_hz));
  out.rec.extra_names = in.rec.extra_names;
  out.rec.extra.resize(in.rec.extra.size());
  const lab::TruthTable& a = in.truth;
  lab::TruthTable& b = out.truth;
  for (std::size_t j : keep) {
    out.rec.t.push_back(in.rec.t[j]);
    out.rec.p.push_back(in.rec.p[j]);
    out.rec.f.push_back(in.rec.f[j]);
    for (std::size_t c = 0; c < in.rec.extra.size(); ++c)
      out.rec.extra[c].push_back(in.rec.extra[c][j]);
    if (j < a.size()) {
      b.t.push_back(a.t[j]), b.contact.push_back(a.contact[j]), b.tap.push_back(a.tap[j]);
      b.tc.push_back(a.tc[j]), b.c.push_back(a.c[j]), b.anchor.push_back(a.anchor[j]);
      b.force.push_back(a.force[j]), b.k.push_back(a.k[j]), b.mu.push_back(a.mu[j]);
    }
  }
  return out;
}

}  // namespace inhap::eval
