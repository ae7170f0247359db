// Cycles CSV: read as written (every column) and, for rigs that log less, with a plane shape to
// take missing normals from and the angle column for missing directions.
#include "fuzz_common.hpp"
#include "inhap/friction/cycles_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = inhap::fuzz::temp_path("csv");
  inhap::fuzz::write_temp(path, data, size);
  static const inhap::friction::PlaneShape plane(inhap::Vec3::Zero(), inhap::Vec3::UnitZ());
  inhap::fuzz::run([&] { (void)inhap::friction::read_cycles_csv(path); });
  return inhap::fuzz::run([&] {
    (void)inhap::friction::read_cycles_csv(path, {&plane, inhap::Vec3::UnitX(), 5.0});
  });
}
