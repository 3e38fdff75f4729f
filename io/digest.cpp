#include "io/digest.hpp"

#include <openssl/evp.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

namespace sphib {

namespace {

struct Sha256 {
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx{EVP_MD_CTX_new(), EVP_MD_CTX_free};
  Sha256() {
    if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) throw std::runtime_error("SHA-256: cannot start");
  }
  void add(const void* p, size_t n) {
    if (n && EVP_DigestUpdate(ctx.get(), p, n) != 1) throw std::runtime_error("SHA-256: cannot update");
  }
  std::string hex() {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    if (EVP_DigestFinal_ex(ctx.get(), md, &n) != 1) throw std::runtime_error("SHA-256: cannot finish");
    static const char* digits = "0123456789abcdef";
    std::string s;
    for (unsigned int k = 0; k < n; ++k) s += digits[md[k] >> 4], s += digits[md[k] & 15];
    return s;
  }
};

}  // namespace

std::string sha256_hex(const std::string& data) {
  Sha256 h;
  h.add(data.data(), data.size());
  return h.hex();
}

std::string sha256_file_hex(int fd, long long offset, const std::string& path) {
  Sha256 h;
  std::vector<char> buf(1 << 20);
  for (long long at = offset;;) {
    const ssize_t n = ::pread(fd, buf.data(), buf.size(), static_cast<off_t>(at));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::runtime_error("cannot read " + path + ": " + std::strerror(errno));
    if (n == 0) break;
    h.add(buf.data(), static_cast<size_t>(n));
    at += n;
  }
  return h.hex();
}

}  // namespace sphib
