#pragma once
// SHA-256 digests (OpenSSL's libcrypto): of a text (the key of a sweep's run: every resolved scene
// value) and of a file from an offset on (a checkpoint's seal), as 64 lowercase hex digits.
#include <string>

namespace sphib {

std::string sha256_hex(const std::string& data);

// The digest of the bytes of the open file `fd` from `offset` to its end. Throws std::runtime_error
// naming `path` if it cannot be read.
std::string sha256_file_hex(int fd, long long offset, const std::string& path);

}  // namespace sphib
