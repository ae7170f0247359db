// All-or-nothing outputs: an OutputTransaction over several AtomicFiles, checked by failing
// the n-th write and the n-th rename (fault injection), and the multi-file commands (issue 20).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

namespace fs = std::filesystem;

/// Every file in the folder, sorted (temporaries and backups would show here).
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

/// A command with three outputs: a CSV (several writes), a text file and a JSON file.
void write_three(const test::TempDir& dir, const std::string& tag) {
  OutputTransaction tx;
  {
    CsvWriter w(dir.path("a.csv"), {"t", tag});
    for (int i = 0; i < 3; ++i) w.row({double(i), 1.0});
    w.commit();
  }
  write_file_atomic(dir.path("b.txt"), "b " + tag + "\n");
  write_file_atomic(dir.path("c.json"), "{\"tag\": \"" + tag + "\"}\n");
  tx.commit();
}

std::vector<std::string> contents(const test::TempDir& dir) {
  return {read_file(dir.path("a.csv")), read_file(dir.path("b.txt")),
          read_file(dir.path("c.json"))};
}

TEST(Outputs, EveryInjectedWriteOrRenameFaultLeavesTheOldOutputs) {
  test::TempDir dir;
  write_three(dir, "old");
  const auto old = contents(dir);
  const auto files = listing(dir.root());
  ASSERT_EQ(files.size(), 3u);
  // The n-th write: the CSV has a header write and a flush at commit; the others one each.
  int write_faults = 0, rename_faults = 0;
  for (long n = 1; n <= 10; ++n) {
    fault::fail_nth_write(n);
    try {
      write_three(dir, "new");
    } catch (const IoError&) {
      ++write_faults;
    }
    fault::fail_nth_write(0);
    if (contents(dir)[0].find("new") != std::string::npos) break;  // n past the last write
    EXPECT_EQ(contents(dir), old) << "write fault " << n;
    EXPECT_EQ(listing(dir.root()), files) << "write fault " << n;
  }
  EXPECT_GE(write_faults, 3);
  write_three(dir, "old");
  for (long n = 1; n <= 3; ++n) {  // fail the first, second, third rename
    fault::fail_nth_rename(n);
    EXPECT_THROW(write_three(dir, "new"), IoError) << "rename fault " << n;
    fault::fail_nth_rename(0);
    ++rename_faults;
    EXPECT_EQ(contents(dir), old) << "rename fault " << n;
    EXPECT_EQ(listing(dir.root()), files) << "rename fault " << n;
  }
  EXPECT_EQ(rename_faults, 3);
  write_three(dir, "new");  // no fault: all three replaced
  for (const auto& c : contents(dir)) EXPECT_NE(c.find("new"), std::string::npos) << c;
  EXPECT_EQ(listing(dir.root()), files);
}

TEST(Outputs, NewOutputsRolledBackAreRemoved) {
  test::TempDir dir;
  fault::fail_nth_rename(2);
  EXPECT_THROW(write_three(dir, "new"), IoError);
  fault::fail_nth_rename(0);
  EXPECT_TRUE(listing(dir.root()).empty());
}

TEST(Outputs, WithoutATransactionEachFileIsAtomicAlone) {
  test::TempDir dir;
  write_file_atomic(dir.path("x"), "old");
  fault::fail_nth_write(1);
  EXPECT_THROW(write_file_atomic(dir.path("x"), "new"), IoError);
  fault::fail_nth_write(0);
  EXPECT_EQ(read_file(dir.path("x")), "old");
  EXPECT_EQ(listing(dir.root()), std::vector<std::string>{"x"});
}

TEST(Outputs, CheckOutputPathNamesTheProblem) {
  test::TempDir dir;
  EXPECT_NO_THROW(check_output_path(dir.path("fine.csv")));
  EXPECT_TRUE(listing(dir.root()).empty());  // the probe is removed
  try {
    check_output_path(dir.path("missing/x.csv"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  fs::create_directory(dir.path("sub"));
  EXPECT_THROW(check_output_path(dir.path("sub")), Error);
}

// `shape contacts --csv` into a missing folder: the PLY from an earlier run stays as it was.
TEST(Outputs, ShapeContactsWithABlockedCsvLeavesThePly) {
  test::TempDir dir;
  const std::string rec = dir.path("rec.csv");
  {
    CsvWriter w(rec, {"t", "px", "py", "pz", "fx", "fy", "fz"});
    for (int i = 0; i < 2000; ++i) {
      const double t = i * 1e-3, z = 1.0 - 2.0 * t;  // descends through z = 0 at t = 0.5 s
      w.row({t, 0.0, 0.0, z, 0.0, 0.0, z < 0 ? -3.0 * z : 0.0});
    }
    w.commit();
  }
  write_file_atomic(dir.path("p.ply"), "old ply");
  const auto r = test::run_cli("shape contacts " + rec + " --out " + dir.path("p.ply") + " --csv " +
                               dir.path("missing/t.csv"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error:", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("missing"), std::string::npos) << r.out;
  EXPECT_EQ(read_file(dir.path("p.ply")), "old ply");
  EXPECT_EQ(listing(dir.root()), (std::vector<std::string>{"p.ply", "rec.csv"}));
}

// `lab record` with its truth path blocked (a directory): nothing written, checked up front.
TEST(Outputs, LabRecordWithABlockedTruthPathWritesNothing) {
  test::TempDir dir;
  write_file_atomic(dir.path("r.csv"), "old");
  fs::create_directory(dir.path("r.truth.csv"));
  const auto r = test::run_cli("lab record --scene dome --operator tap --seconds 1 --out " +
                               dir.path("r.csv"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("r.truth.csv"), std::string::npos) << r.out;
  EXPECT_EQ(read_file(dir.path("r.csv")), "old");
  EXPECT_EQ(listing(dir.root()), (std::vector<std::string>{"r.csv", "r.truth.csv"}));
}

}  // namespace
}  // namespace inhap
