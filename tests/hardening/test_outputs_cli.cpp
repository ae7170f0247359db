// All-or-nothing outputs of the long multi-file commands across the process boundary (issue
// 20): `eval shape --out-dir` and `inhap demo` with the n-th write or rename failing
// (INHAP_TEST_FAIL_NTH_WRITE / _RENAME, read by the program), and `sys palpate` checking its
// output paths before the palpation.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

namespace fs = std::filesystem;

/// Every file under `dir` (relative path -> content); temporaries and backups show here too.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      out[fs::relative(e.path(), dir).string()] = read_file(e.path().string());
  return out;
}

/// Runs `args` once to learn its outputs in `out`, marks each as old, then fails the n-th write
/// (n = 1, 4, 16, ... until the run gets past its last write) and the n-th rename (n = 1, 3, 5,
/// ... until it gets past its last rename; the library test fails every one): every failed run must
/// exit 1 with the inhap prefix and leave exactly the old files. Returns the number of outputs.
std::size_t check_all_or_nothing(const std::string& args, const fs::path& out) {
  const auto first = test::run_cli(args);
  EXPECT_EQ(first.status, 0) << first.out;
  std::map<std::string, std::string> old = snapshot(out);
  EXPECT_GE(old.size(), 2u);
  for (auto& [name, content] : old) content = "old " + name + "\n";
  for (const char* kind : {"WRITE", "RENAME"}) {
    for (const auto& [name, content] : old) write_file_atomic((out / name).string(), content);
    int failed = 0;
    for (long n = 1; n < 1'000'000; n = kind[0] == 'W' ? 4 * n : n + 2) {
      const auto r =
          test::run_cli(args, "INHAP_TEST_FAIL_NTH_" + std::string(kind) + "=" + std::to_string(n));
      if (r.status == 0) break;  // n is past the last write / rename
      ++failed;
      EXPECT_EQ(r.status, 1) << kind << " " << n << ": " << r.out;
      EXPECT_NE(r.out.find("inhap: error:"), std::string::npos) << r.out;
      EXPECT_EQ(snapshot(out), old) << kind << " fault " << n << ": " << r.out;
      if (::testing::Test::HasFailure()) return old.size();
    }
    EXPECT_GE(failed, 2) << kind;
  }
  // A run without faults replaces every old output (and the last run above was one).
  for (const auto& [name, content] : snapshot(out))
    EXPECT_NE(content, old.count(name) ? old.at(name) : "") << name;
  return old.size();
}

TEST(OutputsCli, EvalShapeOutDirIsAllOrNothing) {
  test::TempDir dir;
  const fs::path out = dir.path("out");
  const std::string args = "eval shape --objects silicone-hemisphere --taps 20 --out-dir " +
                           out.string() + " --json " + (out / "shape.json").string();
  // points, mesh (estimate and threshold), the reference and the JSON
  EXPECT_EQ(check_all_or_nothing(args, out), 6u);
  // A folder the run created is removed again when the run fails.
  const fs::path fresh = dir.path("fresh/sub");
  const auto r = test::run_cli(
      "eval shape --objects silicone-hemisphere --taps 20 --out-dir " + fresh.string(),
      "INHAP_TEST_FAIL_NTH_RENAME=3");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_FALSE(fs::exists(dir.path("fresh"))) << r.out;
}

TEST(OutputsCli, DemoIsAllOrNothing) {
  if (!fs::exists(fs::path(INHAP_SOURCE_DIR) / "web/node_modules"))
    GTEST_SKIP() << "web/node_modules missing (./run setup installs the report's libraries)";
  test::TempDir dir;
  const fs::path out = dir.path("demo");
  // dome_tap.csv, dome_tap.truth.csv, report.html, summary.csv, figures.json, summary.json
  EXPECT_GE(check_all_or_nothing("demo --quick --only tap --out " + out.string(), out), 5u);
}

// The output paths are checked before the palpation (minutes on a full run): a blocked path
// fails at once, before the palpation's progress reaches 100 %, and writes nothing.
TEST(OutputsCli, SysPalpateChecksItsOutputsFirst) {
  test::TempDir dir;
  const std::string common = "sys palpate --scene planar --quick --points grid:1x1 --out ";
  fs::create_directory(dir.path("s.cycles.csv"));  // the cycles path is a folder
  auto r = test::run_cli(common + dir.path("s.json"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error:", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("s.cycles.csv"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("[sys palpate]"), std::string::npos) << "palpated first: " << r.out;
  EXPECT_EQ(snapshot(dir.root()).size(), 0u);
  r = test::run_cli(common + dir.path("missing/s.json"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("[sys palpate]"), std::string::npos) << "palpated first: " << r.out;
  // A writable path palpates (the progress line reaches 100 %) and writes all three files.
  r = test::run_cli(common + dir.path("ok.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("[sys palpate] 100%"), std::string::npos) << r.out;
  for (const char* f : {"ok.json", "ok.cycles.csv", "ok.shape.ply"})
    EXPECT_TRUE(fs::is_regular_file(dir.path(f))) << f;
}

}  // namespace
}  // namespace inhap
