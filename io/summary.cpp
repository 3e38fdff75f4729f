#include "io/summary.hpp"

#include "io/atomic_file.hpp"

namespace sphib {

std::string json_text(const nlohmann::json& j) {
  // nlohmann::json serialises non-finite numbers as null.
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void write_json_atomic(const std::string& path, const nlohmann::json& j) { write_file_atomic(path, json_text(j)); }

}  // namespace sphib
