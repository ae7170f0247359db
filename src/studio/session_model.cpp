// inhap studio session: the Model view (see model_view.hpp and docs/studio.md): record a free
// exploration with its truth, train in the background (eval::train_from_file, as `inhap model
// train`), feel the model against the object with A/B and blind answers.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <functional>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/random.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/eval/model_files.hpp"
#include "inhap/eval/sys_bridge.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/studio/session.hpp"
#include "session_rig.hpp"

namespace inhap::studio {

namespace {

nlohmann::json ok(const char* request) {
  return {{"type", "ok"}, {"request", request}};
}

bool ends_with(const std::string& s, const char* ext) {
  const std::string e(ext);
  return s.size() > e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

}  // namespace

void Session::build_model_rig(Rig& rig, const std::string& mode) {
  if (!model_stream_) model_stream_ = std::make_unique<ModelStream>();
  if (!lab_) {
    build_bridged_model_rig(rig, mode);
    return;
  }
  const Box3 b = scene_.object.shape().bounds();
  const Vec3 start(scene_.region.center.x(), scene_.region.center.y(), b.max.z() + 15);
  if (mode == "model_record") {
    std::unique_ptr<lab::HandOperator> op;
    if (model_rec_operator_ == "mouse") {
      auto m = std::make_unique<MouseOperator>(rig.mailbox, start);
      rig.mouse = m.get();
      op = std::move(m);
    }
    rig.rec_device = std::make_unique<RecordingDevice>(scene_, options_.seed, model_rec_seconds_,
                                                       options_.speed, std::move(op));
    rig.recorder = rig.rec_device.get();
    rig.device = rig.recorder;
    rig.comp = CompensatorConfig::from(rig.recorder->device().info());
    rig.renderer = std::make_unique<haptics::NullRenderer>();
    model_stream_->coverage.clear();
    model_stream_->told_full = false;
    return;
  }
  // Feeling: the lab's hand on a device that touches nothing but what the renderer commands (the
  // object's contact law or the model), at the device's own clock.
  lab::DeviceParams dp;
  dp.seed = options_.seed;
  auto m = std::make_unique<MouseOperator>(rig.mailbox, start);
  rig.mouse = m.get();
  rig.lab_device = std::make_unique<LabHandDevice>(out_of_the_way_object(), dp, std::move(m), 1.0);
  rig.device = rig.lab_device.get();
  rig.comp = CompensatorConfig::from(rig.lab_device->device_info());
  {
    std::lock_guard lock(data_mu_);
    rig.bundle = model_bundle_;
  }
  auto r = std::make_unique<CompareRenderer>(scene_.object, dp.probe.radius_mm,
                                             rig.bundle ? &rig.bundle->model : nullptr,
                                             &rig.lab_device->device(), kDeviceForceLimitN);
  const bool model = ab_blind_ ? ab_model_is_b_ == ab_model_ : ab_model_;
  r->use_model(model);
  rig.compare = r.get();
  rig.renderer = std::move(r);
  model_stream_->rmse = {};
  model_stream_->last_point_t = -1;
  model_stream_->points = nlohmann::json::array();
}

// A bridged device: its own hand moves it over its own object. Recording: nothing commanded, the
// loop's observer ring recorded by the streamer (ModelStream::observed). Feeling: the device's
// sensed force is the object; the model is stepped on the same path.
void Session::build_bridged_model_rig(Rig& rig, const std::string& mode) {
  rig.device = bridge_.get();
  rig.comp = CompensatorConfig::from(bridge_->info());
  if (mode == "model_record") {
    rig.renderer = std::make_unique<haptics::NullRenderer>();
    rig.observed = true;
    model_stream_->observed.start(rig.comp, model_rec_seconds_);
    model_stream_->coverage.clear();
    model_stream_->told_full = false;
    return;
  }
  {
    std::lock_guard lock(data_mu_);
    rig.bundle = model_bundle_;
  }
  const double limit = std::min(kDeviceForceLimitN, bridge_->info().max_force_n);
  auto r =
      std::make_unique<CompareRenderer>(rig.comp, rig.bundle ? &rig.bundle->model : nullptr, limit);
  r->use_model(ab_blind_ ? ab_model_is_b_ == ab_model_ : ab_model_);
  rig.compare = r.get();
  rig.renderer = std::move(r);
  model_stream_->rmse = {};
  model_stream_->last_point_t = -1;
  model_stream_->points = nlohmann::json::array();
}

void Session::stream_model(Rig& rig, bool flush) {
  ModelStream& s = *model_stream_;
  const auto now = std::chrono::steady_clock::now();
  if (rig.recorder) {
    TickPoint p;
    while (rig.recorder->ring().pop(p)) s.coverage.add(p);
  }
  if (rig.recorder || rig.observed) {
    const bool full = rig.recorder ? rig.recorder->full() : s.observed.full();
    if (flush || now - s.last_coverage > std::chrono::milliseconds(500) || (full && !s.told_full)) {
      s.last_coverage = now;
      nlohmann::json j = s.coverage.json();
      j["t"] = rig.recorder ? rig.recorder->logged_s() : s.observed.seconds();
      j["seconds"] = model_rec_seconds_;
      j["full"] = full;
      j["operator"] = model_rec_operator_;
      broadcast_(dump_safe(j));
      s.told_full = s.told_full || full;
    }
  }
  if (rig.compare) {
    ComparePoint c;
    while (rig.compare->ring().pop(c)) {
      s.rmse.add(c);
      if (c.t - s.last_point_t >= 0.005 && s.points.size() < 2000) {  // 200 Hz for the plot
        s.last_point_t = c.t;
        const auto r = [](double v) { return std::round(v * 1e4) / 1e4; };
        s.points.push_back({r(c.t), r(c.object.x()), r(c.object.y()), r(c.object.z()),
                            r(c.model.x()), r(c.model.y()), r(c.model.z())});
      }
    }
    if (flush || now - s.last_compare > std::chrono::milliseconds(50)) {
      s.last_compare = now;
      const Vec3 e = s.rmse.rmse();
      nlohmann::json j{{"type", "compare"},
                       {"points", std::move(s.points)},
                       {"rmse", {e.x(), e.y(), e.z()}},
                       {"n", s.rmse.n},
                       {"has_model", rig.compare->has_model()}};
      if (!ab_blind_) j["source"] = rig.compare->using_model() ? "model" : "object";
      s.points = nlohmann::json::array();
      broadcast_(dump_safe(j));
    }
  }
}

std::string Session::do_model_record(const Message& m) {
  const std::string op = get_choice(m, "operator", {"explore", "mouse"});
  const double seconds = get_number_or(m, "seconds", 1, 600, 65);
  const std::string path = get_string(m, "path", 255);
  if (!ends_with(path, ".csv")) throw ProtocolError("model_record: expected a path ending in .csv");
  workspace_.resolve(path);  // the name's rules now, the file at the stop
  stop_rig();
  model_rec_operator_ = lab_ ? op : "device";  // a bridged device is moved by its own hand
  model_rec_seconds_ = seconds;
  model_rec_path_ = path;
  start_rig("model_record");
  nlohmann::json j = ok("model_record");
  j["operator"] = model_rec_operator_;
  j["seconds"] = seconds;
  j["path"] = path;
  return j.dump();
}

std::string Session::do_model_stop() {
  if (rig_ && rig_->observed) return stop_observed_recording();
  if (!rig_ || !rig_->recorder) throw ProtocolError("model_stop: no recording is running");
  const WorkspacePath out = workspace_.output(model_rec_path_);
  const WorkspacePath truth = workspace_.output(lab::truth_path_for(model_rec_path_));
  stop_stream_ = true;
  if (streamer_.joinable()) streamer_.join();
  rig_->loop->stop();
  lab::LabRecording lab = rig_->recorder->take_log();
  const std::string op = model_rec_operator_;
  rig_.reset();
  std::size_t contact = 0;
  for (int c : lab.truth.contact) contact += c != 0;
  const std::size_t rows = lab.rec.size();
  const double seconds = rows ? lab.rec.t.back() - lab.rec.t.front() : 0.0;
  if (rows) with_names({&out, &truth}, [&] { lab::write_lab_recording(out.path(), lab); });
  start_rig("model");
  nlohmann::json j = ok("model_stop");
  j["path"] = rows ? model_rec_path_ : std::string();
  j["truth"] = rows ? lab::truth_path_for(model_rec_path_) : std::string();
  j["rows"] = rows;
  j["contact_rows"] = contact;
  j["seconds"] = seconds;
  j["operator"] = op;
  return j.dump();
}

std::string Session::stop_observed_recording() {
  const WorkspacePath out = workspace_.output(model_rec_path_);
  stop_stream_ = true;
  if (streamer_.joinable()) streamer_.join();
  rig_->loop->stop();
  ObservedRecording& obs = model_stream_->observed;
  haptics::LoopSample ls;  // the streamer is gone: what the loop pushed since its last look
  for (TickPoint p; rig_->ring.pop(ls);) obs.add(ls, p);
  const std::size_t dropped = rig_->loop->stats().dropped_samples;
  rig_.reset();
  const std::size_t contact = obs.contact_rows(), skipped = obs.skipped();
  const double seconds = obs.seconds();
  const Recording rec = obs.take();
  const std::size_t rows = rec.size();
  if (rows) with_names({&out}, [&] { write_recording(out.path(), rec); });
  start_rig("model");
  nlohmann::json j = ok("model_stop");
  j["path"] = rows ? model_rec_path_ : std::string();
  j["truth"] = "";  // a bridged device has none
  j["rows"] = rows;
  j["contact_rows"] = contact;
  j["seconds"] = seconds;
  j["operator"] = model_rec_operator_;
  j["dropped"] = dropped;  // ticks the streamer did not drain in time (the ring was full)
  j["skipped"] = skipped;  // samples whose device time ran backwards
  return j.dump();
}

std::string Session::do_model_train(const Message& m) {
  TrainJob job;
  job.recording = get_string(m, "recording", 255);
  job.out = get_string(m, "out", 255);
  job.proxy = lab_ ? "palpation" : "recording";
  if (m.body.contains("proxy")) job.proxy = get_choice(m, "proxy", {"palpation", "recording"});
  if (!ends_with(job.out, ".json") || job.out.size() < 6)
    throw ProtocolError("model_train: expected out ending in .json");
  if (training_) throw ProtocolError("model_train: a training is running (Cancel it first)");
  workspace_.input(job.recording);  // exists, regular, no link: checked before the thread starts
  workspace_.output(job.out);
  if (job.proxy == "palpation") {
    std::lock_guard lock(data_mu_);
    if (sys_ && palp_mesh_) job.sys = *sys_, job.shape = *palp_mesh_;
  }
  if (job.proxy == "palpation" && !job.sys && !lab_)
    throw ProtocolError("model_train: palpate reference points in the Palpation view first");
  if (train_thread_.joinable()) train_thread_.join();
  train_cancel_ = false;
  training_ = true;
  nlohmann::json j = ok("model_train");
  j["recording"] = job.recording;
  j["out"] = job.out;
  j["proxy"] = job.proxy;
  j["palpation"] = job.sys ? "palpation view" : job.proxy == "palpation" ? "lab scene" : "";
  j["threads"] = 1;
  train_thread_ =
      std::thread([this, job = std::move(job)]() mutable { train_worker(std::move(job)); });
  return j.dump();
}

std::string Session::do_model_cancel() {
  if (!training_) throw ProtocolError("model_cancel: no training is running");
  train_cancel_ = true;
  return ok("model_cancel").dump();
}

void Session::end_training() {
  train_cancel_ = true;
  if (train_thread_.joinable()) train_thread_.join();
}

std::string Session::do_model_source(const Message& m) {
  const std::string src = get_choice(m, "source", {"object", "model", "a", "b", "toggle"});
  if (!rig_ || !rig_->compare) throw ProtocolError("model_source: open the Model view first");
  if (ab_blind_ && (src == "object" || src == "model"))
    throw ProtocolError("model_source: blind mode: choose a or b");
  if (!ab_blind_ && (src == "a" || src == "b"))
    throw ProtocolError("model_source: a or b only in blind mode");
  bool b = ab_model_;  // blind: B selected; else: the model selected
  if (src == "toggle") b = !ab_model_;
  if (src == "a" || src == "object") b = false;
  if (src == "b" || src == "model") b = true;
  const bool model = ab_blind_ ? ab_model_is_b_ == b : b;
  if (model && !rig_->compare->has_model()) {  // a model trained since this rig was built
    {
      std::lock_guard lock(data_mu_);
      if (!model_bundle_) throw ProtocolError("model_source: train a model first");
    }
    stop_rig();
    start_rig("model");
  }
  if (b != ab_model_) ++ab_switches_;
  ab_model_ = b;
  rig_->compare->use_model(model);
  nlohmann::json j = ok("model_source");
  j["blind"] = ab_blind_;
  if (ab_blind_)
    j["source"] = b ? "b" : "a";
  else
    j["source"] = b ? "model" : "object";
  return j.dump();
}

std::string Session::do_model_blind(const Message& m) {
  const bool on = get_bool_or(m, "on", true);
  const std::string path = get_string(m, "path", 255);
  if (!ends_with(path, ".csv")) throw ProtocolError("model_blind: expected a path ending in .csv");
  workspace_.resolve(path);
  {
    std::lock_guard lock(data_mu_);
    if (on && !model_bundle_) throw ProtocolError("model_blind: train a model first");
  }
  if (!rig_ || !rig_->compare) throw ProtocolError("model_blind: open the Model view first");
  ab_blind_ = on;
  ab_path_ = path;
  ab_model_ = false;
  ab_switches_ = 0;
  if (on) {  // a new trial: which of A/B is the model, drawn from the session's seed
    Rng rng(options_.seed * 7919 + static_cast<std::uint64_t>(++ab_trial_));
    ab_model_is_b_ = rng.uniform() < 0.5;
  }
  if (!rig_->compare->has_model()) {
    stop_rig();
    start_rig("model");
  }
  rig_->compare->use_model(on ? !ab_model_is_b_ : false);  // A selected
  nlohmann::json j = ok("model_blind");
  j["blind"] = on;
  j["trial"] = ab_trial_;
  j["source"] = on ? "a" : "object";
  j["path"] = path;
  return j.dump();
}

std::string Session::do_model_answer(const Message& m) {
  const std::string a = get_choice(m, "model", {"a", "b"});
  if (!ab_blind_) throw ProtocolError("model_answer: start blind mode first");
  AbAnswer ans;
  ans.trial = ab_trial_;
  ans.switches = ab_switches_;
  ans.model_is_b = ab_model_is_b_;
  ans.answer_b = a == "b";
  {
    std::lock_guard lock(data_mu_);
    ans.t_s = latest_.t_s;
  }
  std::string csv =
      "# inhap studio Model view: blind A/B answers (which of A/B was the model)\n"
      "trial,model_was,answer,correct,switches,t\n";
  std::vector<AbAnswer> all = ab_answers_;
  all.push_back(ans);
  for (const AbAnswer& x : all)
    csv +=
        fmt::format("{},{},{},{},{},{:.3f}\n", x.trial, x.model_is_b ? "b" : "a",
                    x.answer_b ? "b" : "a", x.model_is_b == x.answer_b ? 1 : 0, x.switches, x.t_s);
  workspace_.write(ab_path_, csv);  // all answers, atomically; then the session changes
  ab_answers_ = std::move(all);
  // The next trial: a new draw, A selected.
  Rng rng(options_.seed * 7919 + static_cast<std::uint64_t>(++ab_trial_));
  ab_model_is_b_ = rng.uniform() < 0.5;
  ab_model_ = false;
  ab_switches_ = 0;
  if (rig_ && rig_->compare) rig_->compare->use_model(!ab_model_is_b_);
  nlohmann::json j = ok("model_answer");
  j["answers"] = ab_answers_.size();
  j["trial"] = ab_trial_;
  j["path"] = ab_path_;
  j["source"] = "a";
  return j.dump();
}

std::string Session::do_model_stats() {
  // The loop's histograms belong to its thread while it runs: the loop of the Model view is
  // stopped, its statistics read, and a fresh one started (the probe starts above the object).
  if (!rig_ || !rig_->compare) throw ProtocolError("model_stats: open the Model view first");
  stop_stream_ = true;
  if (streamer_.joinable()) streamer_.join();
  rig_->loop->stop();
  const haptics::LoopStats s = rig_->loop->stats();
  rig_.reset();
  start_rig("model");
  return nlohmann::json{{"type", "model_stats"},
                        {"ticks", s.ticks},
                        {"overruns", s.overruns},
                        {"period_us", s.period_us},
                        {"step_p50_us", s.step_p50_us},
                        {"step_p99_us", s.step_p99_us},
                        {"step_max_us", s.step_max_us},
                        {"jitter_p50_us", s.jitter_p50_us},
                        {"jitter_p99_us", s.jitter_p99_us},
                        {"jitter_max_us", s.jitter_max_us},
                        {"training", training_.load()}}
      .dump();
}

}  // namespace inhap::studio
