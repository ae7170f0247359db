#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

namespace {
std::string write(const test::TempDir& dir, const std::string& name, const std::string& text) {
  auto path = dir.path(name);
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& path) {
  try {
    read_recording(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Csv, ReadsRecordingByHeaderNamesInAnyOrder) {
  test::TempDir dir;
  auto path =
      write(dir, "r.csv",
            "# units\nfz,t,px,py,pz,fx,fy,extra\n3,0.001,1,2,3,1,2,9\n6,0.002,4,5,6,4,5,8\n");
  Recording rec = read_recording(path);
  ASSERT_EQ(rec.size(), 2u);
  EXPECT_DOUBLE_EQ(rec.t[1], 0.002);
  EXPECT_EQ(rec.p[1], Vec3(4, 5, 6));
  EXPECT_EQ(rec.f[0], Vec3(1, 2, 3));
  ASSERT_NE(rec.find_extra("extra"), nullptr);
  EXPECT_EQ((*rec.find_extra("extra"))[1], 8);
}

TEST(Csv, RoundTripIsExactAndAtomic) {
  test::TempDir dir;
  Recording rec;
  for (int i = 0; i < 100; ++i) {
    rec.t.push_back(i * 0.001);
    rec.p.emplace_back(i / 3.0, -i * 1e-7, 1e300 / (i + 1));
    rec.f.emplace_back(0.1 * i, 1.0 / 7.0, -2.5);
  }
  rec.set_extra("qx", std::vector<double>(100, 0.125));
  auto path = dir.path("rt.csv");
  write_recording(path, rec);
  Recording back = read_recording(path);
  ASSERT_EQ(back.size(), rec.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    EXPECT_EQ(back.t[i], rec.t[i]);
    EXPECT_EQ(back.p[i], rec.p[i]);
    EXPECT_EQ(back.f[i], rec.f[i]);
  }
  EXPECT_EQ(back.extra_names, rec.extra_names);
  // No temporary file is left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir.root()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

struct BadCase {
  const char* name;
  const char* text;
  const char* expect;  // substring of the error
};

class CsvBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(CsvBad, GivesOneLineErrorWithFileAndLine) {
  test::TempDir dir;
  auto path = write(dir, "bad.csv", GetParam().text);
  std::string err = error_of(path);
  ASSERT_FALSE(err.empty()) << "no error for " << GetParam().name;
  EXPECT_NE(err.find(path), std::string::npos) << err;
  EXPECT_NE(err.find(GetParam().expect), std::string::npos) << err;
  EXPECT_EQ(err.find('\n'), std::string::npos) << err;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CsvBad,
    ::testing::Values(
        BadCase{"empty", "", "empty file"},
        BadCase{"missing", "t,px,py,pz,fx,fy\n0,1,2,3,4,5\n", ":1: missing column 'fz'"},
        BadCase{"ragged_short", "t,px,py,pz,fx,fy,fz\n0,1,2,3,4,5,6\n1,1,2,3\n",
                ":3: expected 7 fields"},
        BadCase{"ragged_long", "t,px,py,pz,fx,fy,fz\n0,1,2,3,4,5,6,7\n", ":2: expected 7 fields"},
        BadCase{"nonnumber", "t,px,py,pz,fx,fy,fz\n0,1,2,abc,4,5,6\n",
                ":2: column 'pz': expected a number, got 'abc'"},
        BadCase{"time", "t,px,py,pz,fx,fy,fz\n0,1,2,3,4,5,6\n0,1,2,3,4,5,6\n",
                ":3: time must be strictly increasing"},
        BadCase{"nan", "t,px,py,pz,fx,fy,fz\n0,1,2,nan,4,5,6\n",
                ":2: column 'pz': expected a finite number"},
        BadCase{"header_is_number", "0,1,2\n", ":1: expected a header row"},
        BadCase{"duplicate", "t,t,px\n", "duplicate column name 't'"}),
    [](const auto& tp) { return std::string(tp.param.name); });

TEST(Csv, MissingFileNamesThePath) {
  try {
    read_recording("/nonexistent/dir/r.csv");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/r.csv"), std::string::npos);
  }
}

TEST(Csv, StreamsRowByRow) {
  test::TempDir dir;
  auto path = write(dir, "s.csv", "a,b\n1,2\n\n3, 4\r\n");
  CsvReader r(path);
  ASSERT_TRUE(r.next());
  EXPECT_EQ(r[r.require("b")], 2);
  ASSERT_TRUE(r.next());
  EXPECT_EQ(r.line(), 4u);
  EXPECT_EQ(r[1], 4);
  EXPECT_FALSE(r.next());
}
