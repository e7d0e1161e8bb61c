// API keys (storage/api_key.h): the documented shape "mk_<8 hex>_<48 hex>", the id as its public
// prefix, SHA-256 as lowercase hex (checked against the standard's test vectors), stable hashes
// and keys that differ.
#include "storage/api_key.h"

#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <string>

namespace mocap::storage {
// Named, so that helpers do not meet other files' in a unity batch.
namespace api_key_test {
namespace {

TEST(ApiKeyTest, GeneratedKeysHaveTheDocumentedShape) {
  auto generated = GenerateApiKey();
  ASSERT_TRUE(generated.ok()) << generated.status();
  const std::string& key = generated->key;
  EXPECT_TRUE(std::regex_match(key, std::regex("mk_[0-9a-f]{8}_[0-9a-f]{48}"))) << key;
  EXPECT_EQ(key.size(), 3u + 8u + 1u + 48u);
  EXPECT_EQ(generated->key_id.size(), 11u);
  EXPECT_EQ(key.substr(0, 11), generated->key_id);
  EXPECT_TRUE(std::regex_match(generated->sha256, std::regex("[0-9a-f]{64}"))) << generated->sha256;
  EXPECT_EQ(generated->sha256, HashApiKey(key));
  EXPECT_EQ(generated->sha256.find(key), std::string::npos);  // what is stored does not hold the key
}

TEST(ApiKeyTest, HashIsSha256InLowercaseHex) {
  // FIPS 180-2 test vectors.
  EXPECT_EQ(HashApiKey(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(HashApiKey("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(HashApiKey("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(ApiKeyTest, HashIsStableAndTellsKeysApart) {
  const std::string key = "mk_0123abcd_" + std::string(48, 'e');
  EXPECT_EQ(HashApiKey(key), HashApiKey(std::string(key)));
  std::string changed = key;
  changed.back() = 'f';
  EXPECT_NE(HashApiKey(key), HashApiKey(changed));
  EXPECT_NE(HashApiKey(key), HashApiKey(key.substr(0, key.size() - 1)));
  EXPECT_NE(HashApiKey(key), HashApiKey(key + "\n"));  // a key pasted with its newline does not match
  // The whole view is hashed, not up to a NUL.
  EXPECT_NE(HashApiKey(std::string_view("mk_a\0b", 6)), HashApiKey("mk_a"));
}

TEST(ApiKeyTest, EveryGeneratedKeyIdAndHashDiffers) {
  std::set<std::string> keys, ids, hashes;
  constexpr int kKeys = 500;  // ids are 32 random bits: a collision among 500 has odds ~3e-5
  for (int i = 0; i < kKeys; ++i) {
    auto generated = GenerateApiKey();
    ASSERT_TRUE(generated.ok()) << generated.status();
    keys.insert(generated->key);
    ids.insert(generated->key_id);
    hashes.insert(generated->sha256);
  }
  EXPECT_EQ(keys.size(), static_cast<size_t>(kKeys));
  EXPECT_EQ(ids.size(), static_cast<size_t>(kKeys));
  EXPECT_EQ(hashes.size(), static_cast<size_t>(kKeys));
}

}  // namespace
}  // namespace api_key_test
}  // namespace mocap::storage
