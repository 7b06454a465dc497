#!/usr/bin/env python3
"""Issue 17's floor and stance figures of retargeted motions, by the report's numpy FK (urdf_fk.py), which
shares no code with syn-retarget.

  contact_check.py URDF ROBOT_MAP MOTION.h5 [MOTION.h5 ...] [--plot DIR] [--json OUT]

Per motion: the share of frames with a sole point more than 1 cm below z = 0 and the deepest point; per
source contact phase (motion.h5 `contact`), the sole centre's largest horizontal distance from where the phase
began (median and p95 over the phases) and its lowest sole point's largest height above the floor (a planted
foot that lands late or hops; median, p95 and max over the phases); GMD's foot-skating ratio (lowest sole point within 5 cm, sole centre
faster than 0.5 m/s over a centred 0.05 s window) of the robot and of the source's foot targets
(landmark_targets, the capture scaled to the robot, with the robot's soles, lowered so the planted frames'
median lowest point is on the floor); the knees' lowest angle. With --plot, one PNG per motion: sole height,
sole centre x and y of each foot against time, the source's contact phases shaded.
"""
import argparse
import json
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trial_report import read_feet, read_motion  # noqa: E402
from urdf_fk import Robot, quaternion_matrices  # noqa: E402

SKATING = {"contact_height": 0.05, "slide_speed": 0.5, "slide_window": 0.05}


def phases(contact):
    """[(begin, end)) runs of True."""
    runs, begin = [], None
    for t, planted in enumerate(list(contact) + [False]):
        if planted and begin is None:
            begin = t
        elif not planted and begin is not None:
            runs.append((begin, t))
            begin = None
    return runs


def centred_speed(time, centre):
    speed = np.zeros(len(time))
    half = SKATING["slide_window"] / 2
    for k in range(len(time)):
        a = np.searchsorted(time, time[k] - half)
        b = min(np.searchsorted(time, time[k] + half, side="right") - 1, len(time) - 1)
        if b <= a:
            a, b = max(k - 1, 0), min(k + 1, len(time) - 1)
        if b > a:
            speed[k] = np.linalg.norm(centre[b] - centre[a]) / (time[b] - time[a])
    return speed


def skating(time, feet):
    """GMD ratio over frames: any foot low and fast. feet: [(lowest [T], centre [T, 2])]."""
    flags = np.zeros(len(time), dtype=bool)
    for lowest, centre in feet:
        flags |= (lowest <= SKATING["contact_height"]) & (centred_speed(time, centre) > SKATING["slide_speed"])
    return float(flags.mean()) if len(time) else 0.0


def over_phases(name, values):
    """Median, p95 and max (mm) of per-phase values in m, 0 when there are none."""
    if not values:
        return {f"{name}_median_mm": 0.0, f"{name}_p95_mm": 0.0, f"{name}_max_mm": 0.0}
    return {f"{name}_median_mm": float(np.median(values) * 1000),
            f"{name}_p95_mm": float(np.percentile(values, 95, method="inverted_cdf") * 1000),
            f"{name}_max_mm": float(max(values) * 1000)}


def sole_points(rotations, positions, soles):
    return positions[:, None, :] + np.einsum("tij,pj->tpi", rotations, soles)


def check(robot, feet, path, plot_dir):
    motion = read_motion(path)
    time, q, names = motion["time"], motion["q"], motion["coordinate_names"]
    rotations, positions = robot.forward_kinematics(q, names)
    contact = motion.get("contact")
    with h5py.File(path, "r") as file:
        contact_feet = [n.decode() if isinstance(n, bytes) else str(n) for n in file["contact_feet"][()]] \
            if "contact_feet" in file else [side for side, _, _ in feet]
    result = {"motion": path, "frames": len(time)}
    lowest_all = np.full(len(time), np.inf)
    robot_feet, source_feet, drifts, lifts, per_foot = [], [], [], [], {}
    for side, link, soles in feet:
        i = robot.index[link]
        points = sole_points(rotations[:, i], positions[:, i], soles)
        lowest = points[:, :, 2].min(axis=1)
        centre = points[:, :, :2].mean(axis=1)
        lowest_all = np.minimum(lowest_all, lowest)
        robot_feet.append((lowest, centre))
        f = contact_feet.index(side) if side in contact_feet else -1
        planted = contact[:, f] if contact is not None and f >= 0 else np.zeros(len(time), dtype=bool)
        for begin, end in phases(planted):
            drifts.append(float(np.max(np.linalg.norm(centre[begin:end] - centre[begin], axis=1))))
            lifts.append(float(max(0.0, np.max(lowest[begin:end]))))
        per_foot[side] = (lowest, centre, planted)
        task = motion.get("landmark_names", []).index(f"{side}_foot") if f"{side}_foot" in motion.get("landmark_names", []) else -1
        if task >= 0:
            target = motion["landmark_targets"][:, task]
            valid = np.isfinite(target[:, 3])
            rotation = np.tile(np.eye(3), (len(time), 1, 1))
            rotation[valid] = quaternion_matrices(target[valid, 3:7])
            source_points = sole_points(rotation, target[:, :3], soles)
            source_feet.append([source_points[:, :, 2].min(axis=1), source_points[:, :, :2].mean(axis=1), planted])
    levels = np.concatenate([lowest[planted] for lowest, _, planted in source_feet]) if source_feet else np.array([])
    level = float(np.median(levels)) if levels.size else 0.0
    knee_columns = [k for k, n in enumerate(names) if "knee" in n.lower()]
    result.update({
        "penetrating_frames": float(np.mean(lowest_all < -0.01)),
        "deepest_mm": float(max(0.0, -lowest_all.min()) * 1000),
        "phases": len(drifts),
        **over_phases("drift", drifts),
        **over_phases("lift", lifts),
        "skating": skating(time, robot_feet),
        "source_skating": skating(time, [(lowest - level, centre) for lowest, centre, _ in source_feet]),
        "lowest_knee_rad": float(q[:, knee_columns].min()) if knee_columns else None,
    })
    if plot_dir:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        figure, axes = plt.subplots(3, 1, figsize=(12, 8), sharex=True)
        for side, (lowest, centre, planted) in per_foot.items():
            line, = axes[0].plot(time, lowest * 1000, label=f"{side} lowest sole point")
            axes[1].plot(time, centre[:, 0], color=line.get_color(), label=f"{side} sole centre x")
            axes[2].plot(time, centre[:, 1], color=line.get_color(), label=f"{side} sole centre y")
            for begin, end in phases(planted):
                for axis in axes:
                    axis.axvspan(time[begin], time[end - 1], color=line.get_color(), alpha=0.12)
        axes[0].axhline(0, color="k", lw=0.5)
        axes[0].axhline(-10, color="r", lw=0.5, ls="--")
        axes[0].set_ylabel("mm")
        axes[1].set_ylabel("m")
        axes[2].set_ylabel("m")
        axes[2].set_xlabel("s")
        for axis in axes:
            axis.legend(loc="upper right", fontsize=7)
        axes[0].set_title(os.path.basename(path))
        figure.tight_layout()
        os.makedirs(plot_dir, exist_ok=True)
        figure.savefig(os.path.join(plot_dir, os.path.basename(path).replace(".h5", ".png")), dpi=80)
        plt.close(figure)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("urdf")
    parser.add_argument("robot_map")
    parser.add_argument("motions", nargs="+")
    parser.add_argument("--plot")
    parser.add_argument("--json")
    args = parser.parse_args()
    robot = Robot(args.urdf)
    feet = read_feet(args.robot_map)
    results = [check(robot, feet, path, args.plot) for path in args.motions]
    print(f"{'motion':40s} {'pen%':>6s} {'deep':>6s} {'drift50':>8s} {'drift95':>8s} {'skate':>6s} {'source':>6s} {'knee':>6s}"
          f" {'lift95':>7s} {'liftmax':>7s}")
    for r in results:
        print(f"{os.path.basename(r['motion']):40s} {100 * r['penetrating_frames']:6.2f} {r['deepest_mm']:6.1f} "
              f"{r['drift_median_mm']:8.1f} {r['drift_p95_mm']:8.1f} {r['skating']:6.3f} {r['source_skating']:6.3f} "
              f"{r['lowest_knee_rad'] if r['lowest_knee_rad'] is not None else float('nan'):6.3f}"
              f" {r['lift_p95_mm']:7.1f} {r['lift_max_mm']:7.1f}")
    if args.json:
        with open(args.json, "w") as file:
            json.dump(results, file, indent=1)


if __name__ == "__main__":
    main()
