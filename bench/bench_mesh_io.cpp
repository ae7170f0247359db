// Mesh file I/O speed: a ~1M-triangle grid (501,264 vertices, 999,698 triangles) with normals
// and a `stiffness` property (N/mm), read and written as binary and ascii PLY and as OBJ.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/geometry/obj.hpp"
#include "inhap/geometry/ply.hpp"

using namespace inhap;

namespace {

TriMesh grid_mesh(int n) {
  TriMesh m;
  std::vector<double> stiffness;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i * 0.1, y = j * 0.1;  // mm
      m.positions.emplace_back(x, y, std::sin(x) * std::cos(y));
      stiffness.push_back(0.5 + 0.01 * ((i * 7 + j * 13) % 100));
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  m.set_property("stiffness", std::move(stiffness));
  m.compute_normals();
  return m;
}

const TriMesh& mesh() {
  static const TriMesh m = grid_mesh(708);
  return m;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("inhap-bench-" + std::to_string(::getpid()) + "-" + name))
      .string();
}

void read_bench(benchmark::State& state, PlyFormat format, const char* name) {
  const std::string path = temp_path(name);
  write_ply(path, mesh(), {format});
  const auto bytes = std::filesystem::file_size(path);
  for (auto _ : state) {
    TriMesh m = read_ply(path);
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["triangles"] = static_cast<double>(mesh().num_triangles());
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
  std::filesystem::remove(path);
}

void BM_ReadPlyBinary1M(benchmark::State& state) {
  read_bench(state, PlyFormat::kBinaryLittleEndian, "r.ply");
}
void BM_ReadPlyBinaryBigEndian1M(benchmark::State& state) {
  read_bench(state, PlyFormat::kBinaryBigEndian, "rbe.ply");
}
void BM_ReadPlyAscii1M(benchmark::State& state) {
  read_bench(state, PlyFormat::kAscii, "ra.ply");
}

void BM_ParsePlyBinaryInMemory1M(benchmark::State& state) {
  const std::string bytes = format_ply(mesh());
  for (auto _ : state) {
    TriMesh m = parse_ply(bytes, "mem");
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}

void BM_WritePlyBinary1M(benchmark::State& state) {
  const std::string path = temp_path("w.ply");
  for (auto _ : state) write_ply(path, mesh());
  std::filesystem::remove(path);
}

void BM_ReadObj1M(benchmark::State& state) {
  const std::string path = temp_path("r.obj");
  write_obj(path, mesh());
  for (auto _ : state) {
    TriMesh m = read_obj(path);
    benchmark::DoNotOptimize(m.positions.data());
  }
  std::filesystem::remove(path);
}

}  // namespace

BENCHMARK(BM_ReadPlyBinary1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadPlyBinaryBigEndian1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParsePlyBinaryInMemory1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadPlyAscii1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WritePlyBinary1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadObj1M)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
