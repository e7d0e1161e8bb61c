#include "client/src/status_mapping.h"

#include <string>

namespace mocap::client {

namespace {

// What a connection failure most likely means, for the two TLS mismatches gRPC reports only as
// transport errors (issue #25: a plaintext client talking to a TLS server got "Socket closed").
std::string TransportHint(const std::string& message) {
  if (message.find("Socket closed") != std::string::npos) {
    // Said of both causes: a plaintext client refused by a TLS server, and a server that stopped or
    // restarted mid-call look the same from here (issue #24: a restart read as a TLS problem).
    return "; the server closed the connection: it may have stopped or restarted (try again), or, if it "
           "serves TLS (mocapd serve --tls-cert), connect with TLS (mocap --tls, or ConnectOptions.tls)";
  }
  if (message.find("andshake failed") != std::string::npos) {
    return "; the TLS handshake failed: trust the server's certificate (mocap --tls-root-certs, or "
           "ConnectOptions.tls_root_certs_pem), or, if the server is plaintext, connect without TLS";
  }
  return "";
}

}  // namespace

absl::Status FromGrpc(const grpc::Status& status) {
  if (status.ok()) return absl::OkStatus();
  std::string message = status.error_message();
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) message += TransportHint(message);
  return absl::Status(static_cast<absl::StatusCode>(status.error_code()), message);
}

}  // namespace mocap::client
