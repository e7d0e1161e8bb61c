// Issue #24's property test: random operation sequences of two tenants on one server never let
// either see, change or break the other's data. An in-process MocapServer (what `mocapd serve`
// runs) over a real SQLite store on loopback, driven through the C++ SDK, plus the raw ImportBvh
// stub for imports held open across other operations.
//
// Both tenants draw database names from one small pool, so every name is used by both at once
// (the hazard of issue #24 finding 1: an import outliving its database, a reused id, an index
// answering with the other's names). Every clip file name, and the root joint of one of the two
// rigs, carries its tenant's name, so a leak shows in any string of any answer. A model of what
// each tenant owns (databases -> rig, clips) predicts every answer; after every step both
// tenants' listings must equal their models.
//
// Size: MOCAP_TWO_TENANT_SEQUENCES sequences (default 12, ~1 s) of MOCAP_TWO_TENANT_STEPS
// operations (default 14) from seed MOCAP_TWO_TENANT_SEED (default 24; sequence i uses seed + i).
// The issue's target, 10,000 sequences (~10 min on 2 cores):
//   MOCAP_TWO_TENANT_SEQUENCES=10000 build/tests/mocap_server_tests --gtest_filter='TwoTenant*'
// All sequences share one server and store (a server per sequence would cost more than the
// sequence): between sequences every database is deleted and both tenants must list nothing. The
// deleted clips' ids pile up across sequences, and are probed as stale ids. A failure prints the
// sequence's seed and its operation trace; MOCAP_TWO_TENANT_SEED=<seed>
// MOCAP_TWO_TENANT_SEQUENCES=1 replays it (on a fresh store: other ids, the same operations).
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "client/wrist_input/wrist_source.h"
#include "mocap/client.h"
#include "mocap/v1/motion_store.grpc.pb.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "server/grpc_server.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace two_tenant_property_test {
namespace {

namespace fs = std::filesystem;
using client::Client;
using Code = absl::StatusCode;

// The tenants' names double as their markers: no answer to one may contain the other's.
constexpr std::array<const char*, 2> kTenants = {"alphacorp", "bravocorp"};
// Shared by both tenants.
constexpr std::array<const char*, 3> kDatabaseNames = {"walks", "runs", "shared"};
// Clip contents: content c is a walk of kFirstFrames + 2c frames on rig c % 2. Rig 0 is the same
// for both tenants (its files are byte-identical too: duplicates must still be per database);
// rig 1's root joint is named after the tenant, so the two tenants' rig 1 differ.
constexpr int kContents = 6;
constexpr int kFirstFrames = 20;
constexpr std::array<int, 2> kRigJoints = {21, 22};

int EnvInt(const char* name, int fallback) {
  const char* text = std::getenv(name);
  return text != nullptr && *text != '\0' ? std::atoi(text) : fallback;
}

int RigOf(int content) { return content % 2; }
int FramesOf(int content) { return kFirstFrames + 2 * content; }
std::string ClipName(int tenant, int content) {
  return std::string(kTenants[tenant]) + "_take" + std::to_string(content) + ".bvh";
}

BvhClip ContentClip(int tenant, int content) {
  const int rig = RigOf(content);
  BvhClip clip = testing::MakeWalkingClip({.extra_root = rig == 1}, FramesOf(content));
  if (rig == 1) {
    std::vector<Joint> joints = clip.skeleton.joints();
    joints[0].name = std::string(kTenants[tenant]) + "_Root";
    clip.skeleton = Skeleton(std::move(joints));
  }
  return clip;
}

// What a tenant owns, as the server should have it.
struct ModelClip {
  std::string name;
  int content = 0;
};
struct ModelDatabase {
  int instance = 0;        // which creation of the name (a deleted and re-created one is another)
  std::optional<int> rig;  // fixed by the first import
  std::map<std::int64_t, ModelClip> clips;
  std::int64_t frames() const {
    std::int64_t total = 0;
    for (const auto& [id, clip] : clips) total += FramesOf(clip.content);
    return total;
  }
  std::optional<std::int64_t> ClipWithContent(int content) const {
    for (const auto& [id, clip] : clips)
      if (clip.content == content) return id;
    return std::nullopt;
  }
};
using TenantModel = std::map<std::string, ModelDatabase>;

// An ImportBvh call on the raw stub with its start and one whole file sent, held open while other
// operations run; what the server looked up when it read the start is recorded.
struct OpenImport {
  std::string database;
  int content = 0;
  std::optional<int> instance;  // the tenant's database of that name at the start (none: it creates one)
  std::optional<int> rig;       // that database's rig then
  grpc::ClientContext context;
  v1::ImportBvhResponse response;
  std::unique_ptr<grpc::ClientWriter<v1::ImportBvhRequest>> writer;
};

class TwoTenantPropertyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path store = dir_ / "var" / "mocap.db";
    {
      auto opened = MotionStore::Open(store);
      ASSERT_TRUE(opened.ok()) << opened.status();
      TenantDirectory tenants(**opened);
      for (int t = 0; t < 2; ++t) {
        auto tenant = tenants.CreateTenant(kTenants[t]);
        ASSERT_TRUE(tenant.ok()) << tenant.status();
        auto key = tenants.AddKey(tenant->id);
        ASSERT_TRUE(key.ok()) << key.status();
        keys_[t] = key->key;
      }
    }
    ServeOptions options;
    options.store = store;
    options.listen = "127.0.0.1:0";
    options.workers = 2;
    options.reconstruction.compute_threads = 2;
    options.drain_timeout = std::chrono::seconds(30);
    auto server = MocapServer::Start(options);
    ASSERT_TRUE(server.ok()) << server.status();
    server_ = *std::move(server);
    const std::string address = "127.0.0.1:" + std::to_string(server_->port());
    for (int t = 0; t < 2; ++t) {
      auto client = Client::Connect(address, {.api_key = keys_[t]});
      ASSERT_TRUE(client.ok()) << client.status();
      clients_[t] = *std::move(client);
    }
    stub_ = v1::MotionStore::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
    WriteFiles();
  }
  void TearDown() override {
    for (auto& open : open_) {  // left open by a failed sequence
      if (!open) continue;
      open->context.TryCancel();
      open->writer->Finish();
    }
    if (server_) server_->Shutdown();
  }

  // Each tenant's clip files, the search query (a walk on neither database rig's exact length)
  // and the session's wrist samples.
  void WriteFiles() {
    fs::create_directories(dir_ / "clips");
    for (int t = 0; t < 2; ++t) {
      for (int c = 0; c < kContents; ++c) {
        const fs::path path = dir_ / "clips" / ClipName(t, c);
        ASSERT_TRUE(WriteBvhFile(ContentClip(t, c), path).ok());
        files_[t][c] = path;
        std::ifstream in(path);
        bytes_[t][c] = std::string(std::istreambuf_iterator<char>(in), {});
      }
    }
    const fs::path query = dir_ / "clips" / "query.bvh";
    ASSERT_TRUE(WriteBvhFile(testing::MakeWalkingClip({}, 31), query).ok());
    auto read = client::ReadBvhQuery(query);
    ASSERT_TRUE(read.ok()) << read.status();
    query_ = *std::move(read);
    query_.set_frame_step(15);  // query frames 0, 15, 30
    auto samples = WristsFromBvh(query, 0.0, 1);
    ASSERT_TRUE(samples.ok()) << samples.status();
    samples_.assign(samples->begin(), samples->begin() + 6);
  }

  // --- running sequences ---

  void RunSequence(std::uint64_t seed, int steps);
  void Step();
  void ResetBetweenSequences();

  // --- the operations (each records its line in the trace and checks its own answer) ---

  void Create(int t, const std::string& name);
  void Delete(int t, const std::string& name);
  void Import(int t, const std::string& name, const std::vector<int>& contents);
  void Describe(int t, const std::string& name);
  // Every clip tenant `t`'s model holds: (database name, clip id).
  std::vector<std::pair<std::string, std::int64_t>> ClipsOf(int t) const {
    std::vector<std::pair<std::string, std::int64_t>> clips;
    for (const auto& [name, database] : model_[t])
      for (const auto& [id, clip] : database.clips) clips.emplace_back(name, id);
    return clips;
  }
  void ExportOwn(int t);
  void DeleteOwnClip(int t);
  void ProbeOthersClip(int t);
  void Search(int t, const std::vector<std::string>& names);
  void Session(int t, const std::string& name);
  void OpenImportCall(int t, const std::string& name, int content);
  void FinishImport(int t);
  void AbandonImport(int t);
  void ReuseRace(int t);

  // --- checks ---

  // Both tenants' listings (databases and every database's clips) equal their models.
  void CheckListings();
  void CheckTenantListings(int t);
  // Fails when `text` holds the other tenant's marker.
  void Scan(int t, const std::string& text, const std::string& where);
  void ScanStatus(int t, const absl::Status& status, const std::string& where) {
    Scan(t, std::string(status.message()), where);
  }
  void ExpectCode(const absl::Status& status, Code expected, const std::string& what) {
    if (status.code() != expected) {
      Fail(what + ": expected " + absl::StatusCodeToString(expected) + ", got " + status.ToString());
    }
  }
  void Fail(const std::string& message) {
    if (failure_.empty()) failure_ = message;
  }
  void Trace(const std::string& line) {
    trace_.push_back(line);
    if (!line.starts_with("--")) ++operations_;
  }
  // A clip id answered as new must never have been answered before (ids are never reused).
  void Issued(std::int64_t id) {
    if (!issued_.insert(id).second) Fail("clip id " + std::to_string(id) + " was answered before");
  }
  void Retire(const ModelDatabase& database) {
    for (const auto& [id, clip] : database.clips) retired_.push_back(id);
  }
  std::int64_t ReceivedBytes(int t);  // tenant t's own byte counter (GetMetrics)

  std::string Other(int t) const { return kTenants[1 - t]; }
  int Draw(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  std::string DrawName() { return kDatabaseNames[Draw(kDatabaseNames.size())]; }
  // Mostly a name the tenant has with clips (searches and sessions that get to work), else any.
  std::string DrawOwnName(int t) {
    std::vector<std::string> names;
    for (const auto& [name, database] : model_[t])
      if (!database.clips.empty()) names.push_back(name);
    return names.empty() || Draw(6) == 0 ? DrawName() : names[Draw(names.size())];
  }
  // Mostly a content of the database's rig (an import that is stored), else any (one refused).
  int DrawContent(int t, const std::string& name) {
    const auto found = model_[t].find(name);
    if (found == model_[t].end() || !found->second.rig || Draw(6) == 0) return Draw(kContents);
    return *found->second.rig + 2 * Draw(kContents / 2);
  }

  testing::ScopedTempDir temp_;
  const fs::path& dir_ = temp_.path();
  std::array<std::string, 2> keys_;
  std::unique_ptr<MocapServer> server_;
  std::array<std::unique_ptr<Client>, 2> clients_;
  std::unique_ptr<v1::MotionStore::Stub> stub_;
  std::array<std::array<fs::path, kContents>, 2> files_;
  std::array<std::array<std::string, kContents>, 2> bytes_;
  v1::BvhQuery query_;
  std::vector<v1::WristSample> samples_;

  std::mt19937_64 rng_;
  std::array<TenantModel, 2> model_;
  std::array<std::unique_ptr<OpenImport>, 2> open_;
  int next_instance_ = 1;
  std::set<std::int64_t> issued_;      // every clip id ever answered as new, of both tenants
  std::vector<std::int64_t> retired_;  // those deleted since (a database or the clip)
  std::vector<std::string> trace_;
  int operations_ = 0;
  std::string failure_;
  std::map<std::string, int> outcomes_;  // what the sequences exercised, for the summary
};

void TwoTenantPropertyTest::RunSequence(std::uint64_t seed, int steps) {
  rng_.seed(seed);
  trace_.clear();
  for (int step = 0; step < steps && failure_.empty(); ++step) {
    Step();
    if (failure_.empty()) CheckListings();
  }
  if (failure_.empty()) ResetBetweenSequences();
}

// One operation drawn at random for a random tenant. An operation that does not apply now (no
// import open, no clip to export) draws again.
void TwoTenantPropertyTest::Step() {
  while (true) {
    const int t = Draw(2);
    const int op = Draw(100);
    if (op < 13) return Create(t, DrawName());
    if (op < 20) return Delete(t, DrawName());
    if (op < 36) {
      const std::string name = DrawName();
      std::vector<int> contents = {DrawContent(t, name)};
      if (Draw(3) == 0) contents.push_back(DrawContent(t, name));
      return Import(t, name, contents);
    }
    if (op < 40) return Describe(t, DrawName());
    if (op < 45) return ExportOwn(t);
    if (op < 49) return DeleteOwnClip(t);
    if (op < 57) return ProbeOthersClip(t);
    if (op < 65) {
      std::vector<std::string> names = {DrawOwnName(t)};
      if (Draw(3) == 0) {
        const std::string second = DrawOwnName(t);
        if (second != names[0]) names.push_back(second);
      }
      return Search(t, names);
    }
    if (op < 70) return Session(t, DrawOwnName(t));
    if (op < 79) {
      if (open_[t]) continue;
      const std::string name = DrawName();
      return OpenImportCall(t, name, DrawContent(t, name));
    }
    if (op < 91) {
      if (!open_[t]) continue;
      return FinishImport(t);
    }
    if (op < 94) {
      if (!open_[t]) continue;
      return AbandonImport(t);
    }
    if (open_[t]) continue;
    return ReuseRace(t);
  }
}

// Ends the open imports and deletes every database, so the next sequence starts from nothing
// (its model is empty): both tenants must then list no database.
void TwoTenantPropertyTest::ResetBetweenSequences() {
  for (int t = 0; t < 2; ++t) {
    if (open_[t]) AbandonImport(t);
    auto listed = clients_[t]->ListDatabases();
    if (!listed.ok()) return Fail("reset: ListDatabases: " + listed.status().ToString());
    for (const v1::DatabaseSummary& database : *listed) {
      if (absl::Status deleted = clients_[t]->DeleteDatabase(database.name()); !deleted.ok()) {
        return Fail("reset: DeleteDatabase " + database.name() + ": " + deleted.ToString());
      }
    }
    for (const auto& [name, database] : model_[t]) Retire(database);
    model_[t].clear();
  }
  CheckListings();
}

// --- operations ---

void TwoTenantPropertyTest::Create(int t, const std::string& name) {
  auto created = clients_[t]->CreateDatabase(name);
  const bool exists = model_[t].contains(name);
  Trace(std::string(kTenants[t]) + " CreateDatabase " + name + " -> " + created.status().ToString());
  if (exists) return ExpectCode(created.status(), Code::kAlreadyExists, "CreateDatabase of an existing name");
  if (!created.ok()) return Fail("CreateDatabase: " + created.status().ToString());
  Scan(t, created->ShortDebugString(), "CreateDatabase");
  if (created->name() != name || created->clip_count() != 0 || created->joint_count() != 0) {
    return Fail("CreateDatabase answered " + created->ShortDebugString());
  }
  model_[t][name] = ModelDatabase{.instance = next_instance_++};
  ++outcomes_["create"];
}

void TwoTenantPropertyTest::Delete(int t, const std::string& name) {
  const absl::Status deleted = clients_[t]->DeleteDatabase(name);
  Trace(std::string(kTenants[t]) + " DeleteDatabase " + name + " -> " + deleted.ToString());
  ScanStatus(t, deleted, "DeleteDatabase");
  if (!model_[t].contains(name)) return ExpectCode(deleted, Code::kNotFound, "DeleteDatabase of a name it lacks");
  ExpectCode(deleted, Code::kOk, "DeleteDatabase");
  Retire(model_[t][name]);
  model_[t].erase(name);
  ++outcomes_["delete"];
}

void TwoTenantPropertyTest::Import(int t, const std::string& name, const std::vector<int>& contents) {
  std::vector<fs::path> files;
  std::string listed;
  for (int c : contents) {
    files.push_back(files_[t][c]);
    listed += " " + std::to_string(c);
  }
  auto imported = clients_[t]->ImportFiles(name, files);
  Trace(std::string(kTenants[t]) + " ImportFiles " + name + " contents" + listed + " -> " +
        (imported.ok() ? imported->ShortDebugString() : imported.status().ToString()));

  // The prediction: the first file fixes a new database's rig; a file of another rig refuses
  // the whole call; content the database (or this call) has already is a duplicate.
  const auto existing = model_[t].find(name);
  ModelDatabase next = existing != model_[t].end() ? existing->second : ModelDatabase{.instance = next_instance_};
  std::set<int> in_call;
  for (int c : contents) {
    if (!next.rig) next.rig = RigOf(c);
    if (*next.rig != RigOf(c)) {
      ScanStatus(t, imported.status(), "ImportFiles");
      ++outcomes_["import refused: other rig"];
      return ExpectCode(imported.status(), Code::kFailedPrecondition, "ImportFiles of another rig");
    }
  }
  if (!imported.ok()) return Fail("ImportFiles: " + imported.status().ToString());
  Scan(t, imported->ShortDebugString(), "ImportFiles");
  if (imported->created_database() != (existing == model_[t].end()) ||
      imported->files_size() != static_cast<int>(contents.size())) {
    return Fail("ImportFiles answered " + imported->ShortDebugString());
  }
  for (size_t i = 0; i < contents.size(); ++i) {
    const v1::FileResult& result = imported->files(static_cast<int>(i));
    const int c = contents[i];
    if (in_call.contains(c)) {
      if (result.outcome() != v1::FileResult::OUTCOME_DUPLICATE || result.clip_id() != 0) {
        return Fail("a repeated file of the call: " + result.ShortDebugString());
      }
    } else if (auto id = next.ClipWithContent(c)) {
      if (result.outcome() != v1::FileResult::OUTCOME_DUPLICATE || result.clip_id() != *id) {
        return Fail("a duplicate of clip " + std::to_string(*id) + " of its own: " + result.ShortDebugString());
      }
    } else {
      if (result.outcome() != v1::FileResult::OUTCOME_IMPORTED || result.clip_id() <= 0 ||
          next.clips.contains(result.clip_id())) {
        return Fail("a new clip: " + result.ShortDebugString());
      }
      next.clips[result.clip_id()] = ModelClip{ClipName(t, c), c};
      Issued(result.clip_id());
    }
    in_call.insert(c);
  }
  if (existing == model_[t].end()) ++next_instance_;
  model_[t][name] = std::move(next);
  ++outcomes_["import"];
}

void TwoTenantPropertyTest::Describe(int t, const std::string& name) {
  auto described = clients_[t]->DescribeDatabase(name);
  Trace(std::string(kTenants[t]) + " DescribeDatabase " + name + " -> " + described.status().ToString());
  const auto found = model_[t].find(name);
  if (found == model_[t].end()) {
    ScanStatus(t, described.status(), "DescribeDatabase");
    return ExpectCode(described.status(), Code::kNotFound, "DescribeDatabase of a name it lacks");
  }
  if (!described.ok()) return Fail("DescribeDatabase: " + described.status().ToString());
  Scan(t, described->ShortDebugString(), "DescribeDatabase");
  const ModelDatabase& database = found->second;
  const int joints = database.rig ? kRigJoints[*database.rig] : 0;
  if (described->clip_count() != static_cast<std::int64_t>(database.clips.size()) ||
      described->frame_count() != database.frames() || described->skeleton().joints_size() != joints) {
    return Fail("DescribeDatabase answered " + described->ShortDebugString());
  }
  if (database.rig == 1 && described->skeleton().joints(0).name() != std::string(kTenants[t]) + "_Root") {
    return Fail("DescribeDatabase: a skeleton that is not its own: " + described->skeleton().joints(0).name());
  }
  ++outcomes_["describe"];
}

void TwoTenantPropertyTest::ExportOwn(int t) {
  std::vector<std::pair<std::string, std::int64_t>> clips = ClipsOf(t);
  if (clips.empty()) return Describe(t, DrawName());
  const auto& [name, id] = clips[Draw(clips.size())];
  auto text = clients_[t]->ExportClip(name, id);
  Trace(std::string(kTenants[t]) + " ExportClip " + name + " " + std::to_string(id) + " -> " +
        text.status().ToString());
  if (!text.ok()) return Fail("ExportClip of its own clip: " + text.status().ToString());
  Scan(t, *text, "ExportClip");
  const ModelClip& clip = model_[t][name].clips[id];
  auto parsed = ParseBvh(*text, "export");
  if (!parsed.ok()) return Fail("the exported clip does not parse: " + parsed.status().ToString());
  if (parsed->num_frames() != FramesOf(clip.content) ||
      parsed->skeleton.num_joints() != kRigJoints[RigOf(clip.content)]) {
    return Fail("ExportClip gave " + std::to_string(parsed->num_frames()) + " frames of " +
                std::to_string(parsed->skeleton.num_joints()) + " joints for content " + std::to_string(clip.content));
  }
  ++outcomes_["export"];
}

void TwoTenantPropertyTest::DeleteOwnClip(int t) {
  std::vector<std::pair<std::string, std::int64_t>> clips = ClipsOf(t);
  if (clips.empty()) return Create(t, DrawName());
  const auto [name, id] = clips[Draw(clips.size())];
  const absl::Status deleted = clients_[t]->DeleteClip(name, id);
  Trace(std::string(kTenants[t]) + " DeleteClip " + name + " " + std::to_string(id) + " -> " + deleted.ToString());
  ExpectCode(deleted, Code::kOk, "DeleteClip of its own clip");
  model_[t][name].clips.erase(id);
  retired_.push_back(id);
  ++outcomes_["delete clip"];
}

// The other tenant's clip id, asked through this tenant's database of the same name (or of
// another name), or a deleted clip's id (either tenant's): NOT_FOUND, by export and by deletion;
// the after-step check sees the other's clip is still there.
void TwoTenantPropertyTest::ProbeOthersClip(int t) {
  std::vector<std::pair<std::string, std::int64_t>> clips = ClipsOf(1 - t);
  const bool deleted_clip = !retired_.empty() && (clips.empty() || Draw(3) == 0);
  if (deleted_clip) clips = {{DrawName(), retired_[Draw(retired_.size())]}};
  const std::string whose = deleted_clip ? " (a deleted clip)" : " (" + Other(t) + "'s clip)";
  if (clips.empty()) return Import(t, DrawName(), {Draw(kContents)});
  auto [name, id] = clips[Draw(clips.size())];
  if (Draw(4) == 0) name = DrawName();
  if (Draw(2) == 0) {
    auto text = clients_[t]->ExportClip(name, id);
    Trace(std::string(kTenants[t]) + " ExportClip " + name + " " + std::to_string(id) + whose + " -> " +
          text.status().ToString());
    if (text.ok()) Scan(t, *text, "ExportClip of the other's clip");
    ScanStatus(t, text.status(), "ExportClip of the other's clip");
    ExpectCode(text.status(), Code::kNotFound, "ExportClip of the other tenant's clip");
  } else {
    const absl::Status deleted = clients_[t]->DeleteClip(name, id);
    Trace(std::string(kTenants[t]) + " DeleteClip " + name + " " + std::to_string(id) + whose + " -> " +
          deleted.ToString());
    ScanStatus(t, deleted, "DeleteClip of the other's clip");
    ExpectCode(deleted, Code::kNotFound, "DeleteClip of the other tenant's clip");
  }
  ++outcomes_["probe other's clip"];
}

void TwoTenantPropertyTest::Search(int t, const std::vector<std::string>& names) {
  v1::FindSimilarPosesRequest request;
  std::string listed;
  for (const std::string& name : names) {
    request.add_databases(name);
    listed += " " + name;
  }
  *request.mutable_bvh() = query_;
  request.set_top_k(5);
  auto found = clients_[t]->FindSimilarPoses(request);
  Trace(std::string(kTenants[t]) + " FindSimilarPoses" + listed + " -> " + found.status().ToString());
  // The first database named that it lacks (NOT_FOUND) or that has no clips (FAILED_PRECONDITION).
  for (const std::string& name : names) {
    const auto database = model_[t].find(name);
    if (database == model_[t].end() || database->second.clips.empty()) {
      ScanStatus(t, found.status(), "FindSimilarPoses");
      ++outcomes_["search refused"];
      return ExpectCode(found.status(), database == model_[t].end() ? Code::kNotFound : Code::kFailedPrecondition,
                        "FindSimilarPoses on " + name);
    }
  }
  if (!found.ok()) return Fail("FindSimilarPoses: " + found.status().ToString());
  Scan(t, found->ShortDebugString(), "FindSimilarPoses");
  if (found->results_size() != 3)
    return Fail("FindSimilarPoses: " + std::to_string(found->results_size()) + " results");
  for (const v1::QueryFrameMatches& frame : found->results()) {
    if (frame.matches_size() == 0) return Fail("FindSimilarPoses: a query frame without matches");
    for (const v1::PoseMatch& match : frame.matches()) {
      const auto database = model_[t].find(match.database());
      const bool named = std::find(names.begin(), names.end(), match.database()) != names.end();
      if (!named || database == model_[t].end() || !database->second.clips.contains(match.clip_id())) {
        return Fail("FindSimilarPoses: a match not in its own databases: " + match.ShortDebugString());
      }
      const ModelClip& clip = database->second.clips.at(match.clip_id());
      if (match.file_name() != clip.name || match.database_frame() < 0 ||
          match.database_frame() >= FramesOf(clip.content)) {
        return Fail("FindSimilarPoses: a match that is not its clip: " + match.ShortDebugString());
      }
    }
  }
  ++outcomes_["search"];
}

void TwoTenantPropertyTest::Session(int t, const std::string& name) {
  v1::SessionConfig config;
  config.set_database(name);
  config.mutable_fixed_lag()->set_lag_frames(2);
  auto stream = clients_[t]->OpenReconstruction(config);
  Trace(std::string(kTenants[t]) + " OpenReconstruction " + name + " -> " + stream.status().ToString());
  const auto database = model_[t].find(name);
  if (database == model_[t].end() || database->second.clips.empty()) {
    ScanStatus(t, stream.status(), "OpenReconstruction");
    ++outcomes_["session refused"];
    return ExpectCode(stream.status(), database == model_[t].end() ? Code::kNotFound : Code::kFailedPrecondition,
                      "OpenReconstruction");
  }
  if (!stream.ok()) return Fail("OpenReconstruction: " + stream.status().ToString());
  const v1::SessionStarted& started = (*stream)->started();
  Scan(t, started.ShortDebugString(), "SessionStarted");
  if (started.database_frames() != database->second.frames() ||
      started.skeleton().joints_size() != kRigJoints[*database->second.rig]) {
    (*stream)->Cancel();
    return Fail("a session on " + name + " drew from " + std::to_string(started.database_frames()) + " frames of " +
                std::to_string(started.skeleton().joints_size()) + " joints, not its own " +
                std::to_string(database->second.frames()));
  }
  if (absl::Status written = (*stream)->Write(samples_); !written.ok()) {
    return Fail("session Write: " + written.ToString());
  }
  int frames = 0;
  auto summary = (*stream)->Finish([&](const v1::ReconstructResponse& reply) {
    frames += reply.frames().frames_size();
    Scan(t, reply.ShortDebugString(), "a session's reply");
  });
  if (!summary.ok()) return Fail("session Finish: " + summary.status().ToString());
  if (frames != static_cast<int>(samples_.size())) return Fail("session: " + std::to_string(frames) + " frames");
  ++outcomes_["session"];
}

// Opens an import, sends one whole file and waits until the server has read the start (its
// byte counter has the file's bytes: start and chunk are handled in order), so the model knows
// which database the import looked up.
void TwoTenantPropertyTest::OpenImportCall(int t, const std::string& name, int content) {
  const std::int64_t before = ReceivedBytes(t);
  auto open = std::make_unique<OpenImport>();
  open->database = name;
  open->content = content;
  if (const auto found = model_[t].find(name); found != model_[t].end()) {
    open->instance = found->second.instance;
    open->rig = found->second.rig;
  }
  open->context.AddMetadata("authorization", "Bearer " + keys_[t]);
  open->context.set_deadline(std::chrono::system_clock::now() + std::chrono::minutes(5));
  open->writer = stub_->ImportBvh(&open->context, &open->response);
  v1::ImportBvhRequest start;
  start.mutable_start()->set_database(name);
  v1::ImportBvhRequest chunk;
  chunk.mutable_chunk()->set_file_name(ClipName(t, content));
  chunk.mutable_chunk()->set_data(bytes_[t][content]);
  chunk.mutable_chunk()->set_end_of_file(true);
  const bool sent = open->writer->Write(start) && open->writer->Write(chunk);
  Trace(std::string(kTenants[t]) + " opens ImportBvh " + name + " content " + std::to_string(content) + " (" +
        (open->instance ? "its database #" + std::to_string(*open->instance) : std::string("no database yet")) + ")");
  if (!sent) return Fail("the open import's first messages were not sent");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (ReceivedBytes(t) < before + static_cast<std::int64_t>(bytes_[t][content].size())) {
    if (std::chrono::steady_clock::now() > deadline) return Fail("the server did not read the open import's file");
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  open_[t] = std::move(open);
}

// Ends the open import. Its outcome follows from the database it looked up at its start, and
// what became of it: never a landing in a database created after it, its tenant's or the other's.
void TwoTenantPropertyTest::FinishImport(int t) {
  std::unique_ptr<OpenImport> open = std::move(open_[t]);
  v1::ImportBvhRequest end;
  end.mutable_end();
  open->writer->Write(end);  // false when the server has ended the call already (another rig)
  open->writer->WritesDone();
  const grpc::Status finished = open->writer->Finish();
  const absl::Status status(static_cast<Code>(finished.error_code()), finished.error_message());
  Trace(std::string(kTenants[t]) + " ends ImportBvh " + open->database + " -> " + status.ToString() + " " +
        open->response.ShortDebugString());
  ScanStatus(t, status, "ImportBvh");
  Scan(t, open->response.ShortDebugString(), "ImportBvh");
  const std::string& name = open->database;
  const auto now = model_[t].find(name);
  const int c = open->content;
  if (open->rig && *open->rig != RigOf(c)) {
    ++outcomes_["open import refused: other rig"];
    return ExpectCode(status, Code::kFailedPrecondition, "an import of another rig");
  }
  if (open->instance && (now == model_[t].end() || now->second.instance != *open->instance)) {
    // The database it started on is gone (whatever holds the name now, of either tenant).
    ++outcomes_["open import outlived its database: NOT_FOUND"];
    return ExpectCode(status, Code::kNotFound, "an import whose database was deleted");
  }
  // Races within the tenant (it created the database, or another import fixed its rig, while
  // this one was open): refused, or stored in that database of its own, never elsewhere.
  const bool raced = (!open->instance && now != model_[t].end()) || (open->instance && !open->rig && now->second.rig);
  if (raced && !status.ok()) {
    ++outcomes_["open import refused: own race"];
    if (status.code() != Code::kAlreadyExists && status.code() != Code::kFailedPrecondition) {
      Fail("an import racing its own tenant: " + status.ToString());
    }
    return;
  }
  if (!status.ok()) return Fail("ImportBvh: " + status.ToString());
  ModelDatabase next = now != model_[t].end() ? now->second : ModelDatabase{.instance = next_instance_++};
  if (next.rig && *next.rig != RigOf(c)) return Fail("an import stored into a database of another rig");
  next.rig = RigOf(c);
  if (open->response.files_size() != 1 || open->response.created_database() != (now == model_[t].end())) {
    return Fail("ImportBvh answered " + open->response.ShortDebugString());
  }
  const v1::FileResult& result = open->response.files(0);
  if (auto id = next.ClipWithContent(c)) {
    if (result.outcome() != v1::FileResult::OUTCOME_DUPLICATE || result.clip_id() != *id) {
      return Fail("ImportBvh: a duplicate of its own clip " + std::to_string(*id) + ": " + result.ShortDebugString());
    }
  } else {
    if (result.outcome() != v1::FileResult::OUTCOME_IMPORTED || result.clip_id() <= 0) {
      return Fail("ImportBvh: " + result.ShortDebugString());
    }
    next.clips[result.clip_id()] = ModelClip{ClipName(t, c), c};
    Issued(result.clip_id());
  }
  model_[t][name] = std::move(next);
  ++outcomes_[raced ? "open import stored: own race" : "open import stored"];
}

// Abandons the open import: cancelled, or half-closed without its end message. Nothing is stored.
void TwoTenantPropertyTest::AbandonImport(int t) {
  std::unique_ptr<OpenImport> open = std::move(open_[t]);
  const bool cancel = Draw(2) == 0;
  if (cancel) {
    open->context.TryCancel();
  } else {
    open->writer->WritesDone();
  }
  const grpc::Status finished = open->writer->Finish();
  Trace(std::string(kTenants[t]) + (cancel ? " cancels" : " half-closes") + " ImportBvh " + open->database + " -> " +
        finished.error_message());
  Scan(t, finished.error_message(), "an abandoned ImportBvh");
  if (finished.ok()) Fail("an import without its end message succeeded");
  ++outcomes_["open import abandoned"];
}

// Issue #24 finding 1 as a sequence: this tenant's import open on its database, the database
// deleted, the other tenant creating (or filling) its own of the same name, the import ending.
void TwoTenantPropertyTest::ReuseRace(int t) {
  const std::string name = DrawName();
  Trace("-- reuse race: " + std::string(kTenants[t]) + " on " + name);
  if (!model_[t].contains(name)) {
    Import(t, name, {DrawContent(t, name)});
    if (!failure_.empty() || !model_[t].contains(name)) return;
    CheckListings();
  }
  OpenImportCall(t, name, DrawContent(t, name));
  if (!failure_.empty()) return;
  CheckListings();
  Delete(t, name);
  CheckListings();
  if (model_[1 - t].contains(name)) {
    Import(1 - t, name, {DrawContent(1 - t, name)});
  } else {
    Create(1 - t, name);
  }
  CheckListings();
  FinishImport(t);
}

// --- checks ---

void TwoTenantPropertyTest::CheckListings() {
  for (int t = 0; t < 2 && failure_.empty(); ++t) CheckTenantListings(t);
}

void TwoTenantPropertyTest::CheckTenantListings(int t) {
  const std::string who = kTenants[t];
  auto listed = clients_[t]->ListDatabases();
  if (!listed.ok()) return Fail(who + " ListDatabases: " + listed.status().ToString());
  std::set<std::string> names;
  for (const v1::DatabaseSummary& database : *listed) {
    Scan(t, database.ShortDebugString(), "ListDatabases");
    names.insert(database.name());
    const auto model = model_[t].find(database.name());
    if (model == model_[t].end())
      return Fail(who + " lists a database it does not own: " + database.ShortDebugString());
    const int joints = model->second.rig ? kRigJoints[*model->second.rig] : 0;
    if (database.clip_count() != static_cast<std::int64_t>(model->second.clips.size()) ||
        database.frame_count() != model->second.frames() || database.joint_count() != joints) {
      return Fail(who + " lists " + database.ShortDebugString() + "; its model has " +
                  std::to_string(model->second.clips.size()) + " clips, " + std::to_string(model->second.frames()) +
                  " frames, " + std::to_string(joints) + " joints");
    }
  }
  if (names.size() != model_[t].size()) {
    return Fail(who + " lists " + std::to_string(names.size()) + " databases; its model has " +
                std::to_string(model_[t].size()));
  }
  for (const auto& [name, database] : model_[t]) {
    auto clips = clients_[t]->ListClips(name);
    if (!clips.ok()) return Fail(who + " ListClips " + name + ": " + clips.status().ToString());
    std::map<std::int64_t, std::string> seen;
    for (const v1::Clip& clip : *clips) {
      Scan(t, clip.ShortDebugString(), "ListClips");
      seen[clip.id()] = clip.source_name();
    }
    std::map<std::int64_t, std::string> expected;
    for (const auto& [id, clip] : database.clips) expected[id] = clip.name;
    if (seen != expected) return Fail(who + "'s database " + name + " lists other clips than its model");
  }
}

void TwoTenantPropertyTest::Scan(int t, const std::string& text, const std::string& where) {
  if (text.find(Other(t)) != std::string::npos) {
    Fail(std::string(kTenants[t]) + " saw " + Other(t) + "'s name in " + where + ": " + text.substr(0, 400));
  }
}

std::int64_t TwoTenantPropertyTest::ReceivedBytes(int t) {
  auto text = clients_[t]->GetMetrics();
  if (!text.ok()) return -1;
  const std::string name = "\nmocap_received_bytes_total ";
  const size_t at = text->find(name);
  return at == std::string::npos ? -1 : std::stoll(text->substr(at + name.size()));
}

TEST_F(TwoTenantPropertyTest, RandomSequencesNeverCrossTenants) {
  const int sequences = EnvInt("MOCAP_TWO_TENANT_SEQUENCES", 12);
  const int steps = EnvInt("MOCAP_TWO_TENANT_STEPS", 14);
  const std::uint64_t seed = static_cast<std::uint64_t>(EnvInt("MOCAP_TWO_TENANT_SEED", 24));
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < sequences; ++i) {
    RunSequence(seed + i, steps);
    if (!failure_.empty()) {
      std::ostringstream trace;
      for (size_t s = 0; s < trace_.size(); ++s) trace << "  " << s + 1 << ". " << trace_[s] << "\n";
      FAIL() << failure_ << "\nsequence " << i << " of " << sequences << ", seed " << seed + i
             << " (replay: MOCAP_TWO_TENANT_SEED=" << seed + i << " MOCAP_TWO_TENANT_SEQUENCES=1"
             << " MOCAP_TWO_TENANT_STEPS=" << steps << "); its operations:\n"
             << trace.str();
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << sequences << " two-tenant sequences of " << steps << " steps (seed " << seed << "), " << operations_
            << " operations, in " << seconds << " s; no cross-tenant read, write or name. Exercised:\n";
  for (const auto& [what, count] : outcomes_) std::cout << "  " << what << ": " << count << "\n";
}

}  // namespace
}  // namespace two_tenant_property_test
}  // namespace mocap
