// inhap/core/text.hpp (edit distance, closest name, progress line), parse_number_list
// (core/csv.hpp) and fault::from_environment (core/atomic_file.hpp): known answers.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/text.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

TEST(Text, EditDistanceKnownPairs) {
  EXPECT_EQ(text::edit_distance("kitten", "sitting"), 3u);  // the textbook example
  EXPECT_EQ(text::edit_distance("", "abc"), 3u);
  EXPECT_EQ(text::edit_distance("abc", ""), 3u);
  EXPECT_EQ(text::edit_distance("flaw", "lawn"), 2u);
  EXPECT_EQ(text::edit_distance("same", "same"), 0u);
}

TEST(Text, ClosestNameOnlyWhenCloseEnough) {
  const std::vector<std::string> names{"shape", "model", "eval", "serve"};
  EXPECT_EQ(text::closest("shpae", names), "shape");  // distance 2 < 5 / 2 + 1
  EXPECT_EQ(text::closest("evla", names), "eval");
  EXPECT_EQ(text::closest("xyzzy", names), "");  // every name 4-5 edits away
  EXPECT_EQ(text::closest("modle", {}), "");
}

TEST(Text, ProgressLine) {
  EXPECT_EQ(text::progress_line("train", 0.5, 3.2, false), "[train]  50% (eta 3 s)");
  EXPECT_EQ(text::progress_line("train", 0.5, 0, true), "\r[train]  50%");
  EXPECT_EQ(text::progress_line("train", 1.0, 7, false), "[train] 100%\n");  // no eta when done
}

TEST(Text, ParseNumberListTakesExactlyN) {
  double v[3] = {0, 0, 0};
  ASSERT_TRUE(parse_number_list("1.5,-2,3e2", 3, v));
  EXPECT_EQ(v[0], 1.5);
  EXPECT_EQ(v[1], -2.0);
  EXPECT_EQ(v[2], 300.0);
  EXPECT_FALSE(parse_number_list("1,2", 3, v));
  EXPECT_FALSE(parse_number_list("1,2,3,4", 3, v));
  EXPECT_FALSE(parse_number_list("1,x,3", 3, v));
  EXPECT_FALSE(parse_number_list("1,,3", 3, v));
  ASSERT_TRUE(parse_number_list("12.5,-3", 2, v));
  EXPECT_EQ(v[0], 12.5);
  EXPECT_EQ(v[1], -3.0);
}

TEST(Text, FaultInjectionFromTheEnvironment) {
  const test::TempDir dir;
  ::setenv("INHAP_TEST_FAIL_NTH_WRITE", "1", 1);
  fault::from_environment();
  ::unsetenv("INHAP_TEST_FAIL_NTH_WRITE");
  EXPECT_THROW(write_file_atomic(dir.path("a.txt"), "x"), Error);  // the first write fails
  EXPECT_FALSE(std::filesystem::exists(dir.path("a.txt")));
  fault::fail_nth_write(0);
  write_file_atomic(dir.path("a.txt"), "x");  // and only that one
  EXPECT_TRUE(std::filesystem::exists(dir.path("a.txt")));
  ::setenv("INHAP_TEST_FAIL_NTH_WRITE", "", 1);  // empty: no fault
  fault::from_environment();
  ::unsetenv("INHAP_TEST_FAIL_NTH_WRITE");
  write_file_atomic(dir.path("b.txt"), "y");
  EXPECT_TRUE(std::filesystem::exists(dir.path("b.txt")));
}

}  // namespace
}  // namespace inhap
