// libFuzzer target: the scene parser must refuse any input with a SceneError (never crash, hang
// or throw anything else). Built with -DSPHIB_FUZZ=ON and clang (scripts/run_fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    sphib::parse_scene(text, "fuzz.toml");
  } catch (const sphib::SceneError&) {
  }
  return 0;
}
