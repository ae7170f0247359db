// The virtual user study of thesis sec. 5.4 and the servo-step timing (eval/tca_study.hpp).
// Units: mm, N, N/mm, s; step times in microseconds.
#include "inhap/eval/tca_study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/lab/participant.hpp"
#include "inhap/rendering/datasets.hpp"

namespace inhap::eval {

namespace {

double tca_seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TcaStudyResult run_tca_study(const TcaStudyOptions& o) {
  if (o.participants < 1 || o.trials < 1)
    throw Error(fmt::format("--participants and --trials must be >= 1, got {} and {}",
                            o.participants, o.trials));
  TcaStudyResult r;
  r.config.participants = o.participants;
  r.config.trials = o.trials;
  r.config.seed = o.seed;
  const rendering::StudyConfig& cfg = r.config;
  const long total = long(o.participants) * long(rendering::participant_schedule(cfg, 0).size());
  std::vector<std::vector<rendering::TrialResult>> per(o.participants);
  std::atomic<int> next{0};
  std::atomic<long> done{0};
  std::mutex progress_mutex;
  const auto start = std::chrono::steady_clock::now();
  auto worker = [&] {
    for (int p = next++; p < o.participants; p = next++) {
      lab::VirtualParticipant vp(lab::sample_participant(o.seed * 1000003ull + std::uint64_t(p)));
      for (const auto& spec : rendering::participant_schedule(cfg, p)) {
        per[p].push_back(rendering::run_trial(vp, vp, spec));
        const long d = ++done;
        if (!o.progress) continue;
        std::lock_guard lock(progress_mutex);
        const double el = tca_seconds_since(start);
        o.progress(fmt::format("{} of {} trials", d, total), double(d) / double(total),
                   d < total ? el / double(d) * double(total - d) : 0.0);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, o.threads); ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  for (auto& v : per) r.trials.insert(r.trials.end(), v.begin(), v.end());
  r.summary = rendering::summarize(r.trials);
  r.study_s = tca_seconds_since(start);
  for (const auto& t : r.trials) r.incomplete += !t.session.completed;
  return r;
}

TcaConditions tca_conditions(const rendering::StudySummary& s) {
  using rendering::Algorithm;
  using rendering::Task;
  return {s.get(Algorithm::kTCA, Task::kShape), s.get(Algorithm::kCBA, Task::kShape),
          s.get(Algorithm::kTCA, Task::kStiffness), s.get(Algorithm::kCBA, Task::kStiffness)};
}

TriMesh tca_timing_surface(std::uint64_t seed, const std::string& afm) {
  if (afm.empty()) return rendering::afm_like_surface(seed);
  Grid raw = read_wsxm_top(afm);
  level_plane(raw);
  const int n = 257;
  Grid h = resample_bilinear(raw, n), k(n, n);
  const double lo = raw.min(), span = std::max(raw.max() - lo, 1e-12);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double v = h.at(x, y);
      h.at(x, y) = 10.0 * (v - lo) / span;
      k.at(x, y) = 1.0 - 0.8 * (v - lo) / span;
    }
  return grid_to_mesh(h, 100.0 / (n - 1), &k);
}

StepTiming time_servo_steps(const rendering::Model& model, rendering::Algorithm algorithm) {
  rendering::State state;
  const Box3 b = model.mesh().bbox();
  std::vector<double> us;
  long contact = 0;
  const double force = 1.5, speed = 0.04;  // N, mm per tick (40 mm/s at 1 kHz)
  for (double y = b.min.y() + 5; y < b.max.y() - 4; y += 10) {
    Vec3 p(b.min.x() + 2, y, b.max.z() + 2);
    for (double x = b.min.x() + 2; x < b.max.x() - 2; x += speed) {
      p.x() = x;
      const auto t0 = std::chrono::steady_clock::now();
      const Vec3 f = rendering::step(model, state, p, algorithm);
      const auto t1 = std::chrono::steady_clock::now();
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
      contact += state.collision;
      p.z() += std::clamp(0.3 * (f.norm() - force), -0.05, 0.05);  // hand: push until 1.5 N
    }
    for (int i = 0; i < 200; ++i)
      rendering::step(model, state, Vec3(p.x(), p.y(), b.max.z() + 2), algorithm);  // lift
  }
  StepTiming t;
  t.steps = static_cast<long>(us.size());
  t.contact_steps = contact;
  if (us.empty()) return t;
  std::sort(us.begin(), us.end());
  t.p50 = us[us.size() / 2];
  t.p99 = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  t.max = us.back();
  return t;
}

}  // namespace inhap::eval
