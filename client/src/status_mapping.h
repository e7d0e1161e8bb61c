// grpc::Status -> absl::Status (the codes are the same numbers), in one place.
#pragma once

#include <grpcpp/support/status.h>

#include "absl/status/status.h"

namespace mocap::client {

absl::Status FromGrpc(const grpc::Status& status);

}  // namespace mocap::client
