#!/usr/bin/env python3
"""Independent check of syn-export's robot-learning formats, with numpy only (no synsculpt code): loads
the exports with np.load / np.loadtxt, recomputes every link pose by forward kinematics straight from the
URDF (xml.etree), and compares with the source robot CSV (root x,y,z, quaternion w,x,y,z, joints in URDF
order). Prints one line per failed check and exits 1 if any, else prints "ok" and a summary.

    check_exports.py ROBOT.urdf SOURCE.csv FPS UNITREE.csv GMR.npz MJLAB.npz
"""
import sys
import xml.etree.ElementTree as ET

import numpy as np

urdf_path, source_path, fps_text, unitree_path, gmr_path, mjlab_path = sys.argv[1:7]
fps = float(fps_text)
failures = []


def check(name, ok, detail=''):
    if not ok:
        failures.append(f'{name}: {detail}')


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def axis_angle(axis, angle):
    axis = axis / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def quat_matrix(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


robot = ET.parse(urdf_path).getroot()
links = [link.get('name') for link in robot.findall('link')]
joints = []
for joint in robot.findall('joint'):
    origin = joint.find('origin')
    xyz = np.array([float(v) for v in (origin.get('xyz', '0 0 0') if origin is not None else '0 0 0').split()])
    rpy = [float(v) for v in (origin.get('rpy', '0 0 0') if origin is not None else '0 0 0').split()]
    axis = joint.find('axis')
    joints.append({'name': joint.get('name'), 'type': joint.get('type'), 'parent': joint.find('parent').get('link'),
                   'child': joint.find('child').get('link'), 'xyz': xyz, 'rot': rpy_matrix(*rpy),
                   'axis': np.array([float(v) for v in (axis.get('xyz') if axis is not None else '1 0 0').split()])})
moving = [j for j in joints if j['type'] in ('revolute', 'continuous', 'prismatic')]
root = [l for l in links if l not in {j['child'] for j in joints}][0]

source = np.loadtxt(source_path, delimiter=',', ndmin=2)
T, J, B = source.shape[0], len(moving), len(links)


def forward_kinematics(row):
    """World rotation and position of every link for one source row."""
    poses = {root: (quat_matrix(*row[3:7]), row[0:3].copy())}
    q = dict(zip([j['name'] for j in moving], row[7:]))
    pending = list(joints)
    while pending:
        for j in list(pending):
            if j['parent'] not in poses:
                continue
            r, p = poses[j['parent']]
            r_joint, p_joint = r @ j['rot'], p + r @ j['xyz']
            if j['type'] in ('revolute', 'continuous'):
                r_joint = r_joint @ axis_angle(j['axis'], q[j['name']])
            elif j['type'] == 'prismatic':
                p_joint = p_joint + r_joint @ (j['axis'] / np.linalg.norm(j['axis']) * q[j['name']])
            poses[j['child']] = (r_joint, p_joint)
            pending.remove(j)
    return [poses[l] for l in links]


fk = [forward_kinematics(source[t]) for t in range(T)]
body_pos = np.array([[p for _, p in frame] for frame in fk])
body_rot = np.array([[r for r, _ in frame] for frame in fk])

# ---- unitree-csv: root x,y,z, quaternion x,y,z,w, joints ----
unitree = np.loadtxt(unitree_path, delimiter=',', ndmin=2)
check('unitree shape', unitree.shape == (T, 7 + J), unitree.shape)
if unitree.shape == (T, 7 + J):
    check('unitree root position', np.array_equal(unitree[:, 0:3], source[:, 0:3]))
    check('unitree quaternion x,y,z,w', np.array_equal(unitree[:, 3:7], source[:, [4, 5, 6, 3]]))
    check('unitree joints', np.array_equal(unitree[:, 7:], source[:, 7:]))


def same_rotation_xyzw(q, r):
    return np.allclose(quat_matrix(q[3], q[0], q[1], q[2]), r, atol=1e-9)


# ---- gmr-npz ----
gmr = np.load(gmr_path, allow_pickle=False)
check('gmr keys', set(gmr.files) >= {'fps', 'root_pos', 'root_rot', 'dof_pos', 'link_body_list', 'local_body_pos'},
      gmr.files)
check('gmr fps', gmr['fps'].shape == () and abs(float(gmr['fps']) - fps) < 1e-9, gmr['fps'])
check('gmr root_pos', np.allclose(gmr['root_pos'], source[:, 0:3], atol=1e-12))
check('gmr root_rot shape', gmr['root_rot'].shape == (T, 4))
check('gmr root_rot x,y,z,w', all(same_rotation_xyzw(gmr['root_rot'][t], body_rot[t, links.index(root)]) for t in range(T)))
check('gmr dof_pos', np.array_equal(gmr['dof_pos'], source[:, 7:]))
check('gmr link_body_list', list(gmr['link_body_list']) == links, list(gmr['link_body_list'])[:3])
local = np.einsum('tji,tbj->tbi', body_rot[:, links.index(root)], body_pos - body_pos[:, links.index(root)][:, None, :])
check('gmr local_body_pos', gmr['local_body_pos'].shape == (T, B, 3) and np.allclose(gmr['local_body_pos'], local, atol=1e-9),
      np.abs(gmr['local_body_pos'] - local).max() if gmr['local_body_pos'].shape == (T, B, 3) else gmr['local_body_pos'].shape)

# ---- mjlab-npz ----
mj = np.load(mjlab_path, allow_pickle=False)
check('mjlab keys', set(mj.files) >= {'fps', 'joint_pos', 'joint_vel', 'body_pos_w', 'body_quat_w', 'body_lin_vel_w',
                                      'body_ang_vel_w'}, mj.files)
check('mjlab fps', mj['fps'].shape == (1,) and abs(mj['fps'][0] - fps) < 1e-9, mj['fps'])
check('mjlab joint_pos', np.array_equal(mj['joint_pos'], source[:, 7:]))
time = np.arange(T) / fps


def central_difference(x):
    d = np.empty_like(x)
    d[1:-1] = (x[2:] - x[:-2]) / (time[2:] - time[:-2])[(slice(None),) + (None,) * (x.ndim - 1)]
    d[0] = (x[1] - x[0]) / (time[1] - time[0])
    d[-1] = (x[-1] - x[-2]) / (time[-1] - time[-2])
    return d


check('mjlab joint_vel', np.allclose(mj['joint_vel'], central_difference(source[:, 7:]), atol=1e-6))
err = np.abs(mj['body_pos_w'] - body_pos).max()
check('mjlab body_pos_w', mj['body_pos_w'].shape == (T, B, 3) and err < 1e-9, err)
quat = mj['body_quat_w']
check('mjlab body_quat_w w,x,y,z',
      quat.shape == (T, B, 4) and all(np.allclose(quat_matrix(*quat[t, b]), body_rot[t, b], atol=1e-9)
                                      for t in range(T) for b in range(B)))
check('mjlab quaternion sign continuity', np.all(np.einsum('tbi,tbi->tb', quat[1:], quat[:-1]) > 0))
check('mjlab body_lin_vel_w', np.allclose(mj['body_lin_vel_w'], central_difference(body_pos), atol=1e-6),
      np.abs(mj['body_lin_vel_w'] - central_difference(body_pos)).max())
# Angular velocity: rotation vector of R[after] R[before]^T over the time between them.
angular = np.zeros((T, B, 3))
for t in range(T):
    before, after = max(t - 1, 0), min(t + 1, T - 1)
    for b in range(B):
        relative = body_rot[after, b] @ body_rot[before, b].T
        angle = np.arccos(np.clip((np.trace(relative) - 1) / 2, -1, 1))
        vector = np.array([relative[2, 1] - relative[1, 2], relative[0, 2] - relative[2, 0], relative[1, 0] - relative[0, 1]])
        angular[t, b] = vector / (2 * np.sin(angle)) * angle if angle > 1e-12 else vector / 2
        angular[t, b] /= time[after] - time[before]
check('mjlab body_ang_vel_w', np.allclose(mj['body_ang_vel_w'], angular, atol=1e-6),
      np.abs(mj['body_ang_vel_w'] - angular).max())
check('mjlab body_names', list(mj['body_names']) == links)
check('mjlab joint_names', list(mj['joint_names']) == [j['name'] for j in moving])

if failures:
    print('\n'.join(failures))
    sys.exit(1)
print(f'ok: {T} frames, {J} joints, {B} links; largest body_pos_w error {err:.2e} m')
