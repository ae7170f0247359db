// `inhap model train | eval | render` end to end on a synthetic recording.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/datadriven/synthetic.hpp"
#include "support/temp_dir.hpp"

namespace inhap::datadriven {
namespace test_cli_model {

int run(const std::string& args, const std::string& log) {
  const std::string cmd = std::string(INHAP_CLI) + " " + args + " > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(CliModel, TrainEvalRenderRoundTrip) {
  inhap::test::TempDir dir;
  SyntheticParams sp;
  sp.samples = 8000;
  write_recording(dir.path("train.csv"), synthetic_recording(sp));
  sp.seed = 2;
  sp.samples = 3000;
  const Recording test_rec = synthetic_recording(sp);
  write_recording(dir.path("test.csv"), test_rec);
  write_file_atomic(dir.path("sys.json"), "{}");
  const std::string log = dir.path("log.txt");

  ASSERT_EQ(run("model train --recording " + dir.path("train.csv") + " --sys " +
                    dir.path("sys.json") + " --out " + dir.path("m.json") +
                    " --bins 2 --centers 40 --design regression --seed 3",
                log),
            0)
      << read_file(log);
  const auto model = nlohmann::json::parse(read_file(dir.path("m.json")));
  EXPECT_EQ(model["references"]["sys"]["path"], dir.path("sys.json"));
  EXPECT_EQ(model["train"]["bins"], 2);

  ASSERT_EQ(run("model eval --model " + dir.path("m.json") + " --recording " +
                    dir.path("test.csv") + " --json " + dir.path("eval.json"),
                log),
            0)
      << read_file(log);
  const auto ev = nlohmann::json::parse(read_file(dir.path("eval.json")));
  EXPECT_GT(ev["contact_samples"].get<int>(), 1000);
  for (const char* a : {"x", "y", "z"}) {
    EXPECT_GT(ev["errors"]["rmse_n"][a].get<double>(), 0.0);
    EXPECT_LT(ev["errors"]["rmse_n"][a].get<double>(), 1.0);  // forces reach about 5 N
  }
  EXPECT_EQ(ev["contact_source"], "column:contact");

  ASSERT_EQ(run("model render --model " + dir.path("m.json") + " --recording " +
                    dir.path("test.csv") + " --out " + dir.path("forces.csv"),
                log),
            0)
      << read_file(log);
  const CsvTable t = read_csv(dir.path("forces.csv"));
  ASSERT_EQ(t.rows(), test_rec.size());
  const auto& contact = t.column("contact");
  const auto& fz = t.column("fz");
  for (std::size_t i = 0; i < t.rows(); ++i)
    if (contact[i] == 0) {
      ASSERT_EQ(fz[i], 0.0) << i;
    }
}

TEST(CliModel, LocalFeaturesOnAFlatObjectMatchTheWorldFrameAndNeedNormals) {
  // On the synthetic flat object (normal +z everywhere) the surface frame is the world frame
  // exactly, so a local-frame model renders the same forces as the (q - p, q, pdot) model.
  inhap::test::TempDir dir;
  SyntheticParams sp;
  sp.samples = 6000;
  Recording train = synthetic_recording(sp);
  write_recording(dir.path("plain.csv"), train);
  train.set_extra("nx", std::vector<double>(train.size(), 0.0));
  train.set_extra("ny", std::vector<double>(train.size(), 0.0));
  train.set_extra("nz", std::vector<double>(train.size(), 1.0));
  write_recording(dir.path("train.csv"), train);
  const std::string log = dir.path("log.txt");
  const std::string common =
      " --preset world --bins 2 --centers 40 --seed 3 --recording " + dir.path("train.csv");
  ASSERT_EQ(run("model train" + common + " --features local --out " + dir.path("l.json"), log), 0)
      << read_file(log);
  ASSERT_EQ(run("model train" + common + " --features ue_q_v --out " + dir.path("w.json"), log), 0)
      << read_file(log);
  for (const char* m : {"l", "w"})
    ASSERT_EQ(run(std::string("model eval --model ") + dir.path(std::string(m) + ".json") +
                      " --recording " + dir.path("train.csv") + " --json " +
                      dir.path(std::string(m) + "-eval.json"),
                  log),
              0)
        << read_file(log);
  const auto el = nlohmann::json::parse(read_file(dir.path("l-eval.json")));
  const auto ew = nlohmann::json::parse(read_file(dir.path("w-eval.json")));
  EXPECT_EQ(nlohmann::json::parse(read_file(dir.path("l.json")))["features"], "local");
  // In the world preset the tangent mirror is off unless asked for (it assumes a tangentially
  // isotropic material).
  EXPECT_EQ(nlohmann::json::parse(read_file(dir.path("l.json")))["train"]["tangent_mirror"], false);
  ASSERT_EQ(
      run("model train" + common + " --features local --tangent-mirror --out " + dir.path("m.json"),
          log),
      0)
      << read_file(log);
  EXPECT_EQ(nlohmann::json::parse(read_file(dir.path("m.json")))["train"]["tangent_mirror"], true);
  // In the world preset the stiffness and shear priors and the friction cone are off unless asked
  // for; asked for, all
  // reach the model file (the synthetic object's normal force grows with depth and its
  // tangential force with the shear: both priors are fitted).
  EXPECT_FALSE(nlohmann::json::parse(read_file(dir.path("l.json"))).contains("stiffness_prior"));
  EXPECT_FALSE(nlohmann::json::parse(read_file(dir.path("l.json"))).contains("shear_prior"));
  EXPECT_FALSE(nlohmann::json::parse(read_file(dir.path("l.json"))).contains("friction_cone"));
  ASSERT_EQ(run("model train" + common +
                    " --features local --stiffness-prior --shear-prior --friction-cone --out " +
                    dir.path("p.json"),
                log),
            0)
      << read_file(log);
  const auto pj = nlohmann::json::parse(read_file(dir.path("p.json")));
  EXPECT_EQ(pj["train"]["stiffness_prior"], true);
  EXPECT_EQ(pj["train"]["friction_cone"], true);
  EXPECT_EQ(pj["train"]["shear_prior"], true);
  EXPECT_GT(pj["stiffness_prior"]["exponent"].get<double>(), 0.0);
  EXPECT_GT(pj["shear_prior"]["exponent"].get<double>(), 0.0);
  EXPECT_GT(pj["friction_cone"].get<double>(), 0.0);
  for (const char* a : {"x", "y", "z"})
    EXPECT_NEAR(el["errors"]["rmse_n"][a].get<double>(), ew["errors"]["rmse_n"][a].get<double>(),
                1e-9);
  // With no flags, the default preset is the documented pipeline: local frame, mirror, priors,
  // cone, weights 1 5 0.5, blend 1 mm.
  ASSERT_EQ(run("model train --centers 40 --recording " + dir.path("train.csv") + " --out " +
                    dir.path("d.json"),
                log),
            0)
      << read_file(log);
  const auto dj = nlohmann::json::parse(read_file(dir.path("d.json")));
  EXPECT_EQ(dj["features"], "local");
  for (const char* k : {"tangent_mirror", "stiffness_prior", "shear_prior", "friction_cone"})
    EXPECT_EQ(dj["train"][k], true) << k;
  EXPECT_EQ(dj["train"]["feature_weights"], nlohmann::json::array({1.0, 5.0, 0.5}));
  EXPECT_EQ(dj["bin_blend_mm"], 1.0);
  // Without normals the default falls back to the world preset and says so.
  ASSERT_EQ(run("model train --centers 40 --recording " + dir.path("plain.csv") + " --out " +
                    dir.path("f.json"),
                log),
            0)
      << read_file(log);
  EXPECT_NE(read_file(log).find("preset 'world'"), std::string::npos) << read_file(log);
  EXPECT_EQ(nlohmann::json::parse(read_file(dir.path("f.json")))["features"], "ue_q_v");
  // Without normal columns and without a mesh, a local-frame model cannot be trained when asked
  // for explicitly.
  EXPECT_EQ(run("model train --features local --recording " + dir.path("plain.csv") + " --out " +
                    dir.path("x.json"),
                log),
            1);
  EXPECT_NE(read_file(log).find("nx,ny,nz"), std::string::npos) << read_file(log);
}

// Without proxy columns the proxy is estimated from the recording; one that never touches
// anything cannot give a surface: the error names the file and what was expected.
TEST(CliModel, AnUntouchedRecordingWithoutProxyColumnsIsAnError) {
  inhap::test::TempDir dir;
  write_file_atomic(dir.path("rec.csv"), "t,px,py,pz,fx,fy,fz\n0,0,0,0,0,0,0\n0.001,0,0,0,0,0,0\n");
  const std::string log = dir.path("log.txt");
  EXPECT_EQ(
      run("model train --recording " + dir.path("rec.csv") + " --out " + dir.path("m.json"), log),
      1);
  EXPECT_NE(read_file(log).find(dir.path("rec.csv")), std::string::npos) << read_file(log);
  EXPECT_NE(read_file(log).find("surface estimate: expected at least"), std::string::npos)
      << read_file(log);
  write_file_atomic(dir.path("m.json"), "{\"format\": \"inhap-force-model\"}");
  EXPECT_EQ(
      run("model eval --model " + dir.path("m.json") + " --recording " + dir.path("rec.csv"), log),
      1);
  EXPECT_NE(read_file(log).find("version"), std::string::npos) << read_file(log);
}

}  // namespace test_cli_model
}  // namespace inhap::datadriven
