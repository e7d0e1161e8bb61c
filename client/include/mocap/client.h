// The mocap C++ client SDK: the one header to include.
//
//   auto client = mocap::client::Client::Connect("127.0.0.1:50051", {.api_key = key});
//   auto result = (*client)->ImportFiles("walks", {"a.bvh", "b.bvh"});
//   auto bvh = (*client)->ExportClip("walks", result->files(0).clip_id());
//
// Payloads are the generated mocap.v1 messages (proto/mocap/v1/*.proto document every field:
// metres, seconds, Y up). Errors are absl::Status with gRPC's codes: UNAUTHENTICATED (no or bad
// key), NOT_FOUND (no such database or clip for this key's tenant), RESOURCE_EXHAUSTED (a server
// limit; the message says which), UNAVAILABLE (no server; calls safe to repeat are retried first:
// reads, exports, ReconstructTrajectory; CreateDatabase, DeleteDatabase and DeleteClip are not,
// since the server may have acted before the connection broke: describe or list to find out), ...
//
// Thread safety: a Client may be shared by threads; each call is independent. Cost: Connect
// makes a channel (no network traffic until the first call); calls reuse it.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "mocap/v1/motion_store.pb.h"
#include "mocap/v1/pose_search.pb.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap::client {

struct ConnectOptions {
  // Tenant API key (from `mocapd tenant add-key`), sent as "authorization: Bearer <key>".
  std::string api_key;
  // TLS: use it, trusting these PEM root certificates (empty: the system's roots).
  bool tls = false;
  std::string tls_root_certs_pem;
  // Deadline of each unary call attempt.
  std::chrono::milliseconds deadline{30000};
  // Calls safe to repeat (reads, ReconstructTrajectory) answered UNAVAILABLE are tried up to this
  // many times in all, waiting retry_backoff, then twice that, and so on. Creates and deletes are
  // sent once.
  int max_attempts = 4;
  std::chrono::milliseconds retry_backoff{100};
  // Largest message accepted from the server.
  int max_receive_message_bytes = 4 << 20;
};

struct ImportOptions {
  // Frame rate for a database the import creates (0: 30 fps).
  double frame_rate = 0.0;
  // Unit of the files ("m", "cm", "mm", "in"); empty: the server detects it.
  std::string source_unit;
  // Files per atomic batch (0: the whole import is one batch).
  int batch_size = 0;
  // Skip bad files (reported per file) instead of failing the import at the first.
  bool keep_going = false;
  // Retarget files of another rig onto the database's rig instead of refusing them.
  bool retarget_other_rigs = false;
  // Bytes per message (the server accepts up to 1 MiB of file data per message).
  std::size_t chunk_bytes = 1 << 20;
};

struct ImportProgress {
  int files_sent = 0;  // files whose every byte has been sent
  int files_total = 0;
  std::int64_t bytes_sent = 0;
  std::int64_t bytes_total = 0;
  std::string current_file;
};
// Called on the importing thread after every message sent.
using ImportProgressCallback = std::function<void(const ImportProgress&)>;

// One live reconstruction (the Reconstruction.Reconstruct stream), from Client::OpenReconstruction.
//
//   auto stream = client->OpenReconstruction(config);          // waits for `started`
//   writer thread:  stream->Write(samples) ... stream->CloseInput();
//   reader thread:  while (auto reply = stream->Read(); reply.ok() && *reply) handle(**reply);
//                   auto summary = stream->Finish();
// Write blocks while the server is behind (backpressure): the server reads the next samples only
// once its replies have been delivered, so replies must be read while writing. Single-threaded
// code may interleave Write and Read itself, or Write everything and then call Finish(on_reply)
// only for short sessions (a few seconds: replies then fit in the transport's buffers; a longer
// session would stall, the server waiting for the client to read and the client for the server).
//
// Thread safety: one thread may Write/CloseInput while another Reads; Cancel from any thread.
class ReconstructionStream {
 public:
  virtual ~ReconstructionStream() = default;
  // The session's skeleton, frame rate and latency (received before Open returned).
  virtual const v1::SessionStarted& started() const = 0;
  // Sends samples in one message. An error means the call has ended: Finish tells why.
  virtual absl::Status Write(const std::vector<v1::WristSample>& samples) = 0;
  // Ends the input (the server then emits the remaining frames and the summary).
  virtual absl::Status CloseInput() = 0;
  // The next reply (frames or a rejected sample); nullopt once the summary has arrived or the
  // call ended (then Finish returns the summary or the error).
  virtual absl::StatusOr<std::optional<v1::ReconstructResponse>> Read() = 0;
  // Closes the input if still open, reads the remaining replies (each given to `on_reply` when
  // set) and returns the summary, or the call's error.
  virtual absl::StatusOr<v1::SessionSummary> Finish(
      const std::function<void(const v1::ReconstructResponse&)>& on_reply = nullptr) = 0;
  // Abandons the session (the server drops it); Finish then returns CANCELLED.
  virtual void Cancel() = 0;
};

// A BVH query for FindSimilarPoses: the file's text and name (NotFound when it cannot be read).
// Set first_frame, last_frame and frame_step on the result to search part of it.
absl::StatusOr<v1::BvhQuery> ReadBvhQuery(const std::filesystem::path& path);

class Client {
 public:
  // InvalidArgument for an empty address.
  static absl::StatusOr<std::unique_ptr<Client>> Connect(const std::string& address,
                                                         const ConnectOptions& options = {});
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Databases of this key's tenant.
  absl::StatusOr<v1::DatabaseSummary> CreateDatabase(const std::string& name, double frame_rate = 0.0);
  absl::StatusOr<std::vector<v1::DatabaseSummary>> ListDatabases();
  absl::StatusOr<v1::DatabaseInfo> DescribeDatabase(const std::string& name);
  absl::Status DeleteDatabase(const std::string& name);

  // Streams BVH files to the server (one ImportBvh call, not retried). OK: every file has a
  // result in the response (imported, duplicate, or failed with keep_going). An error status
  // names the bad file and line; nothing of its batch was stored.
  absl::StatusOr<v1::ImportBvhResponse> ImportFiles(const std::string& database,
                                                    const std::vector<std::filesystem::path>& files,
                                                    const ImportOptions& options = {},
                                                    const ImportProgressCallback& progress = nullptr);

  absl::StatusOr<std::vector<v1::Clip>> ListClips(const std::string& database);
  // The clip as BVH text (the rig's own unit and axes, as imported; the database's frame rate).
  absl::StatusOr<std::string> ExportClip(const std::string& database, std::int64_t clip_id);
  absl::Status DeleteClip(const std::string& database, std::int64_t clip_id);

  // Starts a live reconstruction session: sends `config` and waits for the server's `started`
  // reply (the first session on a database after an import may wait while its indices are built).
  // Not retried. Errors as the call's status: NOT_FOUND, INVALID_ARGUMENT, RESOURCE_EXHAUSTED...
  absl::StatusOr<std::unique_ptr<ReconstructionStream>> OpenReconstruction(const v1::SessionConfig& config);
  // A whole trajectory in one unary call (retried on UNAVAILABLE; deadline: `deadline`, since
  // index building and long trajectories take longer than ConnectOptions.deadline).
  absl::StatusOr<v1::ReconstructTrajectoryResponse> ReconstructTrajectory(
      const v1::SessionConfig& config, const std::vector<v1::WristSample>& samples,
      std::chrono::milliseconds deadline = std::chrono::minutes(10));

  // Similar poses across skeletons (PoseSearch.FindSimilarPoses): per query frame, the most
  // similar poses in the named databases. Retried on UNAVAILABLE; deadline `deadline`, since the
  // first search on a database after a start or an import waits for its pose index to be built.
  // Long query clips: StreamSimilarPoses (this call's limits: pose_search.proto).
  absl::StatusOr<v1::FindSimilarPosesResponse> FindSimilarPoses(
      const v1::FindSimilarPosesRequest& request, std::chrono::milliseconds deadline = std::chrono::minutes(10));
  // The same search answered in parts as query frames are searched (PoseSearch.StreamSimilarPoses):
  // `on_part` gets each part in query-frame order on the calling thread; returning false cancels
  // the call (then CANCELLED). Not retried; no deadline unless `deadline` > 0.
  absl::Status StreamSimilarPoses(const v1::FindSimilarPosesRequest& request,
                                  const std::function<bool(const v1::FindSimilarPosesResponse&)>& on_part,
                                  std::chrono::milliseconds deadline = std::chrono::milliseconds(0));

  // Server counters in the Prometheus text format.
  absl::StatusOr<std::string> GetMetrics();

  struct Impl;  // the SDK's internals (client/src/client_impl.h)

 private:
  explicit Client(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace mocap::client
