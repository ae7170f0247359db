// Readers that must not trust declared sizes or let invalid values through silently, and
// writers that never write a non-finite number (issue 20).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "datadriven/dd_fixtures.hpp"
#include "friction/sys_helpers.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/json_guard.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/volume.hpp"
#include "inhap/lab/scene.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace test_readers {

/// The message of the ParseError/Error `fn` throws ("" and a test failure if none).
template <class Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an inhap::Error: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(Readers, PgmDeclaringHugeSizesIsTruncatedBeforeAllocating) {
  test::TempDir dir;
  for (const char* magic : {"P5", "P2"}) {
    const std::string path = dir.path(std::string("huge.") + magic + ".pgm");
    const std::string header = std::string(magic) + "\n20000 20000\n255\n";
    std::string body = header + std::string(300, '7');
    if (magic[1] == '2')  // "7 7 7 ...": ASCII pixels
      for (std::size_t i = header.size() + 1; i < body.size(); i += 2) body[i] = ' ';
    std::ofstream(path, std::ios::binary) << body;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string w = error_of([&] { read_grid(path); });
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(has(w, path) && has(w, "truncated")) << w;
    // Touching 3.1 GB would take seconds; a check against the file size takes microseconds.
    // (A generous bound: this asserts no allocation of the declared size, not a speed.)
    EXPECT_LT(s, 0.5) << "the reader touched the declared grid before checking the file";
  }
}

TEST(Readers, NrrdUnknownSpacingIsAnErrorNotOneMillimetre) {
  test::TempDir dir;
  std::ofstream(dir.path("v.raw"), std::ios::binary) << std::string(8, '\0');
  for (const char* spacing :
       {"spacings: nan 2 2", "spacings: 1 inf 2", "space directions: none (0,2,0) (0,0,2)"}) {
    const std::string path = dir.path("v.nhdr");
    std::ofstream(path) << "NRRD0004\ndimension: 3\ntype: uchar\nsizes: 2 2 2\n"
                        << spacing << "\nencoding: raw\ndata file: v.raw\n";
    const std::string w = error_of([&] { read_nrrd(path); });
    EXPECT_TRUE(has(w, "v.nhdr") && has(w, "spacing")) << spacing << ": " << w;
  }
}

TEST(Readers, JsonNumberOverflowIsAParseErrorNamingTheFile) {
  test::TempDir dir;
  write_file_atomic(dir.path("m.json"), "{\"format\": 1e999}");
  EXPECT_TRUE(has(error_of([&] { datadriven::load_force_model(dir.path("m.json")); }), "m.json"));
  write_file_atomic(dir.path("s.json"), "{\"format\": \"inhap-sys\", \"version\": 1e999}");
  EXPECT_TRUE(has(error_of([&] { friction::read_sys_json(dir.path("s.json")); }), "s.json"));
  write_file_atomic(dir.path("scene.json"), "{\"name\": -1e999}");
  EXPECT_TRUE(has(error_of([&] { lab::load_scene(dir.path("scene.json")); }), "scene.json"));
  // Through the program: exit 1, one line, the file named (was "internal error", exit 3).
  const auto r = test::run_cli("model render --model " + dir.path("m.json") + " --recording " +
                               dir.path("m.json") + " --out " + dir.path("o.csv"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error: " + dir.path("m.json"), 0), 0u) << r.out;
}

TEST(Readers, HugeQuotedInputIsCutInTheMessage) {
  test::TempDir dir;
  const std::string big(20u << 20, 'x');
  write_file_atomic(dir.path("m.json"), "{\"format\": \"" + big + "\"}");
  const std::string w = error_of([&] { datadriven::load_force_model(dir.path("m.json")); });
  EXPECT_TRUE(has(w, "m.json")) << w.substr(0, 200);
  EXPECT_LT(w.size(), 1000u);
  EXPECT_FALSE(has(w, "\n"));
}

TEST(Readers, DirectoryGivenAsAFile) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.path("d.csv"));
  EXPECT_TRUE(has(error_of([&] { read_file(dir.path("d.csv")); }), "directory"));
  EXPECT_TRUE(has(error_of([&] { read_recording(dir.path("d.csv")); }), "directory"));
  EXPECT_TRUE(has(error_of([&] { write_file_atomic(dir.path("d.csv"), "x"); }), "directory"));
  const auto r =
      test::run_cli("shape contacts " + dir.path("d.csv") + " --out " + dir.path("p.ply"));
  EXPECT_TRUE(r.status == 1 || r.status == 2) << r.status << " " << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error:", 0), 0u) << r.out;
}

TEST(Readers, CyclesWithAbsurdValuesAreRejected) {
  test::TempDir dir;
  friction::CycleRecord c;
  c.f_normal = 1.0;
  c.tdir = Vec3::UnitX();
  c.nc = Vec3::UnitZ();
  c.pc = Vec3(1e308, 0, 0);  // `sys fit` squared it and wrote null into sys.json
  friction::write_cycles_csv(dir.path("c.csv"), std::vector<friction::CycleRecord>{c});
  const std::string w = error_of([&] { friction::read_cycles_csv(dir.path("c.csv")); });
  EXPECT_TRUE(has(w, "c.csv:") && has(w, "within")) << w;
}

friction::SysModel small_sys() {
  return test::coulomb_sys(
      test::grid_points(3, 3, 10.0), [](std::size_t) { return 0.5; }, 1.0, 1.0);
}

TEST(Readers, SysJsonIdsDoNotWrap) {
  test::TempDir dir;
  friction::write_sys_json(dir.path("sys.json"), small_sys());
  const std::string text = read_file(dir.path("sys.json"));
  write_file_atomic(dir.path("bad.json"), replace_once(text, "\"id\": 0", "\"id\": 4000000000"));
  const std::string w = error_of([&] { friction::read_sys_json(dir.path("bad.json")); });
  EXPECT_TRUE(has(w, "bad.json") && has(w, "id")) << w;
}

TEST(Writers, SysJsonRefusesNonFiniteNumbers) {
  test::TempDir dir;
  friction::SysModel m = small_sys();
  m.points[0].borders[0].result.depth = 1e308 * 10.0;  // overflowed arithmetic
  const std::string w = error_of([&] { friction::write_sys_json(dir.path("sys.json"), m); });
  EXPECT_TRUE(has(w, "sys.json") && has(w, "points[0]")) << w;
  EXPECT_FALSE(std::filesystem::exists(dir.path("sys.json")));
}

TEST(Writers, RequireFiniteJsonNamesThePath) {
  nlohmann::json j;
  j["a"] = {1.0, 2.0, std::nan("")};
  const std::string w = error_of([&] { require_finite_json(j, "f.json"); });
  EXPECT_TRUE(has(w, "f.json") && has(w, "$.a[2]") && has(w, "NaN")) << w;
  j["a"][2] = 3.0;
  EXPECT_NO_THROW(require_finite_json(j, "f.json"));
}

TEST(Readers, SceneWithAbsurdCoordinatesIsRejected) {
  test::TempDir dir;
  lab::save_scene(dir.path("s.json"), lab::builtin_scene("dome"));
  nlohmann::json j = nlohmann::json::parse(read_file(dir.path("s.json")));
  j["region"] = {{"center", {1e308, 0.0}}, {"radius", 10.0}};
  write_file_atomic(dir.path("bad.json"), j.dump());
  const std::string w = error_of([&] { lab::load_scene(dir.path("bad.json")); });
  EXPECT_TRUE(has(w, "bad.json") && has(w, "region.center")) << w;
}

}  // namespace test_readers
}  // namespace inhap
