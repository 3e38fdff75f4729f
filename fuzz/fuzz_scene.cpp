// libFuzzer target: the scene parser must refuse any input with a SceneError (never crash, hang
// or throw anything else). Built with -DSPHIB_FUZZ=ON and clang (scripts/run_fuzz.sh).
// An input that begins "#expr " is a --derive expression instead (app/expression.hpp): evaluated or
// refused with an ExpressionError. A scene's leading comment lines "# set: key=value" are applied as
// --set overrides (fuzz/corpus/deep_set: a key of 15 001 parts).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "app/expression.hpp"
#include "io/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (text.rfind("#expr ", 0) == 0) {
    try {
      sphib::app::evaluate(text.substr(6));
    } catch (const sphib::app::ExpressionError&) {
    }
    return 0;
  }
  std::vector<std::string> sets;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line) && line.rfind("# set: ", 0) == 0;) sets.push_back(line.substr(7));
  try {
    sphib::parse_scene(text, "fuzz.toml", sets);
  } catch (const sphib::SceneError&) {
  }
  return 0;
}
