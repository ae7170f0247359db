// WSxM .top reader: a synthetic file with known samples, bad files, the real AFM topography.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "inhap/core/error.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

namespace {

// Writes a WSxM file: header text padded with spaces to its declared size, then int16 samples.
std::string write_top(const test::TempDir& dir, const std::string& name, int cols, int rows,
                      const std::vector<std::int16_t>& samples,
                      const std::string& extra = "Z Amplitude: 10 nm\r\n",
                      std::size_t drop_bytes = 0) {
  std::string body = "[General Info]\r\n\r\n    Image Data Type: short\r\n    Number of columns: " +
                     std::to_string(cols) + "\r\n    Number of rows: " + std::to_string(rows) +
                     "\r\n    " + extra + "\r\n[Header end]\r\n";
  const std::size_t size = 200 + body.size();
  std::string head = "WSxM file copyright WSxM solutions\r\nSxM Image file\r\nImage header size: " +
                     std::to_string(size) + "\r\n\r\n";
  std::string header = head + body;
  header.resize(size, ' ');
  std::string data(samples.size() * 2, '\0');
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto u = static_cast<std::uint16_t>(samples[i]);
    data[2 * i] = static_cast<char>(u & 0xff);
    data[2 * i + 1] = static_cast<char>(u >> 8);
  }
  // erase, not resize: GCC 12 warns (-Wstringop-overflow) about resize's growing path, which it
  // cannot rule out when this function is inlined into a unity batch.
  data.erase(data.size() - drop_bytes);
  const std::string path = dir.path(name);
  std::ofstream(path, std::ios::binary) << header << data;
  return path;
}

}  // namespace

TEST(Wsxm, ReadsSamplesRowMajorScaledToZAmplitude) {
  test::TempDir dir;
  // 3 columns x 2 rows, raw range -100..900 = 1000 counts spanning 10 nm -> 0.01 nm per count.
  const auto path = write_top(dir, "a.top", 3, 2, {-100, 0, 100, 200, 300, 900});
  Grid g = read_wsxm_top(path);
  ASSERT_EQ(g.width, 3);
  ASSERT_EQ(g.height, 2);
  EXPECT_DOUBLE_EQ(g.at(0, 0), -1.0);
  EXPECT_DOUBLE_EQ(g.at(2, 0), 1.0);
  EXPECT_DOUBLE_EQ(g.at(0, 1), 2.0);
  EXPECT_DOUBLE_EQ(g.at(2, 1), 9.0);
  EXPECT_DOUBLE_EQ(g.max() - g.min(), 10.0);
}

TEST(Wsxm, ReadGridRecognisesWsxmFiles) {
  test::TempDir dir;
  const auto path = write_top(dir, "g.top", 2, 2, {0, 100, 200, 1000});
  Grid g = read_grid(path);
  ASSERT_EQ(g.width, 2);
  EXPECT_DOUBLE_EQ(g.at(1, 1), 10.0);
}

TEST(Wsxm, WithoutAmplitudeKeepsRawLevels) {
  test::TempDir dir;
  const auto path = write_top(dir, "b.top", 2, 1, {-7, 12}, "Comments: none\r\n");
  Grid g = read_wsxm_top(path);
  EXPECT_DOUBLE_EQ(g.at(0, 0), -7.0);
  EXPECT_DOUBLE_EQ(g.at(1, 0), 12.0);
}

TEST(Wsxm, BadFilesNameFileAndProblem) {
  test::TempDir dir;
  const auto truncated =
      write_top(dir, "c.top", 3, 2, {1, 2, 3, 4, 5, 6}, "Z Amplitude: 1 nm\r\n", 3);
  try {
    read_wsxm_top(truncated);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("c.top"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("expected 2 rows x 3 columns of short samples"),
              std::string::npos)
        << e.what();
  }
  const auto no_rows = dir.path("d.top");
  std::ofstream(no_rows, std::ios::binary)
      << "WSxM file copyright\r\nImage header size: 40\r\n[Header end]\r\n     ";
  EXPECT_THROW(read_wsxm_top(no_rows), ParseError);
  const auto not_wsxm = dir.path("e.top");
  std::ofstream(not_wsxm, std::ios::binary) << "P2\n2 2\n255\n0 0 0 0\n";
  try {
    read_wsxm_top(not_wsxm);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 1u);
  }
  EXPECT_THROW(read_wsxm_top(dir.path("missing.top")), IoError);
}

TEST(Wsxm, RealAfmTopography) {
  const std::string path = test::shared_data("afm-topography/sample_0.top");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " absent";
  Grid g = read_wsxm_top(path);
  EXPECT_EQ(g.width, 512);
  EXPECT_EQ(g.height, 512);
  // SOURCE.txt: raw -19468..-5073 spans the Z amplitude 59.7449 nm (0.0041504 nm per count).
  EXPECT_NEAR(g.max() - g.min(), 59.7449, 1e-9);
  EXPECT_NEAR(g.min(), -19468 * 59.7449 / 14395.0, 1e-9);
}
