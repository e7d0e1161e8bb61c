#include "server/import_reactor.h"

#include <algorithm>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "server/proto_convert.h"

namespace mocap {

ImportReactor::ImportReactor(ServiceContext& service, grpc::CallbackServerContext* context,
                             v1::ImportBvhResponse* response)
    : call_(service, context, "ImportBvh"), response_(response) {
  service.workers.Post([this] { Begin(); });
}

void ImportReactor::Begin() {
  MutexLock lock(&mutex_);
  if (absl::Status status = call_.Begin(); !status.ok()) return Complete(status);
  if (absl::Status status = call_.RequireWritableStore(); !status.ok()) return Complete(status);
  StartRead(&request_);
}

void ImportReactor::OnReadDone(bool ok) {
  MutexLock lock(&mutex_);
  if (!ok) {
    // The client half-closed without `end`, went away, or the server is stopping: nothing of the
    // pending batch is stored (the writer's buffered clips are dropped).
    return Complete(call_.context()->IsCancelled()
                        ? absl::CancelledError("import cancelled; nothing from the pending batch was stored")
                        : absl::InvalidArgumentError(
                              "the import stream ended without its end message; nothing from the pending batch was "
                              "stored"));
  }
  call_.service().workers.Post([this] { Handle(); });
}

void ImportReactor::Handle() {
  MutexLock lock(&mutex_);
  absl::Status status;
  try {
    status = HandleMessage();
  } catch (const std::exception& error) {
    status = absl::InternalError(StrCat("import: ", error.what()));
  }
  if (!status.ok() || ended_) return Complete(status);
  StartRead(&request_);
}

absl::Status ImportReactor::HandleMessage() {
  switch (request_.message_case()) {
    case v1::ImportBvhRequest::kStart:
      return HandleStart(request_.start());
    case v1::ImportBvhRequest::kChunk:
      return HandleChunk(request_.chunk());
    case v1::ImportBvhRequest::kEnd:
      if (!writer_) return absl::InvalidArgumentError("the import stream must begin with a start message");
      if (!file_name_.empty()) {
        return absl::InvalidArgumentError(StrCat(file_name_, ": the stream ended before the file's last chunk"));
      }
      MOCAP_RETURN_IF_ERROR(writer_->Finish());
      ToProto(database_, writer_->totals(), response_);
      call_.metrics().FilesImported(writer_->totals().imported, writer_->totals().frames);
      ended_ = true;
      return absl::OkStatus();
    default:
      return absl::InvalidArgumentError("empty import message");
  }
}

absl::Status ImportReactor::HandleStart(const v1::ImportStart& start) {
  if (writer_) return absl::InvalidArgumentError("the import stream has a second start message");
  if (start.database().empty()) return absl::InvalidArgumentError("name the database to import into");
  if (start.batch_size() < 0) return absl::InvalidArgumentError("start.batch_size must not be negative");
  if (start.frame_rate() != 0) {  // 0: the default (30 fps), or the existing database's rate
    if (absl::Status rate = CheckDatabaseFrameRate(start.frame_rate()); !rate.ok()) {
      return absl::InvalidArgumentError(StrCat("start.frame_rate: ", rate.message()));
    }
  }
  std::optional<LengthUnit> unit;
  if (!start.source_unit().empty()) {
    unit = ParseUnit(start.source_unit());
    if (!unit)
      return absl::InvalidArgumentError(StrCat("unknown unit '", start.source_unit(), "' (m, cm, mm, in or cmu)"));
  }
  database_ = start.database();
  MOCAP_ASSIGN_OR_RETURN(
      writer_,
      ImportWriter::Start(call_.store(), ImportTarget{.tenant = call_.tenant().id,
                                                      .database = start.database(),
                                                      .frame_rate = start.frame_rate() == 0 ? 30.0 : start.frame_rate(),
                                                      .unit = unit,
                                                      .batch_size = start.batch_size(),
                                                      .keep_going = start.keep_going(),
                                                      .retarget_other_rigs = start.retarget_other_rigs(),
                                                      .buffer_batch = true,
                                                      .max_pending_frames = call_.service().limits.max_batch_frames}));
  return absl::OkStatus();
}

absl::Status ImportReactor::HandleChunk(const v1::FileChunk& chunk) {
  if (!writer_) return absl::InvalidArgumentError("the import stream must begin with a start message");
  const std::string& name = chunk.file_name();
  if (name.empty() || name.size() > kMaxFileNameBytes) {
    return absl::InvalidArgumentError(
        StrCat("chunk.file_name must have 1 to ", kMaxFileNameBytes, " bytes, not ", name.size()));
  }
  if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos ||
      std::any_of(name.begin(), name.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; })) {
    return absl::InvalidArgumentError("chunk.file_name must be a plain file name: no folders, no control characters");
  }
  if (file_name_.empty()) {
    file_name_ = name;
  } else if (name != file_name_) {
    return absl::InvalidArgumentError(StrCat(name, ": chunk arrived before the last chunk of ", file_name_));
  }
  if (chunk.data().size() > kMaxChunkBytes) {
    return absl::InvalidArgumentError(
        StrCat("chunk.data has ", chunk.data().size(), " bytes; a chunk carries at most ", kMaxChunkBytes, " (1 MiB)"));
  }
  const ServerLimits& limits = call_.service().limits;
  if (static_cast<std::int64_t>(file_bytes_.size() + chunk.data().size()) > limits.max_file_bytes) {
    call_.metrics().Rejected("file_bytes");
    return absl::ResourceExhaustedError(
        StrCat(name, ": file is larger than the server's limit of ", limits.max_file_bytes, " bytes"));
  }
  file_bytes_ += chunk.data();
  call_.metrics().BytesReceived(static_cast<std::int64_t>(chunk.data().size()));
  if (!chunk.end_of_file()) return absl::OkStatus();
  absl::Status status = ImportFile();
  file_name_.clear();
  file_bytes_.clear();
  file_bytes_.shrink_to_fit();
  return status;
}

absl::Status ImportReactor::ImportFile() {
  PreparedFile prepared;
  if (writer_->rig() == nullptr) {
    // The first good file fixes the rig of a new (or empty) database.
    BvhClip clip;
    prepared = PrepareBvhBytes(file_bytes_, file_name_, nullptr, writer_->preprocess(), &clip);
    if (prepared.status.ok()) prepared.status = writer_->SetRigFrom(clip, file_name_);
  }
  if (prepared.status.ok()) prepared = PrepareBvhBytes(file_bytes_, file_name_, writer_->rig(), writer_->preprocess());
  ClipLabels labels = prepared.status.ok() ? ParseClipLabels(file_name_) : ClipLabels{};
  return writer_->Add(file_name_, std::move(prepared), std::move(labels));
}

void ImportReactor::Complete(const absl::Status& status) {
  writer_.reset();  // drops (rolls back) whatever was not committed
  Finish(call_.End(status));
}

}  // namespace mocap
