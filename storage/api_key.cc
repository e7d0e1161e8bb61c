#include "storage/api_key.h"

#include <openssl/evp.h>
#include <openssl/rand.h>

#include <array>

namespace mocap::storage {
namespace {

std::string Hex(const unsigned char* bytes, size_t size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out(2 * size, '0');
  for (size_t i = 0; i < size; ++i) {
    out[2 * i] = kDigits[bytes[i] >> 4];
    out[2 * i + 1] = kDigits[bytes[i] & 15];
  }
  return out;
}

}  // namespace

absl::StatusOr<GeneratedApiKey> GenerateApiKey() {
  std::array<unsigned char, 4 + 24> random{};
  if (RAND_bytes(random.data(), static_cast<int>(random.size())) != 1) {
    return absl::InternalError("the system random source failed; no key was made");
  }
  GeneratedApiKey out;
  out.key_id = "mk_" + Hex(random.data(), 4);
  out.key = out.key_id + "_" + Hex(random.data() + 4, 24);
  out.sha256 = HashApiKey(out.key);
  return out;
}

std::string HashApiKey(std::string_view key) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int size = 0;
  EVP_Digest(key.data(), key.size(), digest.data(), &size, EVP_sha256(), nullptr);
  return Hex(digest.data(), size);
}

}  // namespace mocap::storage
