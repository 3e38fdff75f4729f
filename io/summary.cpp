#include "io/summary.hpp"

#include "io/atomic_file.hpp"

namespace sphib {

void write_json_atomic(const std::string& path, const nlohmann::json& j) {
  // nlohmann::json serialises non-finite numbers as null.
  write_file_atomic(path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace sphib
