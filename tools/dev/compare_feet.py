#!/usr/bin/env python3
"""Where a simulated motion put the feet, against its reference, by an FK independent of the stages.

  compare_feet.py REFERENCE.h5 MOTION.h5 [--png OUT.png] [--model URDF] [--robot-map MAP]

REFERENCE is the motion syn-simulate read (syn-retarget's), MOTION what it wrote or, for a fall, its
--fall-record (fewer frames: the reference is cut to them). Both are placed by tools/report/urdf_fk.py
(numpy, from the URDF), not by Simbody, so a stage's own measure of its landings can be checked against it.

Prints, per touchdown of the reference's contact flags (a foot planted at a frame after one where it was
not), how far the motion's sole centre stood from the reference's horizontally (mm), how far its heading
was turned (deg, signed: + counter-clockwise seen from above) and how high its lowest sole point was (mm),
all at the touchdown frame; then the medians and the largest. With --png, per foot the sole centre's x and
y, the lowest sole point's height and the heading against time, and the pelvis's x, y and heading, the
reference dotted, the reference's stance phases shaded: the plot the issue notes ask for of every
motion-producing change.
"""
import argparse
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
from contact_check import sole_points  # noqa: E402
from trial_report import read_feet, read_motion  # noqa: E402
from urdf_fk import Robot  # noqa: E402


def foot_tracks(robot, motion, feet):
    """Per foot: sole centre [T, 3] (the mean of its sole points), lowest sole point's z [T], heading [T]
    (rad, unwrapped: the link's x axis about the vertical); and, as "pelvis", the root link's position and
    heading."""
    rotations, positions = robot.forward_kinematics(motion["q"], motion["coordinate_names"])
    tracks = {}
    for side, link, soles in feet:
        i = robot.index[link]
        points = sole_points(rotations[:, i], positions[:, i], soles)
        heading = np.unwrap(np.arctan2(rotations[:, i, 1, 0], rotations[:, i, 0, 0]))
        tracks[side] = (points.mean(axis=1), points[:, :, 2].min(axis=1), heading)
    root = 0  # Robot's links are in tree order: the root link (a free base's pelvis) first
    tracks["pelvis"] = (positions[:, root], None, np.unwrap(np.arctan2(rotations[:, root, 1, 0], rotations[:, root, 0, 0])))
    return tracks


def touchdowns(reference, frames):
    """(frame, foot column) of every touchdown in the reference's contact flags within `frames`."""
    contact = reference.get("contact")
    if contact is None:
        return []
    contact = contact[:frames]
    return [(t + 1, f) for t, f in np.argwhere(contact[1:] & ~contact[:-1])]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("reference")
    parser.add_argument("motion")
    parser.add_argument("--png")
    parser.add_argument("--model", default=os.path.join(ROOT, "datasets/robots/unitree_g1/g1_29dof.urdf"))
    parser.add_argument("--robot-map", default=os.path.join(ROOT, "manifests/robots/g1.toml"))
    args = parser.parse_args()
    robot = Robot(args.model)
    feet = read_feet(args.robot_map)
    reference, motion = read_motion(args.reference), read_motion(args.motion)
    frames = len(motion["time"])
    if frames > len(reference["time"]) or not np.allclose(motion["time"], reference["time"][:frames], atol=1e-9):
        sys.exit(f"compare_feet: {args.motion}'s frame times are not {args.reference}'s (or a first part of them)")
    if motion["coordinate_names"] != reference["coordinate_names"]:
        sys.exit(f"compare_feet: {args.motion} and {args.reference} have different coordinates")
    reference = dict(reference, q=reference["q"][:frames], time=reference["time"][:frames])
    ours, theirs = foot_tracks(robot, motion, feet), foot_tracks(robot, reference, feet)
    names = reference.get("contact_names") or [side for side, _, _ in feet]

    distances, turns = [], []
    print("touchdown  foot   moved_mm  turned_deg  lowest_mm")
    for t, f in touchdowns(reference, frames):
        side = names[f]
        if side not in ours:
            continue
        centre, lowest, heading = ours[side]
        ref_centre, _, ref_heading = theirs[side]
        moved = np.linalg.norm(centre[t, :2] - ref_centre[t, :2]) * 1000
        turned = np.degrees(np.remainder(heading[t] - ref_heading[t] + np.pi, 2 * np.pi) - np.pi)
        distances.append(moved)
        turns.append(abs(turned))
        print(f"{motion['time'][t]:9.3f}  {side:5s}  {moved:9.1f}  {turned:10.1f}  {lowest[t] * 1000:9.1f}")
    if distances:
        print(f"{len(distances)} touchdowns: sole centre {np.median(distances):.1f} mm from the reference's median, "
              f"{max(distances):.1f} at most; heading {np.median(turns):.1f} deg off median, {max(turns):.1f} at most")
    else:
        print("no touchdown in the reference's contact flags")

    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        time = motion["time"]
        figure, axes = plt.subplots(6, 1, figsize=(12, 15), sharex=True)
        colours = {side: colour for (side, _, _), colour in zip(feet, ("tab:blue", "tab:red", "tab:green", "tab:orange"))}
        for side, _, _ in feet:
            c = colours[side]
            for k, what in ((0, "x"), (1, "y")):
                axes[k].plot(time, theirs[side][0][:, k], ":", color=c, label=f"{side} reference")
                axes[k].plot(time, ours[side][0][:, k], "-", color=c, label=f"{side} motion")
                axes[k].set_ylabel(f"sole centre {what} (m)")
            axes[2].plot(time, theirs[side][1] * 1000, ":", color=c)
            axes[2].plot(time, ours[side][1] * 1000, "-", color=c)
            axes[3].plot(time, np.degrees(theirs[side][2]), ":", color=c)
            axes[3].plot(time, np.degrees(ours[side][2]), "-", color=c)
        axes[2].set_ylabel("lowest sole point (mm)")
        axes[3].set_ylabel("heading (deg)")
        for k, c in ((0, "black"), (1, "tab:gray")):
            axes[4].plot(time, theirs["pelvis"][0][:, k], ":", color=c)
            axes[4].plot(time, ours["pelvis"][0][:, k], "-", color=c, label="xy"[k])
        axes[4].set_ylabel("pelvis (m)")
        axes[4].legend(loc="upper left")
        axes[5].plot(time, np.degrees(theirs["pelvis"][2]), ":", color="black")
        axes[5].plot(time, np.degrees(ours["pelvis"][2]), "-", color="black")
        axes[5].set_ylabel("pelvis heading (deg)")
        axes[5].set_xlabel("time (s)")
        contact = reference.get("contact")
        if contact is not None:
            for f in range(contact.shape[1]):
                c = colours.get(names[f], "tab:gray")
                for axis in axes:
                    axis.fill_between(time, 0, 1, where=contact[:frames, f], color=c, alpha=0.07,
                                      transform=axis.get_xaxis_transform())
        axes[0].legend(loc="upper left")
        figure.suptitle(f"{os.path.basename(args.motion)} (solid) against {os.path.basename(args.reference)} (dotted)")
        figure.tight_layout()
        figure.savefig(args.png, dpi=70)
        print(f"plot: {args.png}")


if __name__ == "__main__":
    main()
