// CSV throughput (issue 2 asks >= 50 MB/s read): a 60 s recording at 1 kHz (60,000 rows) with
// the columns of a lab recording (t, px..pz in mm, fx..fz in N, three raw-sensor extras), written
// with write_recording and read back with read_recording (validation included: finite values,
// increasing time) and with the streaming CsvReader alone. Throughput is bytes per WALL second
// (MB/s in the output); the file size is printed as a counter.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "inhap/core/csv.hpp"
#include "inhap/core/random.hpp"

using namespace inhap;

namespace {

Recording synthetic_recording(std::size_t rows) {
  Recording r;
  Rng rng(7);
  std::vector<double> sx, sy, sz;
  for (std::size_t i = 0; i < rows; ++i) {
    const double t = 0.001 * static_cast<double>(i);
    r.t.push_back(t);
    r.p.emplace_back(20 * std::sin(0.7 * t) + 0.01 * rng.normal(), 15 * std::cos(0.5 * t),
                     -2 + std::sin(3 * t));
    r.f.emplace_back(0.3 * rng.normal(), 0.3 * rng.normal(), 2 + rng.normal());
    sx.push_back(rng.normal());
    sy.push_back(rng.normal());
    sz.push_back(rng.normal());
  }
  r.set_extra("sx", std::move(sx));
  r.set_extra("sy", std::move(sy));
  r.set_extra("sz", std::move(sz));
  return r;
}

struct File {
  std::string path;
  std::uintmax_t bytes = 0;
  File() {
    path = (std::filesystem::temp_directory_path() /
            ("inhap-bench-csv-" + std::to_string(::getpid()) + ".csv"))
               .string();
    write_recording(path, synthetic_recording(60000));
    bytes = std::filesystem::file_size(path);
  }
  ~File() { std::filesystem::remove(path); }
};

const File& file() {
  static const File f;
  return f;
}

void BM_ReadRecording60k(benchmark::State& state) {
  const File& f = file();
  for (auto _ : state) {
    Recording r = read_recording(f.path);
    benchmark::DoNotOptimize(r.p.data());
  }
  state.counters["file_MB"] = static_cast<double>(f.bytes) / 1e6;
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * f.bytes));
}

void BM_CsvReaderStream60k(benchmark::State& state) {
  const File& f = file();
  for (auto _ : state) {
    CsvReader reader(f.path);
    double sum = 0;
    while (reader.next()) sum += reader[1];
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * f.bytes));
}

void BM_WriteRecording60k(benchmark::State& state) {
  const Recording r = synthetic_recording(60000);
  const std::string path = file().path + ".w";
  for (auto _ : state) write_recording(path, r);
  state.SetBytesProcessed(
      static_cast<std::int64_t>(state.iterations() * std::filesystem::file_size(path)));
  std::filesystem::remove(path);
}

}  // namespace

BENCHMARK(BM_ReadRecording60k)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CsvReaderStream60k)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_WriteRecording60k)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
