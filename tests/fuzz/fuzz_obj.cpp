#include "fuzz_common.hpp"
#include "inhap/geometry/obj.hpp"
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return inhap::fuzz::run([&] {
    (void)inhap::parse_obj(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.obj");
  });
}
