// The ServerStatus gRPC service: GetMetrics returns ServerMetrics in Prometheus text.
#pragma once

#include "mocap/v1/server_status.grpc.pb.h"
#include "server/service_context.h"

namespace mocap {

class ServerStatusService final : public v1::ServerStatus::CallbackService {
 public:
  explicit ServerStatusService(ServiceContext& service) : service_(service) {}
  grpc::ServerUnaryReactor* GetMetrics(grpc::CallbackServerContext* context, const v1::GetMetricsRequest* request,
                                       v1::GetMetricsResponse* response) override;

 private:
  ServiceContext& service_;
};

}  // namespace mocap
