// Recordings and their ground truth: determinism, row counts, truth consistency, operators.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "inhap/core/atomic_file.hpp"
#include "inhap/lab/operators.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap::lab {
namespace {

RecordSpec spec(const std::string& op, double seconds, std::uint64_t seed) {
  RecordSpec s;
  s.operator_name = op;
  s.seconds = seconds;
  s.seed = seed;
  return s;
}

int run_cli(const std::string& args, std::string* output = nullptr) {
  const test::CliResult r = test::run_cli(args);
  if (output) *output = r.out;
  return r.status;
}

TEST(Recording, SameSeedGivesIdenticalBytesOtherSeedsDiffer) {
  test::TempDir dir;
  const Scene scene = builtin_scene("planar");
  for (auto [name, seed] : {std::pair{"a", 5}, {"b", 5}, {"c", 6}})
    write_lab_recording(dir.path(std::string(name) + ".csv"),
                        record_scene(scene, spec("explore", 3.0, seed)));
  EXPECT_EQ(read_file(dir.path("a.csv")), read_file(dir.path("b.csv")));
  EXPECT_EQ(read_file(dir.path("a.truth.csv")), read_file(dir.path("b.truth.csv")));
  EXPECT_NE(read_file(dir.path("a.csv")), read_file(dir.path("c.csv")));
  EXPECT_NE(read_file(dir.path("a.truth.csv")), read_file(dir.path("c.truth.csv")));
}

TEST(Recording, CliWritesSixtyThousandRowsAndTruth) {
  test::TempDir dir;
  const std::string out = dir.path("r.csv");
  std::string log;
  ASSERT_EQ(
      run_cli("lab record --scene planar --operator explore --seconds 60 --seed 1 --out " + out,
              &log),
      0)
      << log;
  const Recording rec = read_recording(out);  // strict reader: finite, increasing, not ragged
  EXPECT_EQ(rec.size(), 60000u);
  ASSERT_NE(rec.find_extra("rfz"), nullptr);
  const TruthTable tr = read_truth(dir.path("r.truth.csv"));
  ASSERT_EQ(tr.size(), 60000u);
  EXPECT_DOUBLE_EQ(rec.t.back(), 59.999);
  for (std::size_t i = 0; i < tr.size(); i += 997) EXPECT_EQ(tr.t[i], rec.t[i]);
}

TEST(Recording, CliRejectsBadInputClearly) {
  std::string log;
  EXPECT_EQ(run_cli("lab record --scene nowhere --seconds 1 --out /tmp/x.csv", &log), 1);
  EXPECT_NE(log.find("unknown scene 'nowhere'"), std::string::npos) << log;
  EXPECT_NE(log.find("planar"), std::string::npos) << log;
  EXPECT_NE(run_cli("lab record --scene planar --operator dance --out /tmp/x.csv", &log), 0);
  EXPECT_EQ(run_cli("lab record --scene-file /nonexistent/s.json --out /tmp/x.csv", &log), 1);
  EXPECT_NE(log.find("/nonexistent/s.json"), std::string::npos) << log;
  ASSERT_EQ(run_cli("lab scenes", &log), 0);
  for (const auto& name : builtin_scene_names()) EXPECT_NE(log.find(name), std::string::npos);
}

// Share of the region's 10 mm cells whose centre lies within 7 mm of a true anchor where the
// contact force reached f_min (N).
double region_cells_pushed(const Scene& scene, const TruthTable& tr, double f_min) {
  constexpr double kCell = 10.0, kNear = 7.0;
  const Region& r = scene.region;
  int cells = 0, visited = 0;
  for (double x = r.center.x() - r.radius; x <= r.center.x() + r.radius; x += kCell)
    for (double y = r.center.y() - r.radius; y <= r.center.y() + r.radius; y += kCell) {
      if ((Vec2(x, y) - r.center).norm() > r.radius) continue;
      ++cells;
      for (std::size_t i = 0; i < tr.size(); ++i)
        if (tr.contact[i] && tr.force[i].norm() >= f_min &&
            std::hypot(tr.anchor[i].x() - x, tr.anchor[i].y() - y) < kNear) {
          ++visited;
          break;
        }
    }
  return static_cast<double>(visited) / std::max(1, cells);
}

TEST(Recording, CoverageExplorationPushesDeepAllOverTheRegion) {
  const Scene scene = builtin_scene("planar");
  RecordSpec plain = spec("explore", 65, 3), cov = plain;
  cov.explore.coverage = true;
  // The coverage run pushes deep (0.8-0.95 x 5 N) at every spot of a grid over the region.
  const double a = region_cells_pushed(scene, record_scene(scene, plain).truth, 3.5);
  const double b = region_cells_pushed(scene, record_scene(scene, cov).truth, 3.5);
  // (measured at seed 3: 0.79 against 0.48)
  EXPECT_GT(b, 0.7) << "plain " << a;
  EXPECT_GT(b, a + 0.15) << "plain " << a;
  // The command line: --coverage names itself in the provenance and needs the explore operator.
  test::TempDir dir;
  std::string log;
  ASSERT_EQ(
      run_cli("lab record --scene planar --coverage --seconds 2 --out " + dir.path("c.csv"), &log),
      0)
      << log;
  EXPECT_NE(read_file(dir.path("c.csv")).find("explore-coverage"), std::string::npos);
  EXPECT_EQ(
      run_cli("lab record --scene planar --operator tap --coverage --out " + dir.path("t.csv"),
              &log),
      1);
  EXPECT_NE(log.find("--coverage: expected --operator explore"), std::string::npos) << log;
}

/// Checks the truth's first-contact bookkeeping of a tap recording; returns the tap count.
int check_taps(const Scene& scene, const LabRecording& lab, double radius) {
  const TruthTable& tr = lab.truth;
  long taps = 0;
  for (std::size_t k = 0; k < tr.size(); ++k) {
    EXPECT_EQ(tr.tap[k] >= 0, tr.contact[k] == 1);
    const bool starts = tr.contact[k] == 1 && (k == 0 || tr.tap[k - 1] != tr.tap[k]);
    if (!starts) {
      if (tr.contact[k]) {
        EXPECT_EQ(tr.tc[k], tr.tc[k - 1]);
      }
      continue;
    }
    EXPECT_EQ(tr.tap[k], taps++);
    if (k == 0) continue;
    EXPECT_EQ(tr.contact[k - 1], 0) << "row " << k;  // the episode starts at this row
    EXPECT_GT(tr.tc[k], tr.t[k - 1]);
    EXPECT_LE(tr.tc[k], tr.t[k]);
    // The contact point is the probe centre touching the undeformed surface.
    EXPECT_NEAR(scene.object.query(tr.c[k]).distance, radius, 2e-3) << "row " << k;
    if (k >= 8) {  // approach speed from the encoder just before contact
      const double v = (lab.rec.p[k - 1] - lab.rec.p[k - 8]).norm() / 0.007;
      EXPECT_GT(v, 12.0) << "row " << k;
      EXPECT_LT(v, 240.0) << "row " << k;
    }
  }
  return static_cast<int>(taps);
}

TEST(Recording, TruthFirstContactsAgreeWithTheContactFlag) {
  for (const char* name : {"silicone-hemisphere", "sponge", "ridged-silicone"}) {
    const Scene scene = builtin_scene(name);
    const LabRecording lab = record_scene(scene, spec("tap", 20.0, 3));
    const int taps = check_taps(scene, lab, 8.0);
    std::printf("%s: %d taps in 20 s\n", name, taps);
    EXPECT_GE(taps, 12) << name;
  }
  RecordSpec tip = spec("tap", 10.0, 4);
  tip.probe = ProbeSpec::tip();
  const Scene scene = builtin_scene("foam-ball");
  EXPECT_GE(check_taps(scene, record_scene(scene, tip), 0.0), 6);
}

TEST(Recording, TapPeakForcesStayInTheOperatorsRange) {
  const LabRecording lab = record_scene(builtin_scene("silicone-block"), spec("tap", 30.0, 8));
  std::vector<double> peaks;
  for (std::size_t k = 0; k < lab.truth.size(); ++k) {
    const long tap = lab.truth.tap[k];
    if (tap < 0) continue;
    if (static_cast<long>(peaks.size()) <= tap) peaks.resize(tap + 1, 0.0);
    peaks[tap] = std::max(peaks[tap], lab.truth.force[k].norm());
  }
  ASSERT_GE(peaks.size(), 15u);
  for (double f : peaks) {
    EXPECT_GT(f, 0.5);
    EXPECT_LT(f, 6.2);
  }
}

TEST(Recording, SixtySecondsOfFreeMotionReadBelow50mNAfterCompensation) {
  const Scene scene = builtin_scene("planar");
  const LabRecording lab = record_scene(scene, spec("air", 60.0, 2));
  double comp = 0, raw = 0;
  for (std::size_t k = 0; k < lab.rec.size(); ++k) {
    EXPECT_EQ(lab.truth.contact[k], 0);
    const Vec3 r((*lab.rec.find_extra("rfx"))[k], (*lab.rec.find_extra("rfy"))[k],
                 (*lab.rec.find_extra("rfz"))[k]);
    raw = std::max(raw, r.norm());
    if (k >= 20) comp = std::max(comp, lab.rec.f[k].norm());  // estimator warm-up
  }
  // Inertia alone (no noise, no weight): how much compensation removes.
  RecordSpec s = spec("air", 60.0, 2);
  s.noise = false, s.gravity = false;
  const LabRecording inertia = record_scene(scene, s);
  double in_raw = 0, in_comp = 0;
  for (std::size_t k = 20; k < inertia.rec.size(); ++k) {
    const Vec3 r((*inertia.rec.find_extra("rfx"))[k], (*inertia.rec.find_extra("rfy"))[k],
                 (*inertia.rec.find_extra("rfz"))[k]);
    in_raw = std::max(in_raw, r.norm());
    in_comp = std::max(in_comp, inertia.rec.f[k].norm());
  }
  std::printf(
      "free motion 60 s: max |f| %.4f N compensated, %.4f N raw; inertia only: raw %.4f, "
      "compensated %.4f N\n",
      comp, raw, in_raw, in_comp);
  EXPECT_LT(comp, 0.05);
  EXPECT_GT(raw, 0.09);
  EXPECT_LT(in_comp, 0.5 * in_raw);
}

TEST(Recording, ExploreCoversPushesStrokesAndASlidingOnlyPassage) {
  const double seconds = 60;
  const LabRecording lab = record_scene(builtin_scene("planar"), spec("explore", seconds, 1));
  const TruthTable& tr = lab.truth;
  double max_fn = 0, slid_early = 0, slid_late = 0;
  int contact_early = 0, early = 0;
  bool always_late = true;
  for (std::size_t k = 1; k < tr.size(); ++k) {
    const double t = tr.t[k];
    max_fn = std::max(max_fn, tr.force[k].z());
    const bool both = tr.contact[k] && tr.contact[k - 1] && tr.tap[k] == tr.tap[k - 1];
    const double slide = both ? (tr.anchor[k] - tr.anchor[k - 1]).norm() : 0.0;
    if (t < seconds * 2 / 3) {
      ++early, contact_early += tr.contact[k], slid_early += slide;
    } else if (t > seconds * 2 / 3 + 5) {
      always_late = always_late && tr.contact[k];
      slid_late += slide;
    }
  }
  std::printf("explore: max f_N %.2f N, contact %.0f %% (first 2/3), anchor slid %.0f / %.0f mm\n",
              max_fn, 100.0 * contact_early / early, slid_early, slid_late);
  EXPECT_GT(max_fn, 4.0);
  EXPECT_LT(max_fn, 6.0);
  EXPECT_GT(contact_early, early / 3);
  EXPECT_LT(contact_early, early * 19 / 20);
  EXPECT_GT(slid_early, 50.0);
  EXPECT_TRUE(always_late);
  EXPECT_GT(slid_late, 100.0);
}

TEST(Recording, TwoRecordingsCanBeWrittenSideBySide) {
  // Regression: two AtomicFiles open at once used to share one stdio buffer.
  test::TempDir dir;
  CsvWriter a(dir.path("a.csv"), {"x"}), b(dir.path("b.csv"), {"y"});
  for (int i = 0; i < 20000; ++i) a.row({double(i)}), b.row({-double(i)});
  a.commit();
  b.commit();
  const CsvTable ta = read_csv(dir.path("a.csv")), tb = read_csv(dir.path("b.csv"));
  ASSERT_EQ(ta.rows(), 20000u);
  ASSERT_EQ(tb.rows(), 20000u);
  EXPECT_EQ(ta.columns[0][12345], 12345);
  EXPECT_EQ(tb.columns[0][12345], -12345);
}

}  // namespace
}  // namespace inhap::lab
