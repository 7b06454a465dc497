#!/usr/bin/env python3
"""The report's numpy forward kinematics (tools/report/urdf_fk.py) against syn-retarget's own (Simbody).

syn-retarget stores, per frame and landmark task, the target pose (landmark_targets) and the distance and
rotation angle between it and the tracked link's frame as Simbody placed it (landmark_error). Recomputing
both from q with the report's FK must give the same numbers: this checks the URDF parsing, the joint order,
the free-base quaternion convention and every joint origin and axis on the links the tasks track.

  check_fk.py MANIFEST OUTPUTS [EXPECTED_JSON]

It also checks the sliding frames the player highlights against syn-evaluate's foot-sliding ratio, and the
human shown beside the robot: the heading and scale trial_report.py fits must carry each
landmark's captured motion exactly onto its targets' motion, as syn-retarget's targets are built.

EXPECTED_JSON (optional): link world positions at a few player frames, for the browser test to compare
player.js's FK against.
"""
import json
import os
import sys
import tomllib

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
from urdf_fk import Robot, quaternion_matrices  # noqa: E402
from trial_report import (PLAYER_RATE_HZ, fit_human_alignment, read_feet, read_human, read_motion,  # noqa: E402
                          sole_kinematics)

POSITION_TOLERANCE = 1e-6   # m: both sides are float64 FK of the same q
ANGLE_TOLERANCE = 1e-6      # rad
ALIGNMENT_TOLERANCE = 1e-9  # m: syn-retarget's targets are an exact similarity transform of the capture
SLIDING_TOLERANCE = 0.03    # the player's sliding frames (motion frames) vs syn-evaluate's ratio (1 kHz)


def main():
    manifest_path, outputs = sys.argv[1], sys.argv[2]
    with open(manifest_path, "rb") as file:
        manifest = tomllib.load(file)
    with open(manifest["robot_map"], "rb") as file:
        tasks = tomllib.load(file)["task"]
    robot = Robot(manifest["model"])
    expected = {}
    worst_position = worst_angle = 0.0
    compared = aligned = 0
    worst_alignment = worst_sliding = 0.0
    for trial in manifest["trial"]:
        path = os.path.join(outputs, manifest["name"], "trials", trial["id"], "motion.h5")
        with h5py.File(path, "r") as file:
            q, time = file["q"][()], file["time"][()]
            names = [n.decode() if isinstance(n, bytes) else n for n in file["coordinate_names"][()]]
            targets, errors = file["landmark_targets"][()], file["landmark_error"][()]
        rotations, positions = robot.forward_kinematics(q, names)
        for i, task in enumerate(tasks):
            link = robot.index[task["link"]]
            position_error = np.linalg.norm(positions[:, link] - targets[:, i, :3], axis=1)
            valid = np.isfinite(errors[:, i, 0])
            if valid.any():
                difference = np.abs(position_error[valid] - errors[valid, i, 0]).max()
                worst_position = max(worst_position, difference)
                compared += int(valid.sum())
            valid = np.isfinite(errors[:, i, 1]) & np.isfinite(targets[:, i, 3])
            if valid.any():
                relative = np.einsum("tji,tjk->tik", rotations[valid, link], quaternion_matrices(targets[valid, i, 3:]))
                cosine = np.clip((np.trace(relative, axis1=1, axis2=2) - 1) / 2, -1, 1)
                worst_angle = max(worst_angle, np.abs(np.arccos(cosine) - errors[valid, i, 1]).max())
        # The human drawn beside the robot: the fitted heading and scale must carry every landmark's capture
        # motion onto its targets' motion (each landmark keeps its own constant offset).
        trial_dir = os.path.dirname(path)
        motion, human = read_motion(path), read_human(os.path.join(trial_dir, "markers.h5"))
        alignment = fit_human_alignment(human, motion, manifest["markerset"])
        for landmark, capture in alignment["pairs"]:
            moved = alignment["scale"] * capture @ alignment["rotation"].T
            target = targets[:, landmark, :3]
            valid = np.isfinite(target).all(axis=1) & np.isfinite(moved).all(axis=1)
            residual = (target[valid] - target[valid].mean(axis=0)) - (moved[valid] - moved[valid].mean(axis=0))
            worst_alignment = max(worst_alignment, np.abs(residual).max())
            aligned += 1
        # The sliding frames the player highlights against syn-evaluate's foot-sliding ratio.
        with open(os.path.join(trial_dir, "metrics.json")) as file:
            metrics = json.load(file)
        soles = sole_kinematics(robot, motion, read_feet(manifest["robot_map"]), metrics["parameters"])
        sliding = np.any([sole["sliding"] for sole in soles], axis=0).mean()
        worst_sliding = max(worst_sliding, abs(sliding - metrics["trial"]["foot_sliding_ratio"]))
        rate = (len(time) - 1) / (time[-1] - time[0])
        stride = max(1, int(round(rate / PLAYER_RATE_HZ)))
        player_frames = [0, (len(time) - 1) // stride // 2]
        expected[trial["id"]] = {str(k): positions[k * stride].tolist() for k in player_frames}
    print(f"check_fk: {compared} landmark samples; report FK vs syn-retarget: worst position difference "
          f"{worst_position:.2e} m, worst angle difference {worst_angle:.2e} rad")
    print(f"check_fk: human alignment on {aligned} landmark tracks: worst residual {worst_alignment:.2e} m")
    print(f"check_fk: sliding frames vs syn-evaluate's foot-sliding ratio: worst difference {worst_sliding:.3f}")
    if len(sys.argv) > 3:
        with open(sys.argv[3], "w") as file:
            json.dump({"links": [link["name"] for link in robot.links], "frames": expected}, file)
    if (compared == 0 or worst_position > POSITION_TOLERANCE or worst_angle > ANGLE_TOLERANCE or aligned == 0 or
            worst_alignment > ALIGNMENT_TOLERANCE or worst_sliding > SLIDING_TOLERANCE):
        print("check_fk: FAILED", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
