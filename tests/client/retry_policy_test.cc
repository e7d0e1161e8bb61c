// The SDK retries UNAVAILABLE only where repeating the call is safe (issue #14: it retried
// CreateDatabase and the deletes, which may have taken effect before the connection broke).
// An in-process MotionStore answers every call UNAVAILABLE and counts the attempts.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <mutex>
#include <string>

#include "mocap/client.h"
#include "mocap/v1/motion_store.grpc.pb.h"

namespace mocap {
namespace {

class UnavailableStore final : public v1::MotionStore::Service {
 public:
  int attempts(const std::string& method) {
    std::lock_guard lock(mutex_);
    return attempts_[method];
  }

  grpc::Status CreateDatabase(grpc::ServerContext*, const v1::CreateDatabaseRequest*,
                              v1::CreateDatabaseResponse*) override {
    return Count("CreateDatabase");
  }
  grpc::Status DeleteDatabase(grpc::ServerContext*, const v1::DeleteDatabaseRequest*,
                              v1::DeleteDatabaseResponse*) override {
    return Count("DeleteDatabase");
  }
  grpc::Status DeleteClip(grpc::ServerContext*, const v1::DeleteClipRequest*, v1::DeleteClipResponse*) override {
    return Count("DeleteClip");
  }
  grpc::Status ListDatabases(grpc::ServerContext*, const v1::ListDatabasesRequest*,
                             v1::ListDatabasesResponse*) override {
    return Count("ListDatabases");
  }
  grpc::Status DescribeDatabase(grpc::ServerContext*, const v1::DescribeDatabaseRequest*,
                                v1::DescribeDatabaseResponse*) override {
    return Count("DescribeDatabase");
  }

 private:
  grpc::Status Count(const std::string& method) {
    std::lock_guard lock(mutex_);
    ++attempts_[method];
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "going away");
  }
  std::mutex mutex_;
  std::map<std::string, int> attempts_;
};

TEST(RetryPolicyTest, OnlyCallsSafeToRepeatAreRetriedOnUnavailable) {
  UnavailableStore service;
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
  builder.RegisterService(&service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  ASSERT_NE(port, 0);
  client::ConnectOptions options{.api_key = "k"};
  options.max_attempts = 3;
  options.retry_backoff = std::chrono::milliseconds(1);
  auto client = client::Client::Connect("127.0.0.1:" + std::to_string(port), options);
  ASSERT_TRUE(client.ok());

  EXPECT_EQ((*client)->CreateDatabase("walks").status().code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ((*client)->DeleteDatabase("walks").code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ((*client)->DeleteClip("walks", 1).code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ((*client)->ListDatabases().status().code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ((*client)->DescribeDatabase("walks").status().code(), absl::StatusCode::kUnavailable);
  for (const char* once : {"CreateDatabase", "DeleteDatabase", "DeleteClip"}) {
    EXPECT_EQ(service.attempts(once), 1) << once << " was sent again after UNAVAILABLE";
  }
  for (const char* retried : {"ListDatabases", "DescribeDatabase"}) {
    EXPECT_EQ(service.attempts(retried), 3) << retried;
  }
  server->Shutdown();
}

}  // namespace
}  // namespace mocap
