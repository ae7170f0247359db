// Usability fixes of issue 20 that only show at the command line: a model's stored mesh path
// resolved from the model's folder (and the error when it is not found), the warning when the
// training data holds too little contact.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/datadriven/synthetic.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "support/meshes.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

namespace fs = std::filesystem;

double rmse_z(const std::string& eval_json) {
  return nlohmann::json::parse(read_file(eval_json))["errors"]["rmse_n"]["z"].get<double>();
}

// A local-frame model trained with `--mesh flat.ply` (a relative path) on the synthetic planar
// object (surface z = 0, normal +z).
TEST(Usability, ModelMeshPathFromTheModelsFolderAndTheErrorWhenMissing) {
  test::TempDir dir;
  datadriven::SyntheticParams sp;
  sp.samples = 6000;
  Recording train = datadriven::synthetic_recording(sp);
  write_recording(dir.path("plain.csv"), train);  // no normal columns: the model needs the mesh
  train.set_extra("nx", std::vector<double>(train.size(), 0.0));
  train.set_extra("ny", std::vector<double>(train.size(), 0.0));
  train.set_extra("nz", std::vector<double>(train.size(), 1.0));
  write_recording(dir.path("normals.csv"), train);
  TriMesh plane = test::make_grid_mesh(31, 31, 4.0);  // 120 mm square, centred below
  plane.transform(1.0, Vec3(60, 60, 0));
  plane.compute_normals();
  write_mesh(dir.path("flat.ply"), plane);
  const std::string in_dir = "cd " + dir.root().string() + " &&";
  auto r = test::run_cli(
      "model train --preset world --features local --bins 2 --centers 40 --seed 3 "
      "--recording normals.csv --mesh flat.ply --out m.json",
      in_dir);
  ASSERT_EQ(r.status, 0) << r.out;
  ASSERT_EQ(nlohmann::json::parse(read_file(dir.path("m.json")))["references"]["mesh"]["path"],
            "flat.ply");
  const std::string eval = "model eval --model " + dir.path("m.json") + " --recording " +
                           dir.path("plain.csv") + " --json ";
  // From another folder the relative path resolves beside the model; the normals (+z) are those
  // of the normal columns, so the errors are the same to the last digit.
  r = test::run_cli(eval + dir.path("e-beside.json"), "cd / &&");
  ASSERT_EQ(r.status, 0) << r.out;
  r = test::run_cli("model eval --model " + dir.path("m.json") + " --recording " +
                    dir.path("normals.csv") + " --json " + dir.path("e-columns.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NEAR(rmse_z(dir.path("e-beside.json")), rmse_z(dir.path("e-columns.json")), 1e-12);
  // The mesh gone: one line naming the model, the path, where it came from and --mesh.
  fs::rename(dir.path("flat.ply"), dir.path("moved.ply"));
  r = test::run_cli(eval + dir.path("e-missing.json"), "cd / &&");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error: " + dir.path("m.json"), 0), 0u) << r.out;
  for (const char* s : {"'flat.ply'", "named by the model", "references.mesh.path", "--mesh"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << ": " << r.out;
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "one line: " << r.out;
  EXPECT_FALSE(fs::exists(dir.path("e-missing.json")));
  // --mesh overrides the model's reference.
  r = test::run_cli(eval + dir.path("e-flag.json") + " --mesh " + dir.path("moved.ply"), "cd / &&");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NEAR(rmse_z(dir.path("e-flag.json")), rmse_z(dir.path("e-columns.json")), 1e-12);
}

/// Seconds of contact in a synthetic recording (its true contact column, 1 kHz).
double contact_seconds(const Recording& rec) {
  double n = 0;
  for (double c : *rec.find_extra("contact")) n += c;
  return n * 1e-3;
}

// Training warns when the recording holds less than 30 s of contact, with the amount it found.
TEST(Usability, ShortTrainingDataIsWarnedAbout) {
  test::TempDir dir;
  datadriven::SyntheticParams sp;
  for (const std::size_t samples : {5000u, 60000u}) {
    sp.samples = samples;
    const Recording rec = datadriven::synthetic_recording(sp);
    const double contact_s = contact_seconds(rec);
    write_recording(dir.path("rec.csv"), rec);
    const auto r = test::run_cli(
        "model train --preset world --bins 2 --centers 40 --seed 3 "
        "--recording " +
        dir.path("rec.csv") + " --out " + dir.path("m.json"));
    ASSERT_EQ(r.status, 0) << r.out;
    const bool warned = r.out.find("inhap: warning: only") != std::string::npos;
    EXPECT_EQ(warned, contact_s < 30.0) << samples << " samples, " << contact_s << " s: " << r.out;
    if (samples == 5000u) {
      EXPECT_NE(r.out.find(fmt::format("only {:.1f} s of contact", contact_s)), std::string::npos)
          << r.out;
    } else {
      EXPECT_GE(contact_s, 30.0) << "the long recording must hold 30 s of contact";
    }
  }
}

}  // namespace
}  // namespace inhap
