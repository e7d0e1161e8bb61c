// libFuzzer target: the caller's own rig of a reconstruction session (issue #24: sizes declared in
// any text are checked before anything is allocated), in both forms: the bytes are a TargetRig —
// a BVH file's text or a list of joints, with a unit. As a session's setup does, it is converted
// and analysed (server FromProto), the synthetic database's rig is mapped onto it, and one pose is
// retargeted, as a session's first frame is.
#include <cstddef>
#include <cstdint>

#include "mocap/v1/target_rig.pb.h"
#include "motion/retarget/retarget_rig.h"
#include "motion/retarget/retargeter.h"
#include "server/reconstruction_convert.h"
#include "tests/support/synthetic_database.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mocap::v1::TargetRig proto;
  if (!proto.ParseFromArray(data, static_cast<int>(size))) return 0;
  absl::StatusOr<mocap::RetargetRig> target = mocap::FromProto(proto);
  if (!target.ok()) return 0;
  const mocap::ReconstructionDatabase& database = *mocap::testing::SharedSyntheticReconstructionSetup().database;
  static const auto* source = [&] {  // the database's side, analysed once
    absl::StatusOr<mocap::RetargetRig> rig = mocap::SourceRigOf(database.rig(), database.body().skeleton());
    if (!rig.ok()) __builtin_trap();  // the synthetic database's own rig always maps
    return new mocap::RetargetRig(*std::move(rig));
  }();
  absl::StatusOr<mocap::Retargeter> retargeter = mocap::Retargeter::Create(*source, *std::move(target));
  if (!retargeter.ok()) return 0;
  const Eigen::VectorXf feature = database.pose_feature(0).transpose();  // a database frame's pose
  const mocap::BodyPose pose =
      database.body().Pose(Eigen::Quaternionf::Identity(), Eigen::Vector3f(0, 1, 0), feature.data() + 2);
  mocap::BodyPose out;
  retargeter->Retarget(database.body(), pose, &out);
  return 0;
}
