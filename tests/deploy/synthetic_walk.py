#!/usr/bin/env python3
"""Small synthetic humanoid walks for the deployment and interop tests (no shared data needed).

A port of the plain rig and walk of tests/support/synthetic_clip.cc (21 joints, centimetres, Y up,
walking along +Z, left side at +X), with the gait cycle, speed and start time as parameters so
that several clips differ in content. Pure Python (no numpy), deterministic.

  synthetic_walk.py bvh OUT.bvh [--frames 90] [--cycle 1.0] [--speed 120] [--start 0]
  synthetic_walk.py csv OUT.csv [--frames 60] [--cycle 1.0] [--speed 120] [--start 0]

`csv` writes the two wrist trajectories (the Hand joints by forward kinematics, metres, seconds
from 0) in the format of cli_util/wrist_source.h:
  time,left_x,left_y,left_z,right_x,right_y,right_z
"""
import argparse
import math

FRAME_TIME = 1.0 / 30.0
ANKLE_HEIGHT = 5.0
TOE_HEIGHT = 0.5
REST_HIPS_HEIGHT = 96.0
THIGH = 43.0
SHIN = 42.0
HIP_YAW = 4.0
ARM_LOWERING = 75.0
ARM_SWING = 18.0
HIP_JOINT_DROP = 6.0
HIP_JOINT_SIDE = 9.0


def rotation(axis, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    if axis == 0:
        return [[1, 0, 0], [0, c, -s], [0, s, c]]
    if axis == 1:
        return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def apply(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


IDENTITY = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


def build_body():
    """Joints as (name, parent, offset, end_site) in depth-first (file) order."""
    joints = []

    def add(name, parent, offset, end_site=None):
        joints.append((name, parent, offset, end_site))
        return len(joints) - 1

    body = {}
    body["hips"] = add("Hips", -1, [0, REST_HIPS_HEIGHT, 0])
    body["spine"] = add("Spine", body["hips"], [0, 10, 0])
    body["chest"] = add("Chest", body["spine"], [0, 15, 0])
    body["neck"] = add("Neck", body["chest"], [0, 22, 0])
    add("Head", body["neck"], [0, 9, 0], [0, 18, 0])
    for side, prefix in ((0, "Left"), (1, "Right")):
        s = 1.0 if side == 0 else -1.0
        shoulder = add(prefix + "Shoulder", body["chest"], [3 * s, 17, 0])
        body[("arm", side)] = add(prefix + "Arm", shoulder, [14 * s, 0, 0])
        body[("forearm", side)] = add(prefix + "ForeArm", body[("arm", side)], [28 * s, 0, 0])
        body[("hand", side)] = add(prefix + "Hand", body[("forearm", side)], [25 * s, 0, 0], [18 * s, 0, 0])
    for side, prefix in ((0, "Left"), (1, "Right")):
        s = 1.0 if side == 0 else -1.0
        body[("upleg", side)] = add(prefix + "UpLeg", body["hips"], [HIP_JOINT_SIDE * s, -HIP_JOINT_DROP, 0])
        body[("leg", side)] = add(prefix + "Leg", body[("upleg", side)], [0, -THIGH, 0])
        body[("foot", side)] = add(prefix + "Foot", body[("leg", side)], [0, -SHIN, 0])
        add(prefix + "ToeBase", body[("foot", side)], [0, TOE_HEIGHT - ANKLE_HEIGHT, 13], [0, 0, 6])
    return joints, body


def solve_leg(z, knee):
    def horizontal(a):
        return THIGH * math.sin(math.radians(a)) + SHIN * math.sin(math.radians(a - knee))

    lo, hi = -80.0, 80.0 + knee
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if horizontal(mid) < z:
            lo = mid
        else:
            hi = mid
    flexion = 0.5 * (lo + hi)
    extent = THIGH * math.cos(math.radians(flexion)) + SHIN * math.cos(math.radians(flexion - knee))
    return flexion, knee, extent


class Walk:
    def __init__(self, cycle=1.0, speed=120.0):
        self.cycle = cycle
        self.speed = speed
        self.half_step = speed * cycle / 4.0
        self.joints, self.body = build_body()

    def hip_yaw(self, t):
        return -HIP_YAW * math.cos(2 * math.pi * t / self.cycle)

    def leg_at(self, t, side):
        p = t / self.cycle + (0.0 if side == 0 else 0.5)
        p -= math.floor(p)
        s = 1.0 if side == 0 else -1.0
        yaw_shift = HIP_JOINT_SIDE * (s * math.sin(math.radians(self.hip_yaw(t))) + math.sin(math.radians(HIP_YAW)))
        stance_end = -self.half_step + 2 * HIP_JOINT_SIDE * math.sin(math.radians(HIP_YAW))
        if p < 0.5:
            u = p / 0.5
            return solve_leg(self.half_step * (1 - 2 * u) + yaw_shift, 5 + 10 * math.sin(math.pi * u))
        u = (p - 0.5) / 0.5
        return solve_leg(stance_end + (self.half_step - stance_end) * 0.5 * (1 - math.cos(math.pi * u)),
                         5 + 55 * math.sin(math.pi * math.sqrt(u)))

    def pose(self, t):
        """Local rotation matrices and the Hips world position (cm) at time t."""
        b = self.body
        local = [IDENTITY] * len(self.joints)
        yaw = self.hip_yaw(t)
        legs = [self.leg_at(t, 0), self.leg_at(t, 1)]
        hips = [0.0, ANKLE_HEIGHT + HIP_JOINT_DROP + max(legs[0][2], legs[1][2]), self.speed * t]
        local[b["hips"]] = rotation(1, yaw)
        local[b["spine"]] = rotation(1, -yaw)
        local[b["chest"]] = rotation(1, -0.5 * yaw)
        local[b["neck"]] = rotation(1, 0.5 * yaw)
        for side in (0, 1):
            s = 1.0 if side == 0 else -1.0
            flexion, knee, _ = legs[side]
            local[b[("upleg", side)]] = mul(rotation(1, -yaw), rotation(0, -flexion))
            local[b[("leg", side)]] = rotation(0, knee)
            local[b[("foot", side)]] = rotation(0, flexion - knee)
            p = t / self.cycle + (0.0 if side == 0 else 0.5)
            p -= math.floor(p)
            swing = -ARM_SWING * math.cos(2 * math.pi * p)
            local[b[("arm", side)]] = mul(rotation(0, -swing), rotation(2, -ARM_LOWERING * s))
            elbow = 20 + 10 * max(0.0, swing) / ARM_SWING
            local[b[("forearm", side)]] = rotation(1, -elbow * s)
        return local, hips

    def hands(self, t):
        """World positions (cm) of the left and right Hand joints at time t."""
        local, hips = self.pose(t)
        world_rot, world_pos = [], []
        for j, (_, parent, offset, _) in enumerate(self.joints):
            if parent < 0:
                world_rot.append(local[j])
                world_pos.append(hips)
            else:
                step = apply(world_rot[parent], offset)
                world_pos.append([world_pos[parent][i] + step[i] for i in range(3)])
                world_rot.append(mul(world_rot[parent], local[j]))
        return world_pos[self.body[("hand", 0)]], world_pos[self.body[("hand", 1)]]


def euler_zxy(m):
    """Degrees (z, x, y) with R = Rz(z) Rx(x) Ry(y) (BVH channels Zrotation Xrotation Yrotation)."""
    i, j, k = 2, 0, 1
    sign = 1.0 if j == (i + 1) % 3 else -1.0
    s = max(-1.0, min(1.0, sign * m[i][k]))
    e1 = math.asin(s)
    if abs(s) < 1.0 - 1e-12:
        e0 = math.atan2(-sign * m[j][k], m[k][k])
        e2 = math.atan2(-sign * m[i][j], m[i][i])
    else:
        e0 = math.atan2(sign * m[k][j], m[j][j])
        e2 = 0.0
    return [0.0 if abs(math.degrees(e)) < 1e-9 else math.degrees(e) for e in (e0, e1, e2)]


def write_bvh(path, walk, frames, start):
    joints = walk.joints
    children = {j: [c for c, joint in enumerate(joints) if joint[1] == j] for j in range(len(joints))}
    lines = ["HIERARCHY"]

    def emit(j, depth):
        name, parent, offset, end_site = joints[j]
        pad = "  " * depth
        lines.append(f"{pad}{'ROOT' if parent < 0 else 'JOINT'} {name}")
        lines.append(pad + "{")
        lines.append(f"{pad}  OFFSET {offset[0]:.6f} {offset[1]:.6f} {offset[2]:.6f}")
        if parent < 0:
            lines.append(f"{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation")
        else:
            lines.append(f"{pad}  CHANNELS 3 Zrotation Xrotation Yrotation")
        for c in children[j]:
            emit(c, depth + 1)
        if not children[j]:
            lines.append(f"{pad}  End Site")
            lines.append(pad + "  {")
            lines.append(f"{pad}    OFFSET {end_site[0]:.6f} {end_site[1]:.6f} {end_site[2]:.6f}")
            lines.append(pad + "  }")
        lines.append(pad + "}")

    emit(0, 0)
    lines += ["MOTION", f"Frames: {frames}", f"Frame Time: {FRAME_TIME:.8f}"]
    for f in range(frames):
        local, hips = walk.pose(start + f * FRAME_TIME)
        values = []
        for j, (_, parent, offset, _) in enumerate(joints):
            if parent < 0:
                values += [hips[i] - offset[i] for i in range(3)]
            values += euler_zxy(local[j])
        lines.append(" ".join(f"{v:.6f}" for v in values))
    with open(path, "w", encoding="ascii") as out:
        out.write("\n".join(lines) + "\n")


def write_csv(path, walk, frames, start):
    lines = ["time,left_x,left_y,left_z,right_x,right_y,right_z"]
    for f in range(frames):
        left, right = walk.hands(start + f * FRAME_TIME)
        values = [f * FRAME_TIME] + [v / 100.0 for v in left + right]
        lines.append(",".join(f"{v:.6f}" for v in values))
    with open(path, "w", encoding="ascii") as out:
        out.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("kind", choices=["bvh", "csv"])
    parser.add_argument("output")
    parser.add_argument("--frames", type=int, default=90)
    parser.add_argument("--cycle", type=float, default=1.0, help="gait cycle, seconds per two steps")
    parser.add_argument("--speed", type=float, default=120.0, help="walking speed, cm/s")
    parser.add_argument("--start", type=float, default=0.0, help="time of the first frame, seconds")
    args = parser.parse_args()
    walk = Walk(args.cycle, args.speed)
    (write_bvh if args.kind == "bvh" else write_csv)(args.output, walk, args.frames, args.start)


if __name__ == "__main__":
    main()
