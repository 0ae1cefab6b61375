"""Quaternion helpers: unit quaternions ``(w, x, y, z)`` as tuples of floats (or of numpy
arrays, element by element).

Products and conjugates (:func:`qmul`, :func:`qconj`), rotating a vector (:func:`qrot`), the
rotation by an angle about an axis (:func:`qaxis`), the z-x-z Euler rotation (:func:`zxz`), and
the quaternion of a rotation matrix (:func:`_quat_of_matrix`, :func:`frame_quat` for a signed
permutation of axes).  Used by the free rigid body (:mod:`coincli.core.rigid`) and the bounce
engine (:mod:`coincli.core.bounce.engine`).  Pure Python: numpy, where a caller passes arrays,
comes in with them.
"""

from __future__ import annotations

import math


def qmul(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw)


def zxz(np, phi, theta, psi):
    """The quaternion of Rz(phi) Rx(theta) Rz(psi)."""
    ct, st = np.cos(theta / 2), np.sin(theta / 2)
    a, b = (phi + psi) / 2, (phi - psi) / 2
    return (ct * np.cos(a), st * np.cos(b), st * np.sin(b), ct * np.sin(a))


def qconj(q):
    return (q[0], -q[1], -q[2], -q[3])


def qrot(q, v):
    """Rotate vector v by unit quaternion q."""
    w, x, y, z = q
    vx, vy, vz = v
    # t = 2 q_vec x v; v' = v + w t + q_vec x t
    tx, ty, tz = 2 * (y * vz - z * vy), 2 * (z * vx - x * vz), 2 * (x * vy - y * vx)
    return (vx + w * tx + (y * tz - z * ty), vy + w * ty + (z * tx - x * tz),
            vz + w * tz + (x * ty - y * tx))


def qaxis(axis, angle):
    s = math.sin(0.5 * angle)
    return (math.cos(0.5 * angle), axis[0] * s, axis[1] * s, axis[2] * s)


def _quat_of_matrix(R):
    """Unit quaternion (w, x, y, z) of a proper rotation matrix (nested lists), Shepperd."""
    tr = R[0][0] + R[1][1] + R[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return ((s / 4), (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s)
    i = max(range(3), key=lambda k: R[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1.0 + R[i][i] - R[j][j] - R[k][k]) * 2
    q = [0.0] * 4
    q[0] = (R[k][j] - R[j][k]) / s
    q[1 + i] = s / 4
    q[1 + j] = (R[j][i] + R[i][j]) / s
    q[1 + k] = (R[k][i] + R[i][k]) / s
    return tuple(q)


def frame_quat(perm, sign):
    """Quaternion of the rotation P with (P v)[k] = sign[k] * v[perm[k]] (user -> frame)."""
    R = [[0.0] * 3 for _ in range(3)]
    for k in range(3):
        R[k][perm[k]] = sign[k]
    return _quat_of_matrix(R)
