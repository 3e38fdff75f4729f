#pragma once
// The message of the SceneError thrown by parsing `text` (named scene.toml), or "" if it parsed.
#include <gtest/gtest.h>

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

// A refusal message m names `key` and says `what`.
inline void expect_refusal(const std::string& m, const std::string& key, const std::string& what) {
  EXPECT_NE(m.find(key), std::string::npos) << m;
  EXPECT_NE(m.find(what), std::string::npos) << m;
}

}  // namespace sphib::test
