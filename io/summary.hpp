#pragma once
// Run summary as JSON (integral results, timings, parameters).
#include <string>

#include <nlohmann/json.hpp>

namespace sphib {

// Pretty-printed (indent 2), written to path.part then renamed to path. NaN and +-Inf become
// null (JSON has no such numbers); invalid UTF-8 in strings is replaced by U+FFFD.
// Throws std::runtime_error naming the file on failure.
void write_json_atomic(const std::string& path, const nlohmann::json& j);

// The text write_json_atomic writes.
std::string json_text(const nlohmann::json& j);

}  // namespace sphib
