#include "server/server_status_service.h"

#include "server/motion_store_service.h"

namespace mocap {

grpc::ServerUnaryReactor* ServerStatusService::GetMetrics(grpc::CallbackServerContext* context,
                                                          const v1::GetMetricsRequest*,
                                                          v1::GetMetricsResponse* response) {
  return RunUnary(service_, context, "GetMetrics", [response](CallScope& call) {
    // Another tenant's traffic is not this tenant's business: a tenant gets its own counters, and
    // only the default tenant (the operator's, which the local admin commands act as) the server's.
    ServerMetrics& server = call.service().metrics;
    const bool operator_call = call.tenant().id == kDefaultTenantId;
    response->set_text(operator_call ? server.PrometheusText() : server.OfTenant(call.tenant().id).PrometheusText());
    return absl::OkStatus();
  });
}

}  // namespace mocap
