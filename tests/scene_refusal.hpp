#pragma once
// The message of the SceneError thrown by parsing `text` (named scene.toml), or "" if it parsed.
#include <string>
#include <vector>

#include "io/scene.hpp"

namespace sphib::test {

inline std::string refusal(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    parse_scene(text, "scene.toml", sets);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace sphib::test
