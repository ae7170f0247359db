// `inhap serve` across a process boundary: the C client (this test process) drives the program
// over loopback; the forces are those of the rendered plane, the recording is complete.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <string>
#include <thread>

#include "inhap/core/csv.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap_bridge.h"
#include "support/meshes.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace inhap {
namespace {

TEST(CliServe, ADeviceClientFeelsTheRenderedPlaneAndTheSessionIsRecorded) {
  test::TempDir dir;
  // A 100 x 100 mm plane at z = 0 with stiffness 0.5 N/mm.
  TriMesh plane = test::make_grid_mesh(21, 21, 5.0);
  plane.set_property("stiffness", std::vector<double>(plane.positions.size(), 0.5));
  const std::string mesh = (dir.root() / "plane.ply").string();
  write_mesh(mesh, plane);
  const std::string rec = (dir.root() / "session.csv").string();
  const int port = 20000 + static_cast<int>(getpid() % 20000);

  test::CliResult serve;
  std::thread server([&] {
    serve = test::run_cli("serve --device udp:" + std::to_string(port) + " --render cba --mesh " +
                          mesh + " --record " + rec +
                          " --seconds 4 --no-realtime --connect-timeout 20 --timeout 0.2");
  });
  inhap_bridge c;
  ASSERT_EQ(inhap_bridge_open(&c, "127.0.0.1", static_cast<unsigned short>(port), nullptr), 0);
  double f[3];
  const double start[3] = {50.0, 50.0, 2.0};
  // Until the program listens, states go nowhere: retry.
  int tries = 0;
  while (inhap_bridge_exchange(&c, 0.0, start, nullptr, 0, f, nullptr, 100000) != 1 &&
         ++tries < 200) {
  }
  ASSERT_LT(tries, 200) << "inhap serve did not answer";
  // Press down to 1 mm below the surface, then hold; the god-object force is k * depth.
  int answered = 0;
  double last_fz = 0;
  for (int i = 1; i <= 1500; ++i) {
    const double z = std::max(-1.0, 2.0 - 0.005 * i);
    const double p[3] = {50.0, 50.0, z};
    if (inhap_bridge_exchange(&c, 1e-3 * i, p, nullptr, 0, f, nullptr, 200000) == 1) {
      ++answered;
      last_fz = f[2];
      EXPECT_EQ(f[0], 0.0);
      EXPECT_EQ(f[1], 0.0);
      if (z > 0.01) {
        EXPECT_EQ(f[2], 0.0) << "tick " << i;
      }
    }
    usleep(500);
  }
  inhap_bridge_close(&c);
  server.join();
  EXPECT_EQ(serve.status, 0) << serve.out;
  EXPECT_GT(answered, 1400);
  EXPECT_NEAR(last_fz, 0.5, 1e-6) << "0.5 N/mm x 1 mm";
  EXPECT_NE(serve.out.find("step p50/p99"), std::string::npos) << serve.out;
  const Recording r = read_recording(rec);
  EXPECT_GE(r.size(), static_cast<std::size_t>(answered));
}

TEST(CliServe, TheVirtualLabServesInProcessAndItsSessionHasTruth) {
  test::TempDir dir;
  TriMesh plane = test::make_grid_mesh(21, 21, 5.0);
  plane.set_property("stiffness", std::vector<double>(plane.positions.size(), 0.5));
  write_mesh(dir.path("plane.ply"), plane);
  const std::string rec = dir.path("lab.csv");
  const auto r = test::run_cli(
      "serve --device lab:planar --operator explore --seed 2 --render cba "
      "--mesh " +
      dir.path("plane.ply") + " --seconds 1.5 --no-realtime --record " + rec);
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("virtual lab"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("read-ahead p50/p99"), std::string::npos) << "CBA reads ahead\n" << r.out;
  const Recording rows = read_recording(rec);
  const CsvTable truth = read_csv(dir.path("lab.truth.csv"));
  EXPECT_GT(rows.size(), 1000u) << "1.5 s at 1 kHz";
  EXPECT_EQ(truth.rows(), rows.size()) << "one truth row per recorded tick";
  for (std::size_t i = 0; i < std::min(rows.size(), truth.rows()); ++i)
    ASSERT_EQ(truth.column("t")[i], rows.t[i]) << "row " << i;
}

TEST(CliServe, BadFlagsGetOneLineErrors) {
  auto r = test::run_cli("serve --device tcp:5 --render cba --mesh x.ply");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("--device"), std::string::npos) << r.out;
  r = test::run_cli("serve --render tca");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("--mesh"), std::string::npos) << r.out;
  r = test::run_cli("serve --render cba --mesh x.ply --listen 0.0.0.0 --device udp:0");
  EXPECT_NE(r.status, 0);
}

}  // namespace
}  // namespace inhap
