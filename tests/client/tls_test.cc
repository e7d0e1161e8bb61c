// TLS end to end: `mocapd serve --tls-cert --tls-key` with a certificate made for the test, the SDK
// trusting it; a client that does not trust it, or speaks plaintext, gets no answer.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

#include "tests/support/server_fixture.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class TlsTest : public testing::ServerFixture {
 protected:
  // A self-signed certificate for 127.0.0.1 and localhost; false when openssl is not installed.
  bool MakeCertificate() {
    cert_ = dir_ / "server.crt";
    key_ = dir_ / "server.key";
    const std::string command =
        "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost "
        "-addext subjectAltName=IP:127.0.0.1,DNS:localhost -keyout " +
        key_.string() + " -out " + cert_.string() + " >/dev/null 2>&1";
    return std::system(command.c_str()) == 0 && fs::exists(cert_);
  }
  static std::string Read(const fs::path& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  fs::path cert_, key_;
};

TEST_F(TlsTest, TheSdkTalksToATlsServerThatItTrusts) {
  if (!MakeCertificate()) GTEST_SKIP() << "openssl is not installed: cannot make a test certificate";
  StartServer({"--tls-cert", cert_.string(), "--tls-key", key_.string()});
  client::ConnectOptions trusted{.api_key = keys_["acme"], .tls = true, .tls_root_certs_pem = Read(cert_)};
  trusted.max_attempts = 1;
  trusted.deadline = std::chrono::milliseconds(5000);
  auto client = client::Client::Connect(server_->address(), trusted);
  ASSERT_TRUE(client.ok()) << client.status();
  ImportWalks(**client);
  auto databases = (*client)->ListDatabases();
  ASSERT_TRUE(databases.ok()) << databases.status();
  EXPECT_EQ(databases->size(), 1u);

  // Plaintext, and TLS trusting other roots (the system's), both fail without an answer.
  client::ConnectOptions plaintext{.api_key = keys_["acme"]};
  plaintext.max_attempts = 1;
  plaintext.deadline = std::chrono::milliseconds(2000);
  // The plaintext client is told it may be TLS (issue #25: it got only "Socket closed").
  const absl::Status plain = (*client::Client::Connect(server_->address(), plaintext))->ListDatabases().status();
  EXPECT_FALSE(plain.ok());
  EXPECT_NE(plain.message().find("TLS"), std::string_view::npos) << plain;
  client::ConnectOptions untrusted = plaintext;
  untrusted.tls = true;
  const absl::Status refused = (*client::Client::Connect(server_->address(), untrusted))->ListDatabases().status();
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("TLS"), std::string_view::npos) << refused;
}

TEST_F(TlsTest, HalfATlsConfigurationIsRefusedAtStart) {
  if (!MakeCertificate()) GTEST_SKIP() << "openssl is not installed: cannot make a test certificate";
  testing::ServerProcess server(MOCAPD_PATH, store_, dir_ / "half.log", {"--tls-cert", cert_.string()});
  EXPECT_TRUE(server.address().empty());
  EXPECT_NE(Read(dir_ / "half.log").find("--tls-key"), std::string::npos) << Read(dir_ / "half.log");
}

}  // namespace
}  // namespace mocap
