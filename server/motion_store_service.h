// The MotionStore gRPC service (proto/mocap/v1/motion_store.proto) on the callback API: each
// handler posts its work to the WorkPool and finishes from there; ImportBvh and ExportClip are
// reactors that read or write one message at a time (backpressure, no thread per stream).
#pragma once

#include "mocap/v1/motion_store.grpc.pb.h"
#include "server/service_context.h"

namespace mocap {

class MotionStoreService final : public v1::MotionStore::CallbackService {
 public:
  explicit MotionStoreService(ServiceContext& service) : service_(service) {}

  grpc::ServerUnaryReactor* CreateDatabase(grpc::CallbackServerContext* context,
                                           const v1::CreateDatabaseRequest* request,
                                           v1::CreateDatabaseResponse* response) override;
  grpc::ServerUnaryReactor* ListDatabases(grpc::CallbackServerContext* context, const v1::ListDatabasesRequest* request,
                                          v1::ListDatabasesResponse* response) override;
  grpc::ServerUnaryReactor* DescribeDatabase(grpc::CallbackServerContext* context,
                                             const v1::DescribeDatabaseRequest* request,
                                             v1::DescribeDatabaseResponse* response) override;
  grpc::ServerUnaryReactor* DeleteDatabase(grpc::CallbackServerContext* context,
                                           const v1::DeleteDatabaseRequest* request,
                                           v1::DeleteDatabaseResponse* response) override;
  grpc::ServerReadReactor<v1::ImportBvhRequest>* ImportBvh(grpc::CallbackServerContext* context,
                                                           v1::ImportBvhResponse* response) override;
  grpc::ServerUnaryReactor* ListClips(grpc::CallbackServerContext* context, const v1::ListClipsRequest* request,
                                      v1::ListClipsResponse* response) override;
  grpc::ServerWriteReactor<v1::ExportClipResponse>* ExportClip(grpc::CallbackServerContext* context,
                                                               const v1::ExportClipRequest* request) override;
  grpc::ServerUnaryReactor* DeleteClip(grpc::CallbackServerContext* context, const v1::DeleteClipRequest* request,
                                       v1::DeleteClipResponse* response) override;

 private:
  ServiceContext& service_;
};

// Runs `work(call)` on the worker pool after authentication and admission, then finishes the
// call with its status. Exceptions become INTERNAL (logged).
grpc::ServerUnaryReactor* RunUnary(ServiceContext& service, grpc::CallbackServerContext* context, const char* method,
                                   std::function<absl::Status(CallScope&)> work);

}  // namespace mocap
