// The servo loop of inhap.Renderer.replay written in C++ alone, for the Python benchmark
// (python/bench/bench_replay.py): reads a mesh with a stiffness map and a recording's t,p, runs
// TCA-MESH (or CBA) through the common servo interface over every row, storing force, IHIP,
// CIHIP and contact per tick as replay does, and prints the best loop time of REPEATS runs.
// Usage: inhap_replay_loop MESH.ply PATH.csv [tca|cba] [REPEATS]. Units: mm, N, s.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/haptics/renderers.hpp"
#include "inhap/rendering/renderer.hpp"

int main(int argc, char** argv) {
  using namespace inhap;
  if (argc < 3) {
    fmt::print(stderr, "usage: {} MESH.ply PATH.csv [tca|cba] [REPEATS]\n", argv[0]);
    return 2;
  }
  try {
    const rendering::Model model(read_mesh(argv[1]));
    const Recording rec = read_recording(argv[2]);
    const bool tca = argc < 4 || std::string(argv[3]) != "cba";
    const int repeats = argc > 4 ? std::max(1, std::atoi(argv[4])) : 3;
    const std::size_t n = rec.size();
    std::vector<Vec3> f(n), q(n), qc(n);
    std::vector<char> contact(n);
    double best = 1e300;
    for (int k = 0; k < repeats; ++k) {
      haptics::MeshRenderer r(model, tca ? rendering::Algorithm::kTCA : rendering::Algorithm::kCBA);
      const auto t0 = std::chrono::steady_clock::now();
      haptics::ServoInput in;
      for (std::size_t i = 0; i < n; ++i) {
        in.t_s = rec.t[i];
        in.p_mm = rec.p[i];
        const haptics::ServoOutput o = r.step(in);
        f[i] = o.force_n;
        q[i] = o.ihip_mm;
        qc[i] = o.cihip_mm;
        contact[i] = o.contact;
      }
      best = std::min(best,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    double sum = 0;
    for (const Vec3& v : f) sum += v.z();
    fmt::print("{} ticks {:.6f} s best of {} ({:.4f} us/tick), sum fz {:.17g}\n", n, best, repeats,
               best / double(n) * 1e6, sum);
  } catch (const Error& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  return 0;
}
