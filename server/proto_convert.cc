#include "server/proto_convert.h"

#include "motion/core/units.h"

namespace mocap {

void ToProto(const DatabaseSummary& summary, v1::DatabaseSummary* out) {
  out->set_name(summary.ref.name());
  out->set_frame_rate(summary.frame_rate);
  out->set_source_unit(summary.has_rig ? std::string(UnitName(summary.unit)) : std::string());
  out->set_joint_count(summary.num_joints);
  out->set_clip_count(summary.num_clips);
  out->set_frame_count(summary.num_frames);
  out->set_duration_seconds(summary.seconds());
}

void ToProto(const RigModel& rig, v1::Skeleton* out) {
  const float metres = static_cast<float>(MetresPerUnit(rig.unit));
  for (int j = 0; j < rig.skeleton.num_joints(); ++j) {
    const Joint& joint = rig.skeleton.joint(j);
    v1::Joint* entry = out->add_joints();
    entry->set_name(joint.name);
    entry->set_parent(joint.parent);
    entry->mutable_offset()->set_x(joint.offset.x() * metres);
    entry->mutable_offset()->set_y(joint.offset.y() * metres);
    entry->mutable_offset()->set_z(joint.offset.z() * metres);
    if (joint.end_site) {
      entry->mutable_end_site()->set_x(joint.end_site->x() * metres);
      entry->mutable_end_site()->set_y(joint.end_site->y() * metres);
      entry->mutable_end_site()->set_z(joint.end_site->z() * metres);
    }
    if (j < static_cast<int>(rig.topology.group_of_joint.size())) {
      entry->set_group(static_cast<v1::BodyGroup>(static_cast<int>(rig.topology.group_of_joint[j]) + 1));
    }
  }
  const BodyLandmarks& l = rig.topology.landmarks;
  v1::BodyLandmarks* landmarks = out->mutable_landmarks();
  landmarks->set_pelvis(l.pelvis);
  landmarks->set_head(l.head);
  landmarks->set_left_wrist(l.left_wrist);
  landmarks->set_right_wrist(l.right_wrist);
  landmarks->set_left_ankle(l.left_ankle);
  landmarks->set_right_ankle(l.right_ankle);
  landmarks->set_left_shoulder(l.left_shoulder);
  landmarks->set_right_shoulder(l.right_shoulder);
  landmarks->set_left_elbow(l.left_elbow);
  landmarks->set_right_elbow(l.right_elbow);
  landmarks->set_left_hip(l.left_hip);
  landmarks->set_right_hip(l.right_hip);
  landmarks->set_left_knee(l.left_knee);
  landmarks->set_right_knee(l.right_knee);
}

void ToProto(const ClipSummary& clip, v1::Clip* out) {
  out->set_id(clip.id);
  out->set_source_name(clip.source_name);
  out->set_frame_count(clip.num_frames);
  out->set_source_frame_rate(clip.source_frame_rate);
  out->set_source_frame_count(clip.source_frames);
  out->set_content_hash(clip.content_hash);
  for (const auto& [key, value] : clip.labels) (*out->mutable_labels())[key] = value;
}

void ToProto(const std::string& database, const ImportTotals& totals, v1::ImportBvhResponse* out) {
  out->set_database(database);
  out->set_created_database(totals.created_database);
  out->set_imported_count(totals.imported);
  out->set_duplicate_count(totals.duplicates);
  out->set_failed_count(totals.failed);
  out->set_frame_count(totals.frames);
  out->set_source_frame_count(totals.source_frames);
  for (const ImportFileResult& file : totals.files) {
    v1::FileResult* result = out->add_files();
    result->set_file_name(file.file_name);
    switch (file.outcome) {
      case ImportFileResult::Outcome::kImported:
        result->set_outcome(v1::FileResult::OUTCOME_IMPORTED);
        break;
      case ImportFileResult::Outcome::kDuplicate:
        result->set_outcome(v1::FileResult::OUTCOME_DUPLICATE);
        break;
      case ImportFileResult::Outcome::kFailed:
        result->set_outcome(v1::FileResult::OUTCOME_FAILED);
        break;
    }
    result->set_clip_id(file.clip_id);
    result->set_frame_count(file.frames);
    result->set_error(file.message);
  }
}

}  // namespace mocap
