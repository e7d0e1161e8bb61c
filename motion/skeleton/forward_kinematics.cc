#include "motion/skeleton/forward_kinematics.h"

namespace mocap {

GlobalPoses ForwardKinematics(const Skeleton& skeleton, const LocalMotion& motion) {
  const int frames = motion.num_frames();
  const int joints = motion.num_joints();
  GlobalPoses g;
  for (Eigen::ArrayXXf* a : {&g.px, &g.py, &g.pz, &g.qw, &g.qx, &g.qy, &g.qz}) a->resize(frames, joints);
  for (int j = 0; j < joints; ++j) {
    const int p = skeleton.parent(j);
    if (p < 0) {
      g.px.col(j) = motion.tx.col(j);
      g.py.col(j) = motion.ty.col(j);
      g.pz.col(j) = motion.tz.col(j);
      g.qw.col(j) = motion.qw.col(j);
      g.qx.col(j) = motion.qx.col(j);
      g.qy.col(j) = motion.qy.col(j);
      g.qz.col(j) = motion.qz.col(j);
      continue;
    }
    // Plain loops over contiguous columns: the compiler vectorises them.
    const float* pw = &g.qw(0, p);
    const float* px = &g.qx(0, p);
    const float* py = &g.qy(0, p);
    const float* pz = &g.qz(0, p);
    const float* ppx = &g.px(0, p);
    const float* ppy = &g.py(0, p);
    const float* ppz = &g.pz(0, p);
    const float* lw = &motion.qw(0, j);
    const float* lx = &motion.qx(0, j);
    const float* ly = &motion.qy(0, j);
    const float* lz = &motion.qz(0, j);
    const float* tx = &motion.tx(0, j);
    const float* ty = &motion.ty(0, j);
    const float* tz = &motion.tz(0, j);
    float* ow = &g.qw(0, j);
    float* ox = &g.qx(0, j);
    float* oy = &g.qy(0, j);
    float* oz = &g.qz(0, j);
    float* opx = &g.px(0, j);
    float* opy = &g.py(0, j);
    float* opz = &g.pz(0, j);
    for (int f = 0; f < frames; ++f) {
      const float w = pw[f], x = px[f], y = py[f], z = pz[f];
      // Rotate the local translation by the parent's world rotation: v + 2w(u×v) + 2u×(u×v).
      const float vx = tx[f], vy = ty[f], vz = tz[f];
      const float cx = 2 * (y * vz - z * vy), cy = 2 * (z * vx - x * vz), cz = 2 * (x * vy - y * vx);
      opx[f] = ppx[f] + vx + w * cx + (y * cz - z * cy);
      opy[f] = ppy[f] + vy + w * cy + (z * cx - x * cz);
      opz[f] = ppz[f] + vz + w * cz + (x * cy - y * cx);
      // World rotation = parent world rotation * local rotation.
      const float bw = lw[f], bx = lx[f], by = ly[f], bz = lz[f];
      ow[f] = w * bw - x * bx - y * by - z * bz;
      ox[f] = w * bx + x * bw + y * bz - z * by;
      oy[f] = w * by - x * bz + y * bw + z * bx;
      oz[f] = w * bz + x * by - y * bx + z * bw;
    }
  }
  return g;
}

LocalMotion RestMotion(const Skeleton& skeleton) {
  LocalMotion motion;
  motion.Resize(1, skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    motion.SetRotation(0, j, Eigen::Quaternionf::Identity());
    motion.SetTranslation(0, j, skeleton.joint(j).offset);
  }
  return motion;
}

Eigen::VectorXf BoneLengths(const LocalMotion& motion) {
  Eigen::VectorXf lengths(motion.num_joints());
  for (int j = 0; j < motion.num_joints(); ++j) {
    lengths[j] =
        j == 0 ? 0.0f
               : (motion.tx.col(j).square() + motion.ty.col(j).square() + motion.tz.col(j).square()).sqrt().mean();
  }
  return lengths;
}

}  // namespace mocap
