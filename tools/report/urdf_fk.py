"""A URDF's kinematic tree and its forward kinematics, in numpy, independent of the C++ stages.

The report uses it twice: to write the robot description the 3-D player draws (player.js repeats the same
FK in JavaScript, so a motion file's q is all the page needs), and to place the feet's sole points for the
contact and sliding frames. Conventions follow common/simbody/model.cpp: a free base's coordinates are
base_qw, base_qx, base_qy, base_qz (the pelvis orientation in the world) then base_x, base_y, base_z; every
other coordinate is named after its URDF joint. The tests check this FK against syn-retarget's own
landmark errors (tests/report/check_fk.py).
"""
import xml.etree.ElementTree as ElementTree

import numpy as np


def rpy_matrix(rpy):
    """URDF fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    roll, pitch, yaw = rpy
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def matrix_quaternion(rotation):
    """w, x, y, z of a rotation matrix (Shepperd's method, stable for every angle)."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * np.sqrt(1.0 + trace)
        return np.array([0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s])
    i = int(np.argmax([m[0, 0], m[1, 1], m[2, 2]]))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
    q = np.zeros(4)
    q[0] = (m[k, j] - m[j, k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (m[j, i] + m[i, j]) / s
    q[1 + k] = (m[k, i] + m[i, k]) / s
    return q if q[0] >= 0 else -q


def quaternion_matrices(quaternions):
    """Rotation matrices [..., 3, 3] of unit quaternions [..., 4] given as w, x, y, z (normalized here)."""
    q = quaternions / np.linalg.norm(quaternions, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)], axis=-2)


def axis_angle_matrices(axis, angles):
    """Rotations [T, 3, 3] by `angles` [T] about the unit `axis` (Rodrigues)."""
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    s, c = np.sin(angles)[:, None, None], np.cos(angles)[:, None, None]
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def _floats(text, default):
    return [float(v) for v in text.split()] if text else list(default)


class Robot:
    """Links in tree order (every parent before its children), each with the joint that carries it."""

    def __init__(self, urdf_path):
        root = ElementTree.parse(urdf_path).getroot()
        self.name = root.get("name", "")
        link_elements = {link.get("name"): link for link in root.findall("link")}
        joints = {}
        for joint in root.findall("joint"):
            origin = joint.find("origin")
            axis = joint.find("axis")
            joints[joint.find("child").get("link")] = {
                "name": joint.get("name"), "type": joint.get("type"), "parent": joint.find("parent").get("link"),
                "xyz": _floats(origin.get("xyz") if origin is not None else None, (0, 0, 0)),
                "rpy": _floats(origin.get("rpy") if origin is not None else None, (0, 0, 0)),
                "axis": _floats(axis.get("xyz") if axis is not None else None, (1, 0, 0))}
        roots = [name for name in link_elements if name not in joints]
        if len(roots) != 1:
            raise ValueError(f"{urdf_path}: expected one root link, found {roots}")
        children = {}
        for child, joint in joints.items():
            children.setdefault(joint["parent"], []).append(child)
        self.links = []  # dicts: name, parent (index or -1), joint (dict or None), com (xyz in the link frame)
        order = [roots[0]]
        index = {}
        while order:
            name = order.pop(0)
            index[name] = len(self.links)
            joint = joints.get(name)
            inertial = link_elements[name].find("inertial")
            com_origin = inertial.find("origin") if inertial is not None else None
            mass = inertial.find("mass") if inertial is not None else None
            self.links.append({
                "name": name, "parent": index[joint["parent"]] if joint else -1, "joint": joint,
                "com": _floats(com_origin.get("xyz") if com_origin is not None else None, (0, 0, 0)),
                "mass": float(mass.get("value")) if mass is not None else 0.0})
            order.extend(children.get(name, []))
        self.index = index

    def description(self, coordinate_names):
        """What player.js needs: per link its parent, joint origin (xyz, quaternion w,x,y,z), joint axis and
        the index of its coordinate in q (-1 for fixed joints); the free base's q indexes."""
        column = {name: i for i, name in enumerate(coordinate_names)}
        links = []
        for link in self.links:
            joint = link["joint"]
            entry = {"name": link["name"], "parent": link["parent"], "com": link["com"], "mass": link["mass"]}
            if joint:
                entry.update({"joint": joint["name"], "type": joint["type"], "xyz": joint["xyz"],
                              "quaternion": matrix_quaternion(rpy_matrix(joint["rpy"])).tolist(),
                              "axis": joint["axis"],
                              "q": column.get(joint["name"], -1) if joint["type"] != "fixed" else -1})
            links.append(entry)
        base = [column.get(n, -1) for n in ("base_qw", "base_qx", "base_qy", "base_qz", "base_x", "base_y", "base_z")]
        return {"robot": self.name, "links": links, "base_q": base if min(base) >= 0 else None}

    def forward_kinematics(self, q, coordinate_names):
        """World rotations [T, links, 3, 3] and positions [T, links, 3] of every link frame for q [T, nq]."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        frames = q.shape[0]
        column = {name: i for i, name in enumerate(coordinate_names)}
        rotations = np.zeros((frames, len(self.links), 3, 3))
        positions = np.zeros((frames, len(self.links), 3))
        base = [column.get(n) for n in ("base_qw", "base_qx", "base_qy", "base_qz", "base_x", "base_y", "base_z")]
        for i, link in enumerate(self.links):
            joint = link["joint"]
            if joint is None:
                if None in base:  # a fixed root: the URDF's world frame
                    rotations[:, i] = np.eye(3)
                else:
                    rotations[:, i] = quaternion_matrices(q[:, base[:4]])
                    positions[:, i] = q[:, base[4:]]
                continue
            parent_rotation, parent_position = rotations[:, link["parent"]], positions[:, link["parent"]]
            origin_rotation = rpy_matrix(joint["rpy"])
            rotation = parent_rotation @ origin_rotation
            position = parent_position + parent_rotation @ np.asarray(joint["xyz"])
            if joint["type"] in ("revolute", "continuous") and joint["name"] in column:
                rotation = rotation @ axis_angle_matrices(joint["axis"], q[:, column[joint["name"]]])
            elif joint["type"] == "prismatic" and joint["name"] in column:
                axis = np.asarray(joint["axis"]) / np.linalg.norm(joint["axis"])
                position = position + (rotation @ axis) * q[:, column[joint["name"]], None]
            rotations[:, i], positions[:, i] = rotation, position
        return rotations, positions
