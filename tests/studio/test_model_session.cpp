// The Model view driven through the session, no browser (session_model.cpp): a training's files
// land all or none (a failure in the second file or a Cancel leaves none of them and the old ones
// intact); a training after a Palpation view fit uses those yield surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/sys_lab.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/lab/sim_device.hpp"
#include "inhap/studio/security.hpp"
#include "inhap/studio/session.hpp"
#include "support/broadcasts.hpp"
#include "support/slow.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using namespace inhap::studio;
namespace fs = std::filesystem;

namespace {

// A session on a lab scene over the folder `root`, its broadcasts kept for waiting on.
struct Lab : test::Broadcasts {
  /// `speed`: the lab's simulated seconds per wall second. 20 records fast; a session that only
  /// trains takes 1, so that its device and servo loop leave the cores to the (nice 19) training
  /// (at 20 under ASan they took both: a training of 15 s did not end in 600 s).
  Lab(const fs::path& root, const std::string& scene, int fail_training_file = 0, double speed = 20)
      : ws(root),
        session(options(scene, fail_training_file, speed), ws,
                [this](const std::string& m) { add(m); }) {
    session.start();
  }
  static StudioOptions options(const std::string& scene, int fail, double speed) {
    StudioOptions o;
    o.device = "lab:" + scene;
    o.speed = speed;
    o.seed = 1;
    o.fail_training_file = fail;
    return o;
  }
  nlohmann::json send(const nlohmann::json& m) {
    return nlohmann::json::parse(session.handle(m.dump()), nullptr, false);
  }
  /// The Model view, a recording of `seconds` simulated s with the explore operator in rec.csv.
  void record(double seconds) {
    ASSERT_EQ(send({{"type", "mode"}, {"mode", "model"}}).value("type", ""), "ok");
    ASSERT_EQ(send({{"type", "model_record"},
                    {"operator", "explore"},
                    {"seconds", seconds},
                    {"path", "rec.csv"}})
                  .value("type", ""),
              "ok");
    ASSERT_FALSE(wait("coverage", 120 * test::slow_factor(), [](const nlohmann::json& j) {
                   return j.value("full", false);
                 }).is_null());
    ASSERT_GT(send({{"type", "model_stop"}}).value("rows", 0), 0);
  }
  /// Trains rec.csv into `out`; the "trained" broadcast, or {"status": "no trained broadcast"}
  /// when none came in time (the training runs on a lowest-priority thread: under the sanitizers
  /// and a loaded machine it has taken over 600 s).
  nlohmann::json train(const std::string& out) {
    const auto r = send({{"type", "model_train"}, {"recording", "rec.csv"}, {"out", out}});
    if (r.value("type", "") != "ok") return r;
    const auto t = wait("trained", 600 * test::slow_factor());
    return t.is_null() ? nlohmann::json{{"status", "no trained broadcast"}} : t;
  }
  Workspace ws;
  Session session;
};

// Every file in the folder and its content.
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_regular_file()) m[e.path().filename().string()] = read_file(e.path().string());
  return m;
}

// The files of `root` that differ from `old` (new, changed or gone), "" when none.
std::string changes(const fs::path& root, const std::map<std::string, std::string>& old) {
  const auto now = snapshot(root);
  std::string d;
  for (const auto& [name, content] : now)
    if (!old.count(name))
      d += " new " + name;
    else if (old.at(name) != content)
      d += " changed " + name;
  for (const auto& [name, content] : old)
    if (!now.count(name)) d += " gone " + name;
  return d;
}

}  // namespace

TEST(StudioModelSession, TrainingFilesLandAllOrNone) {
  test::TempDir dir;
  std::map<std::string, std::string> old;
  {  // The recording.
    Lab lab(dir.root(), "planar");
    lab.record(15);
  }
  {  // A training that succeeds: the old files.
    Lab lab(dir.root(), "planar", 0, 1);
    ASSERT_EQ(lab.send({{"type", "mode"}, {"mode", "model"}}).value("type", ""), "ok");
    const auto t = lab.train("m.json");
    ASSERT_EQ(t.value("status", ""), "done") << t.dump();
    old = snapshot(dir.root());
    for (const auto& f : t["files"]) EXPECT_TRUE(old.count(f.get<std::string>())) << f;
    for (const char* f : {"m.json", "m.coverage.csv", "m.palpation.json", "m.palpation.shape.ply",
                          "m.palpation.cycles.csv", "m.palpation.refs.csv", "m.proxy.csv"})
      EXPECT_TRUE(old.count(f)) << f;
    EXPECT_EQ(t.value("threads", 0), 1);
    EXPECT_GT(t.value("cpu_s", 0.0), 0.0);
  }
  {  // The second file of the training fails to write: no file changes, no temporary stays.
    Lab lab(dir.root(), "planar", 2, 1);
    const auto t = lab.train("m.json");
    EXPECT_EQ(t.value("status", ""), "failed") << t.dump();
    EXPECT_NE(t.value("message", "").find("m.proxy.csv"), std::string::npos) << t.dump();
    EXPECT_EQ(changes(dir.root(), old), "");
  }
  {  // A new name, the same failure: none of its files appears.
    Lab lab(dir.root(), "planar", 2, 1);
    EXPECT_EQ(lab.train("n.json").value("status", ""), "failed");
    EXPECT_EQ(changes(dir.root(), old), "");
  }
  {  // Cancel once files are written (the proxy), old names and new: none appears or changes.
    Lab lab(dir.root(), "planar", 0, 1);
    for (const std::string out : {"m.json", "n.json"}) {
      ASSERT_EQ(lab.send({{"type", "mode"}, {"mode", "model"}}).value("type", ""), "ok");
      ASSERT_EQ(lab.send({{"type", "model_train"}, {"recording", "rec.csv"}, {"out", out}})
                    .value("type", ""),
                "ok");
      ASSERT_FALSE(lab.wait("train_progress", 300 * test::slow_factor(),
                            [](const nlohmann::json& j) {
                              return j.value("note", "").rfind("proxy:", 0) == 0;
                            })
                       .is_null());
      lab.send({{"type", "model_cancel"}});
      const auto done = lab.wait("trained", 300 * test::slow_factor());
      ASSERT_FALSE(done.is_null()) << out;
      EXPECT_EQ(done.value("status", ""), "cancelled") << out;
      EXPECT_EQ(changes(dir.root(), old), "") << out;
    }
  }
}

// The Palpation view fits yield surfaces on the lab's planar; a training in the Model view then
// uses them (not the lab scene palpated anew): it says so, the yield surfaces it wrote beside the
// model are the view's (its points, not `sys palpate`'s nine), and their elastic limits match the
// lab's friction truth mu * f_N.
TEST(StudioModelSession, TrainingUsesThePalpationViewsYieldSurfaces) {
  test::TempDir dir;
  Lab lab(dir.root(), "planar");
  const lab::Scene scene = lab::builtin_scene("planar");
  const double radius = lab::DeviceParams{}.probe.radius_mm;
  const auto c = scene.region.center;
  nlohmann::json points = nlohmann::json::array();
  std::vector<Vec3> want;
  for (const auto& [dx, dy] : std::vector<std::pair<double, double>>{{-6, -4}, {6, -4}, {0, 6}}) {
    const auto p = scene.object.shape().drop(c.x() + dx, c.y() + dy, radius);
    ASSERT_TRUE(p);
    points.push_back({p->x(), p->y(), p->z()});
    want.push_back(*p);
  }
  ASSERT_EQ(lab.send({{"type", "mode"}, {"mode", "palpation"}}).value("type", ""), "ok");
  const auto run =
      lab.send({{"type", "palpate"}, {"points", points}, {"quick", true}, {"speed", 20}});
  ASSERT_EQ(run.value("status", ""), "running") << run.dump();
  const auto fit = lab.wait("yield", 600 * test::slow_factor());
  ASSERT_FALSE(fit.is_null());
  ASSERT_EQ(fit["points"].size(), 3u);

  lab.record(15);
  const auto r = lab.send({{"type", "model_train"}, {"recording", "rec.csv"}, {"out", "m.json"}});
  EXPECT_EQ(r.value("palpation", ""), "palpation view") << r.dump();
  const auto t = lab.wait("trained", 600 * test::slow_factor());
  ASSERT_FALSE(t.is_null()) << "no trained broadcast";
  ASSERT_EQ(t.value("status", ""), "done") << t.dump();
  ASSERT_FALSE(t["lines"].empty());
  EXPECT_EQ(t["lines"][0], "yield surfaces of the Palpation view");

  const friction::SysModel sys =
      friction::read_sys_json((dir.root() / "m.palpation.json").string());
  ASSERT_EQ(sys.points.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_LT((sys.points[i].position - want[i]).norm(), 0.5) << i;
  std::vector<double> rel;
  for (std::size_t i = 0; i < sys.points.size(); ++i) {
    const double mu = scene.object.mu_at(sys.points[i].position);
    for (std::size_t j = 0; j < sys.f_normal_levels.size(); ++j)
      for (std::size_t k = 0; k < sys.angles.size(); ++k) {
        const friction::BorderResult& b = sys.border(i, j, k).result;
        if (b.extrapolated || b.no_sliding) continue;
        rel.push_back(std::abs(b.f_limit - mu * sys.f_normal_levels[j]) /
                      (mu * sys.f_normal_levels[j]));
      }
  }
  ASSERT_GE(rel.size(), 6u);
  std::sort(rel.begin(), rel.end());
  EXPECT_LT(rel[rel.size() / 2], 0.1);
}
