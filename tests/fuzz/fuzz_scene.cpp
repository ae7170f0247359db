#include "fuzz_common.hpp"
#include "inhap/lab/scene.hpp"
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return inhap::fuzz::run([&] {
    // Mesh geometry names a file relative to the scene's folder: none exists in the fuzz cwd
    // unless the input names one of the corpus files, which is fine.
    (void)inhap::lab::parse_scene(std::string_view(reinterpret_cast<const char*>(data), size),
                                  "fuzz.json");
  });
}
