// The fuzz targets' seed corpora (tests/fuzz/corpus/<reader>/) are valid inputs: each reads
// without error, so fuzzing starts from files that reach deep into every reader.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "inhap/core/csv.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/geometry/heightmap.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/volume.hpp"
#include "inhap/lab/scene.hpp"

namespace inhap {
namespace {

namespace fs = std::filesystem;

TEST(FuzzSeeds, EverySeedIsAValidInput) {
  // From CMake, absolute (__FILE__ may be relative under a compiler cache).
  const fs::path corpus = fs::path(INHAP_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
  const std::map<std::string, std::function<void(const std::string&)>> readers = {
      {"ply", [](const std::string& p) { read_mesh(p); }},
      {"obj", [](const std::string& p) { read_mesh(p); }},
      {"recording", [](const std::string& p) { read_recording(p); }},
      {"cycles",  // seeds without normal columns take them from a plane, as the target does
       [](const std::string& p) {
         const friction::PlaneShape plane(Vec3::Zero(), Vec3::UnitZ());
         friction::read_cycles_csv(p, {&plane, Vec3::UnitX(), 5.0});
       }},
      {"model", [](const std::string& p) { datadriven::load_force_model(p); }},
      {"sys", [](const std::string& p) { friction::read_sys_json(p); }},
      {"scene", [](const std::string& p) { lab::load_scene(p); }},
      {"nrrd", [](const std::string& p) { read_nrrd(p); }},
      {"pgm", [](const std::string& p) { read_grid(p); }},
      {"height_csv", [](const std::string& p) { read_grid(p); }},
      {"wsxm", [](const std::string& p) { read_wsxm_top(p); }},
  };
  for (const auto& [name, read] : readers) {
    const fs::path dir = corpus / name;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int seeds = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
      EXPECT_NO_THROW(read(e.path().string())) << e.path();
      ++seeds;
    }
    EXPECT_GE(seeds, 1) << name;
  }
}

}  // namespace
}  // namespace inhap
