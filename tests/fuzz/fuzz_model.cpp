#include "fuzz_common.hpp"
#include "inhap/datadriven/model_io.hpp"
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return inhap::fuzz::run([&] {
    (void)inhap::datadriven::force_model_from_json(
        std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
  });
}
