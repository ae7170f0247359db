// inhap studio session: the Model view's training (see model_view.hpp and docs/studio.md), as
// `inhap model train` does it (eval::train_from_file), in a process of its own.
//
// Why a process: Linux groups the threads of one session for the CPU (autogroup: each session
// gets a fair share, and nice only ranks threads inside one group). A training thread at nice 19
// still spent the studio's whole share, and under load from other sessions the servo thread then
// waited for that share to come round again (its run delay equalled its lateness: measured, no
// page faults, no lock). The training runs in a forked child that starts a session of its own
// (setsid), so a CPU group of its own: it gets a session's share as any other program does, and
// the studio's group keeps its share for the servo loop. (The child's group stays at nice 0: at
// nice 19 it got under 2 % of a core on a loaded machine and the training did not finish.) Where
// the kernel has no autogroups, the child's nice 19 ranks it below the servo thread.
//
// The child writes every file to a temporary in the workspace (TrainingFiles) and reports its
// progress and result as JSON lines on a pipe; the session's thread relays the progress, and
// when the child is done renames all the temporaries onto their names in one OutputTransaction
// (all or none), then loads the model for feeling. Cancel kills the child; its temporaries
// (named after a random token) are removed.
#include <dirent.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <thread>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/cancel.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/eval/model_files.hpp"
#include "inhap/eval/sys_bridge.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/studio/model_view.hpp"
#include "inhap/studio/session.hpp"

namespace inhap::studio {

namespace {

// The training was cancelled from the page.
struct Cancelled : Error {
  Cancelled() : Error("cancelled") {}
};

double process_cpu_s() {  // user + system CPU seconds of this process (every thread)
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The files of one training, all or nothing. The intermediate files (the yield surfaces, the
// shape, the proxied recording) are written to exclusive temporaries beside their names, in the
// workspace's folder handles, and read from there; the model and its companions are written in
// an OutputTransaction (AtomicFile's temporaries, O_EXCL | O_NOFOLLOW), which also takes the
// intermediate temporaries; its commit() renames them all onto their names, or puts every name
// back as it was. Destroyed before (a failure, Cancel), the temporaries are removed: none of the
// files appears and the old ones stay.
class TrainingFiles {
 public:
  /// `stem`: the model's name without ".json"; every file of the training starts with it.
  TrainingFiles(const Workspace& ws, std::string stem, int fail_nth)
      : ws_(ws),
        stem_(std::move(stem)),
        tmp_stem_(stem_ + ".part-" + random_hex()),
        fail_nth_(fail_nth) {}
  ~TrainingFiles() {
    if (!handed_)
      for (const auto& f : staged_) std::remove(f->tmp.c_str());
    if (armed_) fault::fail_nth_write(0);
  }
  /// What a forked child has: the same temporaries' names, nothing staged yet; it removes
  /// nothing when destroyed (the training thread of a sanitizer build: the parent stages the
  /// names the training reports, or sweeps them).
  struct Twin {};
  TrainingFiles(const TrainingFiles& o, Twin)
      : ws_(o.ws_), stem_(o.stem_), tmp_stem_(o.tmp_stem_), fail_nth_(o.fail_nth_) {
    handed_ = true;
  }
  TrainingFiles(const TrainingFiles&) = delete;
  TrainingFiles& operator=(const TrainingFiles&) = delete;
  struct Staged {
    WorkspacePath dst;  ///< the name's folder handle + the name
    std::string tmp;    ///< its temporary, through the same handle
  };
  /// The temporary of `name` (stem + rest): stem.part-RANDOM + rest, beside it (a writer's
  /// sidecars, named after its output, so land on the temporaries of their own names).
  const Staged& stage(const std::string& name) {
    WorkspacePath dst = ws_.output(name);
    const std::string tmp_name = tmp_stem_ + name.substr(stem_.size());
    const std::string dir = dst.path().substr(0, dst.path().rfind('/') + 1);
    std::string tmp = dir + std::filesystem::path(tmp_name).filename().string();
    staged_.push_back(std::make_unique<Staged>(Staged{std::move(dst), std::move(tmp)}));
    return *staged_.back();
  }
  /// `text` with the temporaries' names replaced by the names.
  std::string tidy(std::string text) const {
    for (std::size_t at = text.find(tmp_stem_); at != std::string::npos;
         at = text.find(tmp_stem_, at + stem_.size()))
      text.replace(at, tmp_stem_.size(), stem_);
    return text;
  }
  /// Before each file written: the fault injection of the tests (StudioOptions).
  void next_file() {
    if (++written_ == fail_nth_) {
      fault::fail_nth_write(1);
      armed_ = true;
    }
  }
  /// The staged temporaries become the transaction's (it renames or removes them).
  void hand_to(OutputTransaction& tx) {
    for (const auto& f : staged_) tx.defer(f->tmp, f->dst.path());
    handed_ = true;
  }
  /// The names staged so far, in order.
  std::vector<std::string> names() const {
    std::vector<std::string> v;
    for (const auto& f : staged_) v.push_back(name_of(*f));
    return v;
  }
  /// Removes every file in the folder of `out` named after the random token: the temporaries,
  /// and those of a writer killed half-way (AtomicFile's own beside them).
  void sweep(const WorkspacePath& out) const {
    const std::string prefix = std::filesystem::path(tmp_stem_).filename().string();
    // A description of its own ("."): a dup would share the folder's read position.
    const int fd = ::openat(out.fd(), ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    DIR* d = fd >= 0 ? ::fdopendir(fd) : nullptr;
    if (!d) {
      if (fd >= 0) ::close(fd);
      return;
    }
    std::vector<std::string> doomed;
    while (const dirent* e = ::readdir(d))
      if (std::string_view(e->d_name).rfind(prefix, 0) == 0) doomed.emplace_back(e->d_name);
    for (const std::string& n : doomed) ::unlinkat(::dirfd(d), n.c_str(), 0);
    ::closedir(d);
  }

 private:
  static std::string random_hex() {
    unsigned char b[8] = {};
    if (::getrandom(b, sizeof b, 0) != static_cast<ssize_t>(sizeof b))
      throw Error("getrandom failed");
    std::string hex;
    for (unsigned char c : b) hex += fmt::format("{:02x}", c);
    return hex;
  }
  std::string name_of(const Staged& f) const {  // the workspace name of a staged file
    return stem_ + f.tmp.substr(f.tmp.rfind('/') + 1 +
                                std::filesystem::path(tmp_stem_).filename().string().size());
  }
  const Workspace& ws_;
  std::string stem_, tmp_stem_;
  std::vector<std::unique_ptr<Staged>> staged_;  // stable addresses
  int fail_nth_ = 0, written_ = 0;
  bool handed_ = false, armed_ = false;
};

// The thesis' proxy for training: `inhap sys palpate --scene NAME` (or the Palpation view's
// fit: `sys`, `shape`), then `inhap sys proxy` on the recording `in`; the files as the page
// names them (beside the model, named after its stem).
struct PalpationProxy {
  const TrainingFiles::Staged *sys_file = nullptr, *mesh_file = nullptr, *proxied = nullptr;
  friction::SysModel sys;
  TriMesh shape;
  std::vector<std::string> files;
};
PalpationProxy palpation_proxy(TrainingFiles& tf, const lab::Scene& scene, std::uint64_t seed,
                               const std::string& stem, std::optional<friction::SysModel>& sys,
                               std::optional<TriMesh>& shape, const WorkspacePath& in,
                               const Progress& progress,
                               const std::function<void(const std::string&)>& say) {
  PalpationProxy r;
  const std::string sys_name = stem + ".palpation.json";
  const std::string mesh_name = stem + ".palpation.shape.ply";
  const std::string rec_name = stem + ".proxy.csv";
  const TrainingFiles::Staged& sf = tf.stage(sys_name);
  const TrainingFiles::Staged& mf = tf.stage(mesh_name);
  r.sys_file = &sf;
  r.mesh_file = &mf;
  if (sys && shape) {
    say("yield surfaces of the Palpation view");
    with_names({&sf.dst, &mf.dst}, [&] {
      tf.next_file();
      friction::write_sys_json(sf.tmp, *sys);
      tf.next_file();
      write_mesh(mf.tmp, *shape);
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
    // `sys palpate`'s four files (sys.json and its sidecars, named after it).
    tf.stage(stem + ".palpation.cycles.csv");
    tf.stage(stem + ".palpation.refs.csv");
    with_names({&sf.dst}, [&] {
      tf.next_file();
      eval::write_scene_palpation(sf.tmp, pal);
    });
    std::string text = tf.tidy(sf.dst.tidy(eval::scene_palpation_text(sf.tmp, pal)));
    while (!text.empty() && text.back() == '\n') text.pop_back();
    say(text);
    r.sys = std::move(pal.sys);
    r.shape = std::move(pal.shape_mesh);
    r.files = {sys_name, stem + ".palpation.cycles.csv", mesh_name, stem + ".palpation.refs.csv"};
  }
  const TrainingFiles::Staged& pf = tf.stage(rec_name);
  r.proxied = &pf;
  const auto run = with_names({&in, &sf.dst, &mf.dst, &pf.dst}, [&] {
    tf.next_file();
    return eval::proxy_file(sf.tmp, mf.tmp, in.path(), pf.tmp, 0.0, true);
  });
  say(fmt::format("proxy: {} rows, {} in contact, {} sliding -> {}", run.rows, run.counts.contact,
                  run.counts.sliding, rec_name));
  r.files.push_back(rec_name);
  return r;
}

// Writes all of `s` to `fd`; false when the reader is gone.
bool write_all(int fd, std::string s) {
  s += '\n';
  for (std::size_t at = 0; at < s.size();) {
    const ssize_t n = ::write(fd, s.data() + at, s.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    at += static_cast<std::size_t>(n);
  }
  return true;
}

struct ChildJob {
  std::string recording, out, proxy;
  std::optional<friction::SysModel> sys;  // the Palpation view's, when fitted
  std::optional<TriMesh> shape;
};

// The child's work: every file to its temporary, the progress and the result as JSON lines on
// `fd`. Returns the result line ({"type":"result", "status":"done"|"failed", ...}).
nlohmann::json train_child(const Workspace& ws, const lab::Scene& scene, std::uint64_t seed,
                           ChildJob& job, TrainingFiles& tf, int fd) {
  const double cpu0 = process_cpu_s();
  auto last = std::chrono::steady_clock::time_point();
  const Progress progress = [&](const std::string& stage, double f, double eta) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(200) && f < 1) return;
    last = now;
    if (!write_all(
            fd,
            dump_safe(
                {{"type", "train_progress"}, {"stage", stage}, {"fraction", f}, {"eta_s", eta}})))
      throw Cancelled();  // nobody listens any more
  };
  std::vector<std::string> lines;  // what training printed
  const auto say = [&](const std::string& note) {
    lines.push_back(note);
    if (!write_all(fd, dump_safe({{"type", "train_progress"}, {"note", note}}))) throw Cancelled();
  };
  nlohmann::json res{{"type", "result"}};
  try {
    const std::string& out = job.out;
    const std::string stem = out.substr(0, out.size() - 5);
    const WorkspacePath in = ws.input(job.recording);
    const WorkspacePath dst = ws.output(out);
    eval::TrainFileOptions o;  // the defaults of `inhap model train`
    o.recording = in.path();
    std::optional<friction::SysModel> sys;
    std::optional<PalpationProxy> pp;
    if (job.proxy == "palpation") {
      pp.emplace(palpation_proxy(tf, scene, seed, stem, job.sys, job.shape, in, progress, say));
      sys = std::move(pp->sys);
      o.recording = pp->proxied->tmp;
      o.sys = pp->sys_file->tmp;
      o.mesh = pp->mesh_file->tmp;
    }
    o.request.params.threads = 1;
    o.progress = progress;
    o.on_note = [&](const std::string& note) { say(tf.tidy(note)); };
    eval::TrainFileResult r = with_names({&in, pp ? &pp->proxied->dst : nullptr},
                                         [&] { return eval::train_from_file(o); });
    if (!sys && !r.estimate)
      throw Error(fmt::format("{}: has proxy columns; train it with proxy palpation",
                              quote_input(job.recording, 200)));
    r.model.provenance.recording_path = pp ? stem + ".proxy.csv" : job.recording;
    if (sys) {
      r.model.provenance.sys_path = stem + ".palpation.json";
      r.model.provenance.mesh_path = stem + ".palpation.shape.ply";
    }
    // In the order of `inhap model train`: the model after the files it references (their
    // digests are of the files as written), every one to its temporary.
    const TrainingFiles::Staged& model = tf.stage(out);
    const TrainingFiles::Staged& cov_file = tf.stage(datadriven::coverage_path_for(out));
    with_names({&in, &dst}, [&] {
      if (r.estimate) {
        tf.stage(stem + ".surface.ply");
        tf.stage(stem + ".sys.json");
        tf.next_file();
        eval::write_estimate_files(model.tmp, *r.estimate, r.model.provenance);
        r.model.provenance.sys_path = tf.tidy(r.model.provenance.sys_path);
        r.model.provenance.mesh_path = tf.tidy(r.model.provenance.mesh_path);
      }
      tf.next_file();
      datadriven::save_force_model(model.tmp, r.model);
      lines.push_back(eval::range_note(r.model.provenance, r.set, o.force_limit_n));
      tf.next_file();
      for (const std::string& l : eval::write_training_coverage(r.set, cov_file.tmp))
        lines.push_back(tf.tidy(cov_file.dst.tidy(l)));
    });
    lines.push_back(eval::train_summary(r.model, false));
    CoverageTracker cov;  // the training set's coverage (its proxy), as written
    for (std::size_t i = 0; i < r.set.size(); ++i)
      cov.add(TickPoint{double(i) * 1e-3, r.set.q[i], r.set.f[i], true});
    const auto& st = r.model.provenance.stats;
    res["status"] = "done";
    res["files"] = tf.names();
    res["sys"] = sys ? stem + ".palpation.json" : stem + ".sys.json";
    res["mesh"] = sys ? stem + ".palpation.shape.ply" : stem + ".surface.ply";
    res["samples"] = st.samples;
    res["fit_s"] = st.seconds;
    res["support"] = st.support;
    res["coverage"] = cov.json();
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& e) {
    res["status"] = "failed";
    res["message"] = quote_input(tf.tidy(e.what()), 1024);
  }
  res["lines"] = lines;
  res["cpu_s"] = process_cpu_s() - cpu0;
  return res;
}

// The child process: a session (and so a CPU group) of its own; dies with the studio. Never
// returns.
[[noreturn]] void child_main(const Workspace& ws, const lab::Scene& scene, std::uint64_t seed,
                             ChildJob& job, TrainingFiles& tf, int fd, pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);
  ::setsid();                          // a CPU group of its own (autogroup)
  ::setpriority(PRIO_PROCESS, 0, 19);  // the lowest priority where there are no such groups
  int code = 1;
  try {
    const nlohmann::json r = train_child(ws, scene, seed, job, tf, fd);
    code = write_all(fd, dump_safe(r)) ? 0 : 1;
  } catch (...) {
  }
  ::_exit(code);  // no destructors, no atexit: the parent's threads are not here
}

// Under AddressSanitizer the training runs in a thread of this process instead: GCC 12's ASan
// allocator is not locked around fork(), so a forked child can wait for ever on an allocator
// lock that another thread of the studio held at the fork (seen in the sanitizer suite:
// StudioModelSession.TrainingFilesLandAllOrNone, the child blocked in asan_malloc).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kTrainInThread = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kTrainInThread = true;
#else
constexpr bool kTrainInThread = false;
#endif
#else
constexpr bool kTrainInThread = false;
#endif

// The training thread of a sanitizer build: cancelled (through the library's cancel flag) and
// joined when left, its pipe drained meanwhile (a full pipe would block its writes), before the
// pipe's read end `fd` closes.
struct TrainThread {
  CancelFlag flag;
  std::atomic<bool> done{false};
  std::thread thread;
  int fd = -1;
  ~TrainThread() {
    flag.request();
    if (!thread.joinable()) return;
    char b[4096];
    while (!done) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 50) > 0 && ::read(fd, b, sizeof b) == 0) break;  // closed
    }
    thread.join();
  }
};

// The parent's end of the child: killed and reaped when left early.
struct Child {
  pid_t pid = -1;
  int fd = -1;
  int status = 0;
  ~Child() {
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      reap();
    }
    if (fd >= 0) ::close(fd);
  }
  void reap() {
    while (pid > 0 && ::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    pid = -1;
  }
};

// Relays the child's progress lines to `broadcast` until it closes the pipe; returns its result
// line (null when it sent none). Throws Cancelled as soon as `cancel` is set.
nlohmann::json relay(Child& child, const std::atomic<bool>& cancel,
                     const std::function<void(const std::string&)>& broadcast) {
  nlohmann::json result;
  std::string buf;
  for (;;) {
    if (cancel) throw Cancelled();
    pollfd p{child.fd, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    char b[65536];
    const ssize_t n = ::read(child.fd, b, sizeof b);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return result;  // the child is gone
    buf.append(b, static_cast<std::size_t>(n));
    for (std::size_t nl; (nl = buf.find('\n')) != std::string::npos; buf.erase(0, nl + 1)) {
      nlohmann::json j = nlohmann::json::parse(buf.substr(0, nl), nullptr, false);
      if (!j.is_object()) continue;
      if (j.value("type", "") == "result")
        result = std::move(j);
      else
        broadcast(dump_safe(j));
    }
  }
}

}  // namespace

void Session::train_worker(TrainJob job) {
  // This thread only relays; the work is the child's (see the top of this file).
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
  const auto t0 = std::chrono::steady_clock::now();
  const std::string& out = job.out;
  nlohmann::json done{
      {"type", "trained"}, {"recording", job.recording}, {"out", out}, {"proxy", job.proxy}};
  std::optional<WorkspacePath> dst;
  std::optional<TrainingFiles> tf;
  try {
    dst.emplace(workspace_.output(out));
    tf.emplace(workspace_, out.substr(0, out.size() - 5), options_.fail_training_file);
    ChildJob cj{job.recording, out, job.proxy, std::move(job.sys), std::move(job.shape)};
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw Error("training: cannot create a pipe");
    Child child;
    child.fd = fds[0];
    TrainThread in_thread;  // declared after `child`: joined before the pipe closes
    in_thread.fd = fds[0];
    if (kTrainInThread) {
      in_thread.thread = std::thread([&, fd = fds[1]] {
        CancelScope scope(&in_thread.flag);
        try {
          TrainingFiles twin(*tf, TrainingFiles::Twin{});
          write_all(fd, dump_safe(train_child(workspace_, scene_, options_.seed, cj, twin, fd)));
        } catch (...) {
        }
        ::close(fd);
        in_thread.done = true;
      });
    } else {
      const pid_t parent = ::getpid();
      child.pid = ::fork();
      if (child.pid == 0) {
        ::close(fds[0]);
        child_main(workspace_, scene_, options_.seed, cj, *tf, fds[1], parent);
      }
      ::close(fds[1]);
      if (child.pid < 0) throw Error("training: cannot start the training process");
    }
    nlohmann::json result = relay(child, train_cancel_, broadcast_);
    child.reap();
    if (train_cancel_) throw Cancelled();
    if (!result.is_object())
      throw Error(WIFSIGNALED(child.status)
                      ? fmt::format("the training process died (signal {})", WTERMSIG(child.status))
                      : "the training process ended without a result");
    done["lines"] = result["lines"];
    if (result.value("status", "") != "done") throw Error(result.value("message", "failed"));
    // Every file at once: the temporaries renamed onto their names, or none.
    for (const auto& f : result["files"]) tf->stage(f.get<std::string>());
    with_names({&*dst}, [&] {
      OutputTransaction tx;
      tf->hand_to(tx);
      tx.commit();
    });
    const WorkspacePath sys_in = workspace_.input(result.value("sys", ""));
    workspace_.input(result.value("mesh", ""));  // a regular file, no link: then by its name
    const WorkspacePath mesh_in = workspace_.output(result.value("mesh", ""));  // (the reader
    // chooses the format by the extension, which the handle's path has not)
    const WorkspacePath model_in = workspace_.input(out);
    auto bundle = with_names({&sys_in, &mesh_in, &model_in}, [&] {
      return std::make_shared<DataDrivenBundle>(datadriven::load_force_model(model_in.path()),
                                                friction::read_sys_json(sys_in.path()),
                                                read_mesh(mesh_in.path()), 0.0);
    });
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    done["status"] = "done";
    done["files"] = result["files"];
    for (const char* k : {"samples", "fit_s", "support", "coverage"}) done[k] = result[k];
    done["wall_s"] = wall;
    done["threads"] = 1;
    done["cpu_s"] = result.value("cpu_s", 0.0);  // the child's CPU time (every thread)
    done["cores"] = wall > 0 ? result.value("cpu_s", 0.0) / wall : 0.0;
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
  if (tf && dst) tf->sweep(*dst);  // a killed child's temporaries
  training_ = false;
  broadcast_(dump_safe(done));
}

}  // namespace inhap::studio
