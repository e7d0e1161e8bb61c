#include "server/motion_store_service.h"

#include <new>

#include <spdlog/spdlog.h>

#include "motion/bvh/bvh_writer.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/local_motion.h"
#include "server/import_reactor.h"
#include "server/owned_reactor.h"
#include "server/proto_convert.h"

namespace mocap {
namespace {

absl::Status CheckName(const std::string& name) {
  if (name.empty()) return absl::InvalidArgumentError("name the database");
  return absl::OkStatus();
}

// The tenant's database, or NotFound (also for another tenant's: existence is not revealed).
absl::StatusOr<DatabaseSummary> TenantDatabase(CallScope& call, const std::string& name) {
  MOCAP_RETURN_IF_ERROR(CheckName(name));
  return call.store().FindDatabase(name, call.tenant().id);
}

// ExportClip: formats the clip on a worker, then writes it in chunks, one write in flight.
class ExportReactor : public OwnedReactor<grpc::ServerWriteReactor<v1::ExportClipResponse>> {
 public:
  static constexpr size_t kChunkBytes = 64 << 10;

  ExportReactor(ServiceContext& service, grpc::CallbackServerContext* context, const v1::ExportClipRequest& request)
      : call_(service, context, "ExportClip"), request_(request) {
    service.workers.Post([this] { Load(); });
  }
  void OnWriteDone(bool ok) override {
    MutexLock lock(&mutex_);
    if (!ok) return Complete(absl::CancelledError("the client stopped reading"));
    WriteNext();
  }

 private:
  void Load() {
    MutexLock lock(&mutex_);
    absl::Status status = call_.Begin();
    if (status.ok()) {
      try {
        status = Format();
      } catch (const std::exception& error) {
        status = absl::InternalError(StrCat("exporting: ", error.what()));
      }
    }
    if (!status.ok()) return Complete(status);
    WriteNext();
  }
  absl::Status Format() {
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary database, TenantDatabase(call_, request_.database()));
    MOCAP_RETURN_IF_ERROR(call_.store().FindClip(database.ref, request_.clip_id()).status());
    MOCAP_ASSIGN_OR_RETURN(RigModel rig, call_.store().LoadRig(database.ref));
    MOCAP_ASSIGN_OR_RETURN(StoredClip clip, call_.store().LoadClip(database.ref, request_.clip_id(), rig));
    // In the rig's own unit and axes: the exported file reads like the file imported.
    clip.motion.frame_time = 1.0 / database.frame_rate;
    text_ = FormatBvh(ToFileConventions(clip.skeleton, clip.motion, rig));
    call_.metrics().BytesSent(static_cast<std::int64_t>(text_.size()));
    return absl::OkStatus();
  }
  void WriteNext() {
    if (offset_ >= text_.size()) return Complete(absl::OkStatus());
    const size_t size = std::min(kChunkBytes, text_.size() - offset_);
    chunk_.set_data(text_.substr(offset_, size));
    offset_ += size;
    StartWrite(&chunk_);
  }
  void Complete(const absl::Status& status) { Finish(call_.End(status)); }

  CallScope call_;
  const v1::ExportClipRequest request_;
  std::string text_;
  size_t offset_ = 0;
  v1::ExportClipResponse chunk_;
};

}  // namespace

grpc::ServerUnaryReactor* RunUnary(ServiceContext& service, grpc::CallbackServerContext* context, const char* method,
                                   std::function<absl::Status(CallScope&)> work) {
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  service.workers.Post([&service, context, reactor, method, work = std::move(work)] {
    CallScope call(service, context, method);
    // Every call is answered, whatever its work throws (issue #24: a dropped exception left a call
    // unanswered): authentication inside the try too, and the last resort for what is no exception.
    absl::Status status;
    try {
      status = call.Begin();
      if (status.ok()) status = work(call);
    } catch (const std::bad_alloc&) {
      status = absl::ResourceExhaustedError(StrCat(method, ": out of memory"));
    } catch (const std::exception& error) {
      status = absl::InternalError(StrCat(method, ": ", error.what()));
    } catch (...) {
      status = absl::InternalError(StrCat(method, ": an unknown error"));
    }
    reactor->Finish(call.End(status));
  });
  return reactor;
}

grpc::ServerUnaryReactor* MotionStoreService::CreateDatabase(grpc::CallbackServerContext* context,
                                                             const v1::CreateDatabaseRequest* request,
                                                             v1::CreateDatabaseResponse* response) {
  return RunUnary(service_, context, "CreateDatabase", [request, response](CallScope& call) -> absl::Status {
    MOCAP_RETURN_IF_ERROR(call.RequireWritableStore());
    MOCAP_RETURN_IF_ERROR(CheckName(request->name()));
    const double frame_rate = request->frame_rate() == 0 ? 30.0 : request->frame_rate();
    if (absl::Status rate = CheckDatabaseFrameRate(frame_rate); !rate.ok()) {
      return absl::InvalidArgumentError(StrCat("frame_rate: ", rate.message()));
    }
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary created,
                           call.store().CreateEmptyDatabase(request->name(), frame_rate, call.tenant().id));
    ToProto(created, response->mutable_database());
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* MotionStoreService::ListDatabases(grpc::CallbackServerContext* context,
                                                            const v1::ListDatabasesRequest*,
                                                            v1::ListDatabasesResponse* response) {
  return RunUnary(service_, context, "ListDatabases", [response](CallScope& call) -> absl::Status {
    MOCAP_ASSIGN_OR_RETURN(std::vector<DatabaseSummary> databases, call.store().ListDatabases(call.tenant().id));
    for (const DatabaseSummary& database : databases) ToProto(database, response->add_databases());
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* MotionStoreService::DescribeDatabase(grpc::CallbackServerContext* context,
                                                               const v1::DescribeDatabaseRequest* request,
                                                               v1::DescribeDatabaseResponse* response) {
  return RunUnary(service_, context, "DescribeDatabase", [request, response](CallScope& call) -> absl::Status {
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary database, TenantDatabase(call, request->name()));
    v1::DatabaseInfo* info = response->mutable_info();
    info->set_name(database.ref.name());
    info->set_frame_rate(database.frame_rate);
    info->set_clip_count(database.num_clips);
    info->set_frame_count(database.num_frames);
    if (database.has_rig) {
      info->set_source_unit(std::string(UnitName(database.unit)));
      MOCAP_ASSIGN_OR_RETURN(RigModel rig, call.store().LoadRig(database.ref));
      ToProto(rig, info->mutable_skeleton());
    }
    return absl::OkStatus();
  });
}

grpc::ServerUnaryReactor* MotionStoreService::DeleteDatabase(grpc::CallbackServerContext* context,
                                                             const v1::DeleteDatabaseRequest* request,
                                                             v1::DeleteDatabaseResponse*) {
  return RunUnary(service_, context, "DeleteDatabase", [request](CallScope& call) -> absl::Status {
    MOCAP_RETURN_IF_ERROR(call.RequireWritableStore());
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary database, TenantDatabase(call, request->name()));
    return call.store().DeleteDatabase(database.ref);
  });
}

grpc::ServerReadReactor<v1::ImportBvhRequest>* MotionStoreService::ImportBvh(grpc::CallbackServerContext* context,
                                                                             v1::ImportBvhResponse* response) {
  return new ImportReactor(service_, context, response);
}

grpc::ServerUnaryReactor* MotionStoreService::ListClips(grpc::CallbackServerContext* context,
                                                        const v1::ListClipsRequest* request,
                                                        v1::ListClipsResponse* response) {
  return RunUnary(service_, context, "ListClips", [request, response](CallScope& call) -> absl::Status {
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary database, TenantDatabase(call, request->database()));
    MOCAP_ASSIGN_OR_RETURN(std::vector<ClipSummary> clips, call.store().ListClips(database.ref));
    for (const ClipSummary& clip : clips) ToProto(clip, response->add_clips());
    return absl::OkStatus();
  });
}

grpc::ServerWriteReactor<v1::ExportClipResponse>* MotionStoreService::ExportClip(grpc::CallbackServerContext* context,
                                                                                 const v1::ExportClipRequest* request) {
  return new ExportReactor(service_, context, *request);
}

grpc::ServerUnaryReactor* MotionStoreService::DeleteClip(grpc::CallbackServerContext* context,
                                                         const v1::DeleteClipRequest* request,
                                                         v1::DeleteClipResponse*) {
  return RunUnary(service_, context, "DeleteClip", [request](CallScope& call) -> absl::Status {
    MOCAP_RETURN_IF_ERROR(call.RequireWritableStore());
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary database, TenantDatabase(call, request->database()));
    return call.store().DeleteClip(database.ref, request->clip_id());
  });
}

}  // namespace mocap
