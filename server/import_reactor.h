// The ImportBvh call: reads one message at a time; each finished file is parsed and prepared on
// a worker before the next read (backpressure), and clips are kept in memory until their batch
// commits in one short transaction (server/import_writer.h), so a client that goes away or a
// stream without its `end` message leaves the store unchanged.
#pragma once

#include <memory>
#include <string>

#include "mocap/v1/motion_store.grpc.pb.h"
#include "server/owned_reactor.h"
#include "server/service_context.h"
#include "storage/import_writer.h"

namespace mocap {

class ImportReactor : public OwnedReactor<grpc::ServerReadReactor<v1::ImportBvhRequest>> {
 public:
  ImportReactor(ServiceContext& service, grpc::CallbackServerContext* context, v1::ImportBvhResponse* response);
  void OnReadDone(bool ok) override;

 private:
  static constexpr size_t kMaxFileNameBytes = 255;
  static constexpr size_t kMaxChunkBytes = 1 << 20;  // the API's promise (motion_store.proto)
  void Begin();
  // Handles request_ on a worker; then reads the next message or finishes.
  void Handle();
  absl::Status HandleMessage();
  absl::Status HandleStart(const v1::ImportStart& start);
  absl::Status HandleChunk(const v1::FileChunk& chunk);
  absl::Status ImportFile();
  void Complete(const absl::Status& status);

  CallScope call_;
  v1::ImportBvhResponse* response_;
  v1::ImportBvhRequest request_;
  std::unique_ptr<ImportWriter> writer_;
  std::string database_;
  std::string file_name_;  // file being received; empty between files
  std::string file_bytes_;
  bool ended_ = false;  // `end` received and committed
};

}  // namespace mocap
