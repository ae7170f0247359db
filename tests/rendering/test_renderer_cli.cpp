// `inhap tca stroke` end to end: PLY in, CSV out with the documented columns, and the CBA dip
// over a soft half visible in the HIP height. Units: mm, N, N/mm, s.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "inhap/core/csv.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "rendering/render_fixtures.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;

namespace {

// Runs the CLI; returns its exit status and captures stdout+stderr.
int run_cli(const std::string& args, std::string& output) {
  const std::string cmd = std::string(INHAP_CLI) + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  char buf[4096];
  output.clear();
  while (std::fgets(buf, sizeof buf, pipe)) output += buf;
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(RendererCli, TcaStrokeWritesTrajectoryCsv) {
  test::TempDir dir;
  const std::string mesh = dir.path("halves.ply");
  write_mesh(mesh, test::grid_mesh(
                       80, 10, 0.5, -20, -2.5, [](double, double) { return 0.0; },
                       [](double x, double) { return x < -1e-9 ? 1.0 : 0.25; }));
  std::string out;
  for (const std::string alg : {"cba", "tca"}) {
    const std::string csv = dir.path(alg + ".csv");
    ASSERT_EQ(run_cli("tca stroke --mesh " + mesh + " --algorithm " + alg +
                          " --from -15,0 --to 15,0 --force 1 --speed 30 --seed 2 --out " + csv,
                      out),
              0)
        << out;
    const CsvTable t = read_csv(csv);
    const std::vector<std::string> cols = {"t",  "px", "py", "pz", "qx",     "qy", "qz",
                                           "cx", "cy", "cz", "fx", "fy",     "fz", "k",
                                           "s",  "tx", "ty", "tz", "contact"};
    ASSERT_EQ(t.names, cols);
    ASSERT_GT(t.rows(), 1000u);
    EXPECT_NEAR(t.column("t")[1] - t.column("t")[0], 0.001, 1e-12);
    // HIP height over the stiff and the soft half while in contact.
    double zs = 0, zf = 0;
    int ns = 0, nf = 0;
    for (std::size_t i = 0; i < t.rows(); ++i) {
      if (t.column("contact")[i] != 1.0) continue;
      const double x = t.column("px")[i], z = t.column("pz")[i];
      if (x > -12 && x < -3) zs += z, ++ns;
      if (x > 2 && x < 5) zf += z, ++nf;
    }
    ASSERT_GT(ns, 100);
    ASSERT_GT(nf, 50);
    const double step = zf / nf - zs / ns;  // CBA: -F (1/0.25 - 1/1) = -3 mm
    if (alg == "cba") {
      EXPECT_NEAR(step, -3.0, 0.15);
    } else {
      EXPECT_LT(std::abs(step), 0.25);  // TCA: only the a_s restoration over <= 5 mm
    }
  }
  std::ifstream in(dir.path("tca.csv"));
  std::string first;
  std::getline(in, first);
  std::getline(in, first);
  EXPECT_EQ(first.rfind("# units", 0), 0u) << first;
}

TEST(RendererCli, TcaStrokeRejectsBadArguments) {
  test::TempDir dir;
  const std::string mesh = dir.path("plane.ply");
  write_mesh(mesh, test::flat_plane(4, 4, 1, 0, 0));
  std::string out;
  EXPECT_NE(
      run_cli("tca stroke --mesh " + mesh + " --from '1;2' --to 3,3 --out " + dir.path("a.csv"),
              out),
      0);
  EXPECT_NE(out.find("--from: expected X,Y"), std::string::npos) << out;
  EXPECT_NE(run_cli("tca stroke --mesh " + mesh + " --algorithm xyz --from 1,1 --to 3,3 --out " +
                        dir.path("a.csv"),
                    out),
            0);
  EXPECT_NE(out.find("expected tca or cba"), std::string::npos) << out;
  EXPECT_NE(
      run_cli("tca stroke --mesh " + mesh + " --from 50,50 --to 3,3 --out " + dir.path("a.csv"),
              out),
      0);
  EXPECT_NE(out.find("no surface below"), std::string::npos) << out;
  EXPECT_EQ(run_cli("tca stroke --help", out), 0);
  EXPECT_NE(out.find("N/mm"), std::string::npos);
  EXPECT_NE(out.find("tx,ty,tz"), std::string::npos);
}
