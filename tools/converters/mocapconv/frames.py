"""Coordinate conventions and rotations: a source's frame to the server's native one.

The native frame is the server's own (docs/input-conventions.md): metres, right-handed, Y up. A
source frame is a length unit, an up axis and a handedness; its axes map to the native ones by the
server's own rule (motion/frames/frame_convention.h, NativeBasis), so a converted log is what the
server makes of the same samples declared with `--input-frame`:
  1. a left-handed frame negates its last horizontal axis (Z when X or Y is up, Y when Z is up);
  2. the up axis turns onto +Y by the shortest rotation.
Quaternions are (x, y, z, w) tuples, as OpenXR, WebXR, Unity and Unreal store them, rotating
column vectors by the usual formula (q v q*) in whatever axes they are written in.
"""

import math
from dataclasses import dataclass

UP_AXES = ("+X", "-X", "+Y", "-Y", "+Z", "-Z")

# Rows: native x, y, z as combinations of the (right-handed) source axes, per up axis
# (frame_convention.cc, NativeBasis's `turn`).
_TURN = {
    "+Y": ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    "-Y": ((1, 0, 0), (0, -1, 0), (0, 0, -1)),
    "+Z": ((1, 0, 0), (0, 0, 1), (0, -1, 0)),
    "-Z": ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    "+X": ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    "-X": ((0, 1, 0), (-1, 0, 0), (0, 0, 1)),
}


def _mat_mul(a, b):
    return tuple(tuple(sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)) for i in range(3))


def mat_vec(m, v):
    return tuple(m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3))


def determinant(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
            m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


@dataclass(frozen=True)
class Convention:
    """A source's frame: metres per unit, up axis ('+Y', '-Z', ...), 'right' or 'left'."""
    metres_per_unit: float
    up: str
    handedness: str

    def basis(self):
        """The signed permutation C with native = C · source (before units), as NativeBasis."""
        mirror = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
        if self.handedness == "left":
            last = 1 if self.up[1] == "Z" else 2
            mirror[last][last] = -1
        return _mat_mul(_TURN[self.up], mirror)

    def position_to_native(self, p):
        s = self.metres_per_unit
        return tuple(s * c for c in mat_vec(self.basis(), p))

    def rotation_to_native(self, q):
        """C·R·C⁻¹ on a quaternion, exactly as the server does (frame_transform.h): the axis
        becomes det(C)·C·axis, the angle stays."""
        c = self.basis()
        d = determinant(c)
        x, y, z = (d * v for v in mat_vec(c, q[:3]))
        return (x, y, z, q[3])

    def up_to_native_height(self, height):
        """A coordinate on the source's up axis (source units) as a native height (metres)."""
        sign = 1.0 if self.up[0] == "+" else -1.0
        return sign * height * self.metres_per_unit



# --- quaternions (x, y, z, w) ---

def quat_norm(q):
    return math.sqrt(sum(c * c for c in q))


def quat_normalized(q):
    n = quat_norm(q)
    return tuple(c / n for c in q)



def quat_rotate(q, v):
    """q · v · q* for a unit quaternion q."""
    x, y, z, w = q
    # v + 2w (u × v) + 2 u × (u × v), u = (x, y, z)
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    ccx, ccy, ccz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (v[0] + 2 * (w * cx + ccx), v[1] + 2 * (w * cy + ccy), v[2] + 2 * (w * cz + ccz))



def quat_from_matrix(m):
    """The unit quaternion of a rotation matrix (Shepperd's method: the largest of w, x, y, z first)."""
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 2 * math.sqrt(1 + trace)
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, s / 4)
    elif m[0][0] >= m[1][1] and m[0][0] >= m[2][2]:
        s = 2 * math.sqrt(1 + m[0][0] - m[1][1] - m[2][2])
        q = (s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    elif m[1][1] >= m[2][2]:
        s = 2 * math.sqrt(1 + m[1][1] - m[0][0] - m[2][2])
        q = ((m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    else:
        s = 2 * math.sqrt(1 + m[2][2] - m[0][0] - m[1][1])
        q = ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4, (m[1][0] - m[0][1]) / s)
    return quat_normalized(q)


def quat_slerp(a, b, f):
    dot = sum(x * y for x, y in zip(a, b))
    if dot < 0:
        b, dot = tuple(-c for c in b), -dot
    if dot > 0.9995:
        return quat_normalized(tuple(x + f * (y - x) for x, y in zip(a, b)))
    theta = math.acos(dot)
    sa, sb = math.sin((1 - f) * theta), math.sin(f * theta)
    return quat_normalized(tuple((sa * x + sb * y) / math.sin(theta) for x, y in zip(a, b)))
