#include "server/service_context.h"

#include <new>

#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/log_text.h"

namespace mocap {
namespace {

// The key from "authorization: Bearer <key>"; empty when absent or not a bearer token.
std::string BearerKey(const grpc::CallbackServerContext& context) {
  const auto& metadata = context.client_metadata();
  auto it = metadata.find("authorization");
  if (it == metadata.end()) return {};
  const std::string value(it->second.data(), it->second.size());
  constexpr std::string_view kPrefix = "Bearer ";
  if (value.size() <= kPrefix.size() || value.compare(0, kPrefix.size(), kPrefix) != 0) return {};
  return value.substr(kPrefix.size());
}

}  // namespace

const char* GrpcCodeName(grpc::StatusCode code) {
  static const char* const kNames[] = {
      "OK",        "CANCELLED",      "UNKNOWN",           "INVALID_ARGUMENT",   "DEADLINE_EXCEEDED",
      "NOT_FOUND", "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION",
      "ABORTED",   "OUT_OF_RANGE",   "UNIMPLEMENTED",     "INTERNAL",           "UNAVAILABLE",
      "DATA_LOSS", "UNAUTHENTICATED"};
  const int index = static_cast<int>(code);
  return index >= 0 && index < 17 ? kNames[index] : "UNKNOWN";
}

grpc::Status ToGrpcStatus(const absl::Status& status, const std::string& request_id) {
  if (status.ok()) return grpc::Status::OK;
  const auto code = static_cast<grpc::StatusCode>(status.code());
  if (code == grpc::StatusCode::INTERNAL || code == grpc::StatusCode::DATA_LOSS || code == grpc::StatusCode::UNKNOWN) {
    return grpc::Status(code, StrCat("internal server error (request ", request_id, ")"));
  }
  return grpc::Status(code, std::string(status.message()));
}

CallScope::CallScope(ServiceContext& service, grpc::CallbackServerContext* context, std::string method)
    : service_(service),
      context_(context),
      method_(std::move(method)),
      request_id_(StrCat("r", service.next_request_id.fetch_add(1))),
      start_(std::chrono::steady_clock::now()) {
  service_.metrics.CallStarted();
}

CallScope::~CallScope() {
  if (!ended_) metrics().CallFinished(method_, "CANCELLED", 0.0);
}

absl::Status CallScope::RequireWritableStore() const {
  if (!service_.stores.read_only()) return absl::OkStatus();
  return absl::FailedPreconditionError(
      StrCat(method_,
             ": this server serves a read-only store (mocapd serve --read-only); "
             "change the store with mocapd import on its writer and roll the file out"));
}

absl::Status CallScope::CheckKeyPresent() {
  if (!BearerKey(*context_).empty()) return absl::OkStatus();
  service_.metrics.Rejected("no_key");
  return absl::UnauthenticatedError("no API key: send metadata 'authorization: Bearer <key>'");
}

absl::Status CallScope::Begin(TenantAdmission* admission, const char* limit_name) {
  try {
    return BeginUnguarded(admission, limit_name);
  } catch (const std::bad_alloc&) {
    return absl::ResourceExhaustedError("the server ran out of memory authenticating the call; retry later");
  } catch (const std::exception& error) {
    return absl::InternalError(StrCat("authenticating the call failed: ", error.what()));
  }
}

absl::Status CallScope::BeginUnguarded(TenantAdmission* admission, const char* limit_name) {
  MOCAP_RETURN_IF_ERROR(CheckKeyPresent());
  const std::string key = BearerKey(*context_);
  MOCAP_ASSIGN_OR_RETURN(StorePool::Lease lease, service_.stores.Acquire());
  store_ = std::move(lease);
  absl::StatusOr<Tenant> tenant = TenantDirectory(**store_).Authenticate(key);
  if (!tenant.ok()) {
    if (tenant.status().code() == absl::StatusCode::kUnauthenticated) service_.metrics.Rejected("bad_key");
    return tenant.status();
  }
  tenant_ = std::move(*tenant);
  tenant_metrics_ = &service_.metrics.OfTenant(tenant_.id, tenant_.name);
  tenant_metrics_->CallStarted();
  absl::StatusOr<TenantAdmission::Ticket> ticket = (admission ? *admission : service_.admission).Admit(tenant_.id);
  if (!ticket.ok()) {
    metrics().Rejected(limit_name);
    return ticket.status();
  }
  ticket_ = std::move(*ticket);
  return absl::OkStatus();
}

grpc::Status CallScope::End(const absl::Status& status) {
  ended_ = true;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const grpc::Status mapped = ToGrpcStatus(status, request_id_);
  metrics().CallFinished(method_, GrpcCodeName(mapped.error_code()), seconds);
  const std::string tenant = tenant_.name.empty() ? "-" : tenant_.name;
  if (status.ok()) {
    spdlog::info("request={} method={} tenant={} peer={} code=OK ms={:.1f}", request_id_, method_, tenant,
                 LogText(context_->peer()), seconds * 1e3);
  } else {
    spdlog::warn("request={} method={} tenant={} peer={} code={} ms={:.1f} error=\"{}\"", request_id_, method_, tenant,
                 LogText(context_->peer()), GrpcCodeName(mapped.error_code()), seconds * 1e3,
                 LogText(std::string(status.message())));
  }
  ticket_.reset();
  store_.reset();
  return mapped;
}

}  // namespace mocap
