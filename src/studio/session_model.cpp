// inhap studio session: the Model view (see model_view.hpp and docs/studio.md): record a free
// exploration with its truth, train in the background (eval::train_from_file, as `inhap model
// train`), feel the model against the object with A/B and blind answers.
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <functional>

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

// The training was cancelled from the page (thrown at the next stage boundary).
struct Cancelled : Error {
  Cancelled() : Error("cancelled") {}
};

bool ends_with(const std::string& s, const char* ext) {
  const std::string e(ext);
  return s.size() > e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

// The thesis' proxy for training: `inhap sys palpate --scene NAME` (or the Palpation view's
// fit: `sys`, `shape`), then `inhap sys proxy` on the recording `in`; the files as the page
// names them (beside the model, named after its stem).
struct PalpationProxy {
  std::optional<WorkspacePath> sys_file, mesh_file, proxied;
  friction::SysModel sys;
  TriMesh shape;
  std::vector<std::string> files;
};
PalpationProxy palpation_proxy(const Workspace& ws, const lab::Scene& scene, std::uint64_t seed,
                               const std::string& stem, std::optional<friction::SysModel>& sys,
                               std::optional<TriMesh>& shape, const WorkspacePath& in,
                               const Progress& progress,
                               const std::function<void(const std::string&)>& say) {
  PalpationProxy r;
  const std::string sys_name = stem + ".palpation.json";
  const std::string mesh_name = stem + ".palpation.shape.ply";
  const std::string rec_name = stem + ".proxy.csv";
  r.sys_file.emplace(ws.output(sys_name));
  r.mesh_file.emplace(ws.output(mesh_name));
  r.proxied.emplace(ws.output(rec_name));
  const WorkspacePath &sf = *r.sys_file, &mf = *r.mesh_file, &pf = *r.proxied;
  if (sys && shape) {
    say("yield surfaces of the Palpation view");
    with_names({&sf, &mf}, [&] {
      friction::write_sys_json(sf.path(), *sys);
      write_mesh(mf.path(), *shape);
    });
    r.sys = std::move(*sys);
    r.shape = std::move(*shape);
    r.files = {sys_name, mesh_name};
  } else {
    eval::ScenePalpationOptions po;  // `inhap sys palpate --scene NAME` (9 points)
    po.scene = scene.name;
    po.seed = seed;
    po.progress_label = "palpation";
    po.progress = progress;
    say("palpating the lab's " + scene.name + " as `inhap sys palpate` does");
    eval::ScenePalpation pal = eval::palpate_scene(po);
    with_names({&sf}, [&] { eval::write_scene_palpation(sf.path(), pal); });
    std::string text = sf.tidy(eval::scene_palpation_text(sf.path(), pal));
    while (!text.empty() && text.back() == '\n') text.pop_back();
    say(text);
    r.sys = std::move(pal.sys);
    r.shape = std::move(pal.shape_mesh);
    r.files = {sys_name};
  }
  const auto run = with_names({&in, &sf, &mf, &pf}, [&] {
    return eval::proxy_file(sf.path(), mf.path(), in.path(), pf.path(), 0.0, true);
  });
  say(fmt::format("proxy: {} rows, {} in contact, {} sliding -> {}", run.rows, run.counts.contact,
                  run.counts.sliding, rec_name));
  r.files.push_back(rec_name);
  return r;
}

}  // namespace

void Session::build_model_rig(Rig& rig, const std::string& mode) {
  if (!lab_) throw ProtocolError("mode: the Model view needs the lab (--device lab:SCENE)");
  const Box3 b = scene_.object.shape().bounds();
  const Vec3 start(scene_.region.center.x(), scene_.region.center.y(), b.max.z() + 15);
  if (!model_stream_) model_stream_ = std::make_unique<ModelStream>();
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

void Session::stream_model(Rig& rig, bool flush) {
  ModelStream& s = *model_stream_;
  const auto now = std::chrono::steady_clock::now();
  if (rig.recorder) {
    TickPoint p;
    while (rig.recorder->ring().pop(p)) s.coverage.add(p);
    const bool full = rig.recorder->full();
    if (flush || now - s.last_coverage > std::chrono::milliseconds(500) || (full && !s.told_full)) {
      s.last_coverage = now;
      nlohmann::json j = s.coverage.json();
      j["t"] = rig.recorder->logged_s();
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
  if (!lab_) throw ProtocolError("model_record: the Model view needs the lab");
  stop_rig();
  model_rec_operator_ = op;
  model_rec_seconds_ = seconds;
  model_rec_path_ = path;
  start_rig("model_record");
  nlohmann::json j = ok("model_record");
  j["operator"] = op;
  j["seconds"] = seconds;
  j["path"] = path;
  return j.dump();
}

std::string Session::do_model_stop() {
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

void Session::train_worker(TrainJob job) {
  // One thread at the lowest priority: the servo thread (and the page's server) come first.
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string& recording = job.recording;
  const std::string& out = job.out;
  nlohmann::json done{
      {"type", "trained"}, {"recording", recording}, {"out", out}, {"proxy", job.proxy}};
  auto last = std::make_shared<std::chrono::steady_clock::time_point>();
  const Progress progress = [this, last](const std::string& stage, double f, double eta) {
    if (train_cancel_) throw Cancelled();
    const auto now = std::chrono::steady_clock::now();
    if (now - *last < std::chrono::milliseconds(200) && f < 1) return;
    *last = now;
    broadcast_(
        dump_safe({{"type", "train_progress"}, {"stage", stage}, {"fraction", f}, {"eta_s", eta}}));
  };
  auto said = std::make_shared<std::vector<std::string>>();  // what training printed
  const auto say = [this, said](const std::string& note) {
    if (train_cancel_) throw Cancelled();
    said->push_back(note);
    broadcast_(dump_safe({{"type", "train_progress"}, {"note", note}}));
  };
  try {
    const std::string stem = out.substr(0, out.size() - 5);
    const WorkspacePath in = workspace_.input(recording);
    const WorkspacePath dst = workspace_.output(out);
    std::vector<std::string> lines, files;
    eval::TrainFileOptions o;  // the defaults of `inhap model train`
    o.recording = in.path();
    std::optional<friction::SysModel> sys;
    std::optional<TriMesh> shape;
    std::optional<PalpationProxy> pp;
    if (job.proxy == "palpation") {
      pp.emplace(palpation_proxy(workspace_, scene_, options_.seed, stem, job.sys, job.shape, in,
                                 progress, say));
      sys = std::move(pp->sys);
      shape = std::move(pp->shape);
      files = pp->files;
      o.recording = pp->proxied->path();
      o.sys = pp->sys_file->path();
      o.mesh = pp->mesh_file->path();
    }
    o.request.params.threads = 1;
    o.progress = progress;
    o.on_note = say;
    eval::TrainFileResult r =
        with_names({&in, pp ? &*pp->proxied : nullptr}, [&] { return eval::train_from_file(o); });
    if (train_cancel_) throw Cancelled();
    lines = *said;  // the notes of train_from_file came through `say`
    if (!sys && !r.estimate)
      throw Error(fmt::format("{}: has proxy columns; train it with proxy palpation",
                              quote_input(recording, 200)));
    r.model.provenance.recording_path = pp ? stem + ".proxy.csv" : recording;
    if (sys) {
      r.model.provenance.sys_path = stem + ".palpation.json";
      r.model.provenance.mesh_path = stem + ".palpation.shape.ply";
    }
    // In the order of `inhap model train`, each file atomically: the model is written after the
    // files it references (their digests are of the files as written).
    with_names({&in, &dst}, [&] {
      if (r.estimate)
        for (const std::string& f :
             eval::write_estimate_files(dst.path(), *r.estimate, r.model.provenance))
          files.push_back(dst.tidy(f));
      datadriven::save_force_model(dst.path(), r.model);
      lines.push_back(eval::range_note(r.model.provenance, r.set, o.force_limit_n));
      for (const std::string& l :
           eval::write_training_coverage(r.set, datadriven::coverage_path_for(dst.path())))
        lines.push_back(dst.tidy(l));
    });
    files.insert(files.begin(), out);
    files.push_back(datadriven::coverage_path_for(out));
    lines.push_back(eval::train_summary(r.model, false));
    auto bundle =
        sys ? std::make_shared<DataDrivenBundle>(r.model.model, std::move(*sys), *shape, 0.0)
            : std::make_shared<DataDrivenBundle>(r.model.model, r.estimate->sys, r.estimate->mesh,
                                                 0.0);
    CoverageTracker cov;  // the training set's coverage (its proxy), as written
    for (std::size_t i = 0; i < r.set.size(); ++i)
      cov.add(TickPoint{double(i) * 1e-3, r.set.q[i], r.set.f[i], true});
    const auto& st = r.model.provenance.stats;
    done["status"] = "done";
    done["lines"] = lines;
    done["files"] = files;
    done["samples"] = st.samples;
    done["fit_s"] = st.seconds;
    done["support"] = st.support;
    done["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    done["threads"] = 1;
    done["coverage"] = cov.json();
    std::lock_guard lock(data_mu_);
    model_bundle_ = std::move(bundle);
    model_name_ = out;
  } catch (const Cancelled&) {
    done["status"] = "cancelled";
  } catch (const std::exception& e) {
    done["status"] = "failed";
    done["message"] = quote_input(e.what(), 1024);
  } catch (...) {
    done["status"] = "failed";
    done["message"] = "internal error";
  }
  training_ = false;
  broadcast_(dump_safe(done));
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
