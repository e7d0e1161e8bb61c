#include "server/server_status_service.h"

#include "server/motion_store_service.h"

namespace mocap {

grpc::ServerUnaryReactor* ServerStatusService::GetMetrics(grpc::CallbackServerContext* context,
                                                          const v1::GetMetricsRequest*,
                                                          v1::GetMetricsResponse* response) {
  return RunUnary(service_, context, "GetMetrics", [response](CallScope& call) {
    response->set_text(call.service().metrics.PrometheusText());
    return absl::OkStatus();
  });
}

}  // namespace mocap
