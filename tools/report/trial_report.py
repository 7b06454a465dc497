"""One trial's part of the report: Fig. 3 (momentum and segment boundaries), landmark errors over time,
contact phases, the worst frames, and the compact motion the 3-D player plays (REPORT/trials/ID/)."""
import base64
import json
import os
import tomllib

import numpy as np

import plotting
from files import open_hdf5, write_atomically
from urdf_fk import Robot, quaternion_matrices

# DESIGN.md's foot-sliding definition with syn-evaluate's defaults, for a motion that has no metrics.json.
DEFAULT_SLIDING = {"contact_height": 0.05, "slide_speed": 0.5, "slide_window": 0.05, "penetration": 0.01}
PLAYER_RATE_HZ = 60.0   # playback samples: enough for smooth motion at a fraction of a 120 Hz capture's bytes
WORST_FRAMES = 8        # rows in the worst-frames table


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read_motion(path):
    with open_hdf5(path) as file:
        motion = {"time": file["time"][()], "q": file["q"][()],
                  "coordinate_names": [_text(n) for n in file["coordinate_names"][()]]}
        if "landmark_names" in file:
            motion["landmark_names"] = [_text(n) for n in file["landmark_names"][()]]
            motion["landmark_targets"] = file["landmark_targets"][()]
            motion["landmark_error"] = file["landmark_error"][()]
        # The turn syn-retarget gave the capture to level its floor (identity when it did not).
        attrs = file.attrs
        if "floor_rotation_w" in attrs:
            turn = np.array([[float(attrs["floor_rotation_" + k]) for k in "wxyz"]])
            motion["floor_rotation"] = quaternion_matrices(turn)[0]
        else:
            motion["floor_rotation"] = np.eye(3)
        if "contact" in file:  # issue 17: contact[T, feet], with the feet's names when given
            motion["contact"] = np.asarray(file["contact"][()]).astype(bool)
            # The feet's names: the contact_feet dataset syn-retarget and syn-simulate write, else attributes.
            names = file["contact_feet"][()] if "contact_feet" in file else \
                file["contact"].attrs.get("feet", file.attrs.get("contact_feet"))
            motion["contact_names"] = [_text(n) for n in names] if names is not None else None
        if "contact_force" in file:  # [T, feet, 3] N: syn-retarget's force split, syn-simulate's ground forces
            motion["contact_force"] = file["contact_force"][()]
    return motion


def read_human(markers_path):
    """The captured human as a point tree: bodies (BVH joints, rigid bodies) with their parents when the
    file has them, else its labelled markers with no lines. Positions [T, N, 3] in the capture's frame."""
    with open_hdf5(markers_path) as file:
        if "body_pose" in file and file["body_pose"].shape[1] > 0:
            names = [_text(n) for n in file["bodies"][()]]
            parents = [_text(n) for n in file["body_parents"][()]] if "body_parents" in file else [""] * len(names)
            index = {name: i for i, name in enumerate(names)}
            return {"names": names, "parents": [index.get(p, -1) for p in parents],
                    "positions": file["body_pose"][:, :, :3]}
        names = [_text(n) for n in file["labels"][()]]
        return {"names": names, "parents": [-1] * len(names), "positions": file["points"][()]}


def read_feet(robot_map_path):
    """The robot map's [feet.SIDE] link and sole points (what syn-evaluate's foot sliding uses)."""
    with open(robot_map_path, "rb") as file:
        feet = tomllib.load(file).get("feet", {})
    return [(side, foot["link"], np.asarray(foot["sole_points"], dtype=float)) for side, foot in sorted(feet.items())]


def sole_kinematics(robot, motion, feet, options, kinematics=None):
    """Per foot: lowest sole-point height [T] and sole-centroid horizontal speed [T] over a centred window,
    as DESIGN.md's foot-sliding definition (evaluated at the motion's frames, not syn-evaluate's 1 kHz).
    `kinematics`: robot.forward_kinematics of the motion, when the caller has it already."""
    rotations, positions = kinematics or robot.forward_kinematics(motion["q"], motion["coordinate_names"])
    time = motion["time"]
    result = []
    for side, link, soles in feet:
        i = robot.index[link]
        points = positions[:, i, None, :] + np.einsum("tij,pj->tpi", rotations[:, i], soles)
        lowest = points[:, :, 2].min(axis=1)
        centroid = points[:, :, :2].mean(axis=1)
        speed = np.zeros(len(time))
        half = options["slide_window"] / 2
        for k in range(len(time)):
            a = np.searchsorted(time, time[k] - half)
            b = min(np.searchsorted(time, time[k] + half, side="right") - 1, len(time) - 1)
            if b <= a:  # a window shorter than the frame spacing (30 Hz captures): the neighbouring frames
                a, b = max(k - 1, 0), min(k + 1, len(time) - 1)
            if b > a:
                speed[k] = np.linalg.norm(centroid[b] - centroid[a]) / (time[b] - time[a])
        contact = lowest <= options["contact_height"]
        sliding = (contact & (speed > options["slide_speed"])) | (lowest < -options["penetration"])
        result.append({"side": side, "lowest": lowest, "speed": speed, "contact": contact, "sliding": sliding})
    return result


def _b64(array, dtype):
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode()


def momentum_figure(segments_path, motion, trial_id, stem):
    with open_hdf5(segments_path) as file:
        t, delta_p = file["analysis_time"][()], file["delta_p"][()]
        boundaries = file["boundaries"][()]
        threshold = float(file.attrs["threshold_used"])
    time = motion["time"]
    figure, axes = plotting.new_figure(8.0, 2.6)
    axes.plot(t, delta_p, color="#333", linewidth=0.8, label="ΔP(t)")
    axes.axhline(threshold, color="#c03030", linestyle="--", linewidth=1, label=f"ΔP_th = {threshold:.3g}")
    for b in boundaries[1:-1]:
        axes.axvline(time[min(int(b), len(time) - 1)], color="#3b6fb6", linewidth=0.8, alpha=0.7)
    axes.set_xlabel("time (s)")
    axes.set_ylabel("ΔP (generalized momentum)")
    axes.set_title(f"{trial_id}: momentum-based segmentation ({len(boundaries) - 1} segments, boundaries in blue)")
    axes.legend(frameon=False, loc="upper right", fontsize=8)
    plotting.save(figure, stem)
    return {"segments": int(len(boundaries) - 1), "threshold": threshold,
            "boundary_times": [round(float(time[min(int(b), len(time) - 1)]), 3) for b in boundaries]}


def landmark_error_figure(motion, trial_id, stem):
    figure, axes = plotting.new_figure(8.0, 2.8)
    if "landmark_error" not in motion:
        axes.text(0.5, 0.5, "not available: this motion was not retargeted from landmarks", ha="center",
                  transform=axes.transAxes)
    else:
        error = motion["landmark_error"][:, :, 0] * 1000.0
        for l, name in enumerate(motion["landmark_names"]):
            if np.isfinite(error[:, l]).any():
                axes.plot(motion["time"], error[:, l], linewidth=0.8, label=name)
        axes.set_ylabel("position error (mm)")
        axes.legend(frameon=False, fontsize=7, ncol=4, loc="upper right")
    axes.set_xlabel("time (s)")
    axes.set_title(f"{trial_id}: landmark position error (tracked robot link vs its target)")
    plotting.save(figure, stem)


def draw_contact(axes, motion, time_origin=0.0):
    """The motion file's contact phases on `axes`: a bar per foot where it is planted, named by the file's
    contact_feet (else foot N); time less `time_origin`."""
    contact = motion["contact"]
    names = motion.get("contact_names") or [f"foot {f}" for f in range(contact.shape[1])]
    time = motion["time"] - time_origin
    for f in range(contact.shape[1]):
        starts = np.flatnonzero(np.diff(np.concatenate([[0], contact[:, f].astype(int)])) == 1)
        ends = np.flatnonzero(np.diff(np.concatenate([contact[:, f].astype(int), [0]])) == -1)
        axes.broken_barh([(time[s], time[e] - time[s] + (time[1] - time[0] if len(time) > 1 else 0))
                          for s, e in zip(starts, ends)], (f - 0.4, 0.8), color="#2a9d8f")
    axes.set_yticks(range(contact.shape[1]))
    axes.set_yticklabels(names)


def contact_figure(motion, trial_id, stem):
    """The motion file's contact phases when it has them; the estimated ones are drawn in the player only."""
    figure, axes = plotting.new_figure(8.0, 1.6)
    if "contact" not in motion:
        axes.text(0.5, 0.5, "not available: motion.h5 has no contact dataset", ha="center", va="center",
                  transform=axes.transAxes)
        axes.set_yticks([])
    else:
        draw_contact(axes, motion)
    axes.set_xlabel("time (s)")
    axes.set_title(f"{trial_id}: contact phases")
    plotting.save(figure, stem)
    return "contact" in motion


def worst_frames(motion):
    if "landmark_error" not in motion:
        return []
    error = np.nan_to_num(motion["landmark_error"][:, :, 0], nan=-1.0)
    worst_landmark = error.argmax(axis=1)
    worst = error.max(axis=1)
    order = np.argsort(-worst, kind="stable")
    rows, used = [], []
    for k in order:  # distinct moments: skip frames within 0.25 s of one already listed
        if worst[k] < 0 or any(abs(motion["time"][k] - motion["time"][u]) < 0.25 for u in used):
            continue
        used.append(k)
        angle = motion["landmark_error"][k, worst_landmark[k], 1]
        rows.append({"frame": int(k), "time": round(float(motion["time"][k]), 3),
                     "landmark": motion["landmark_names"][worst_landmark[k]],
                     "error_mm": round(float(worst[k]) * 1000, 1),
                     "angle_deg": round(float(np.degrees(angle)), 1) if np.isfinite(angle) else None})
        if len(rows) == WORST_FRAMES:
            break
    return rows


def fit_human_alignment(human, motion, markerset_path):
    """Rotation about z, scale and offset taking the capture to the robot frame. syn-retarget's targets are
    link_reference + scale * heading * (sample - reference sample) per landmark, so the displacements of each
    landmark's body about its mean, pooled over landmarks and frames, give heading and scale by a 2-D
    Procrustes fit (yaw) and the ratio of spreads (scale); the offset puts the first landmark (the pelvis) on
    its targets' mean. A landmark is a body (BVH) or the mean of its origin markers (C3D, joints)."""
    with open(markerset_path, "rb") as file:
        entries = tomllib.load(file).get("landmark", [])
    names = {name: i for i, name in enumerate(human["names"])}

    def pick(alternatives):  # "A|B": the first name the capture has
        return next((names[n] for n in alternatives.split("|") if n in names), None)

    pairs = []  # (landmark index in motion.h5, the landmark's origin in the capture [T, 3])
    for entry in entries:
        if entry.get("name") not in motion.get("landmark_names", []):
            continue
        if "body" in entry:
            indexes = [pick(entry["body"])]
        else:  # marker-defined: the landmark's origin is the mean of its origin markers
            indexes = [pick(item) for item in entry.get("origin", [])]
        if indexes and None not in indexes:
            pairs.append((motion["landmark_names"].index(entry["name"]),
                          human["positions"][:, indexes].mean(axis=1)))
    # The capture turned as syn-retarget turned it to level its floor, then the yaw and scale fitted.
    floor = motion.get("floor_rotation", np.eye(3))
    levelled = [(landmark, p @ floor.T) for landmark, p in pairs]
    rotation, scale, heading = np.eye(3), 1.0, 0.0
    p_all, q_all = [], []
    for landmark, p in levelled:
        q = motion["landmark_targets"][:, landmark, :3]
        valid = np.isfinite(p).all(axis=1) & np.isfinite(q).all(axis=1)
        if valid.sum() > 1:
            p_all.append(p[valid] - p[valid].mean(axis=0))
            q_all.append(q[valid] - q[valid].mean(axis=0))
    if p_all:
        dp, dq = np.vstack(p_all), np.vstack(q_all)
        heading = np.arctan2((dp[:, 0] * dq[:, 1] - dp[:, 1] * dq[:, 0]).sum(), (dp[:, :2] * dq[:, :2]).sum())
        c, s = np.cos(heading), np.sin(heading)
        rotation = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        spread = np.sqrt((dp ** 2).sum())
        scale = float(np.sqrt((dq ** 2).sum()) / spread) if spread > 0 else 1.0
    offset = np.zeros(3)
    if levelled:
        landmark, p = levelled[0]
        q = motion["landmark_targets"][:, landmark, :3]
        valid = np.isfinite(p).all(axis=1) & np.isfinite(q).all(axis=1)
        if valid.any():
            offset = q[valid].mean(axis=0) - scale * rotation @ p[valid].mean(axis=0)
    # "rotation" takes capture coordinates to the robot's: the floor's turn, then the heading.
    return {"rotation": rotation @ floor, "scale": scale, "heading_deg": float(np.degrees(heading)), "offset": offset,
            "pairs": pairs}


def player_motion(trial_id, motion_class, style, motion, soles, has_contact, human=None):
    """The compact motion the 3-D player plays (trials/ID/motion.js): q, landmark targets, contact and
    sliding flags at <= PLAYER_RATE_HZ, and the human (positions [T, N, 3] already in the robot's frame) when
    given. Returns (that dict, the frame stride, the motion's rate, where its contacts came from, the
    per-frame sliding flags [T, feet])."""
    time = motion["time"]
    rate = (len(time) - 1) / (time[-1] - time[0]) if len(time) > 1 else PLAYER_RATE_HZ
    stride = max(1, int(round(rate / PLAYER_RATE_HZ)))
    picked = np.arange(0, len(time), stride)
    feet_contact = np.stack([s["contact"] for s in soles], axis=1) if soles else np.zeros((len(time), 0), bool)
    contact_source = "estimated"
    if has_contact and motion["contact"].shape[1] == feet_contact.shape[1]:
        # The file's columns in the robot map's order of feet (the player's), by name where the file names them.
        names = motion.get("contact_names")
        sides = [s["side"] for s in soles]
        order = [names.index(side) for side in sides] if names and set(sides) <= set(names) else list(range(len(sides)))
        feet_contact, contact_source = motion["contact"][:, order], "motion.h5"
    sliding = np.stack([s["sliding"] for s in soles], axis=1) if soles else np.zeros((len(time), 0), bool)

    # A frame the player skips still shows: a sample is flagged when any frame it stands for is.
    def spread(flags):
        out = np.zeros((len(picked), flags.shape[1]), dtype=np.uint8)
        for i, k in enumerate(picked):
            out[i] = flags[k:k + stride].any(axis=0)
        return out
    landmarks = None
    if "landmark_targets" in motion:
        targets = motion["landmark_targets"][picked, :, :3]
        landmarks = {"names": motion["landmark_names"], "positions": _b64(targets, "<f4")}
    human_export = None
    if human is not None:
        human_export = {"names": human["names"], "parents": human["parents"],
                        "positions": _b64(human["positions"][picked], "<f4"),
                        "scale": human["scale"], "heading_deg": human["heading_deg"]}
    player = {
        "id": trial_id, "motion_class": motion_class, "style": style,
        "frames": int(len(picked)), "nq": int(motion["q"].shape[1]),
        "time": _b64(time[picked] - time[0], "<f4"), "q": _b64(motion["q"][picked], "<f4"),
        "landmarks": landmarks, "human": human_export, "feet": [s["side"] for s in soles], "contact_source": contact_source,
        "contact": _b64(spread(feet_contact), "u1"), "sliding": _b64(spread(sliding), "u1"),
        "source_frames": picked.tolist()[:1] + [int(stride)]}
    return player, stride, rate, contact_source, sliding


def write_trial(trial, markers_path, markerset_path, motion_path, segments_path, urdf_path, robot_map_path, metrics_path, out_dir):
    """Writes every per-trial file into out_dir; trial.json (the page's summary of the trial) last."""
    os.makedirs(out_dir, exist_ok=True)
    motion = read_motion(motion_path)
    time = motion["time"]
    robot = Robot(urdf_path)
    with open(metrics_path) as file:
        metrics = json.load(file)
    sliding_options = metrics["parameters"] if "contact_height" in metrics.get("parameters", {}) else DEFAULT_SLIDING
    trial_id = trial["id"]
    fig3 = momentum_figure(segments_path, motion, trial_id, os.path.join(out_dir, "fig3"))
    landmark_error_figure(motion, trial_id, os.path.join(out_dir, "landmark_error"))
    has_contact = contact_figure(motion, trial_id, os.path.join(out_dir, "contact"))
    soles = sole_kinematics(robot, motion, read_feet(robot_map_path), sliding_options)

    # The human as captured, brought into the robot's frame by the heading, scale and offset syn-retarget
    # applied (fitted here from the landmark correspondences; the player adds its "beside" offset).
    human = read_human(markers_path)
    if human["positions"].shape[0] != len(time):
        raise ValueError(f"{markers_path}: {human['positions'].shape[0]} frames, {motion_path} has {len(time)}")
    alignment = fit_human_alignment(human, motion, markerset_path)
    human_positions = alignment["scale"] * np.einsum("ij,tnj->tni", alignment["rotation"], human["positions"]) \
        + alignment["offset"]
    # Scaled by height, the human's legs are shorter than the robot's: stand it on the ground (its lowest
    # point's 5th percentile over the trial at z = 0) so its steps read against the grid.
    lowest = np.nanmin(human_positions[:, :, 2], axis=1) if human_positions.shape[1] else np.zeros(1)
    if np.isfinite(lowest).any():
        human_positions[:, :, 2] -= np.nanpercentile(lowest, 5)
    human_track = {"names": human["names"], "parents": human["parents"], "positions": human_positions,
                   "scale": round(alignment["scale"], 4), "heading_deg": round(alignment["heading_deg"], 1)}
    player, stride, rate, contact_source, sliding = player_motion(
        trial_id, trial.get("motion_class", ""), trial.get("style", ""), motion, soles, has_contact, human_track)
    write_atomically(os.path.join(out_dir, "motion.js"),
                     "SynReport.addTrial(" + json.dumps(player, separators=(",", ":")) + ");\n")

    error = motion.get("landmark_error")
    summary = {
        "id": trial_id, "motion_class": trial.get("motion_class", ""), "style": trial.get("style", ""),
        "frames": int(len(time)), "duration_s": round(float(time[-1] - time[0]), 3), "rate_hz": round(float(rate), 2),
        "player_stride": int(stride), "fig3": fig3,
        "human_alignment": {"scale": human_track["scale"], "heading_deg": human_track["heading_deg"]}, "contact_dataset": has_contact,
        "contact_source": contact_source,
        "sliding_frames_estimated": int(sliding.any(axis=1).sum()),
        "foot_sliding_ratio": metrics.get("trial", {}).get("foot_sliding_ratio"),
        "mean_power_w_per_kg": metrics.get("trial", {}).get("mean_power_w_per_kg"),
        "median_landmark_error_mm": {name: round(float(np.nanmedian(error[:, l, 0])) * 1000, 1)
                                     for l, name in enumerate(motion["landmark_names"])
                                     if np.isfinite(error[:, l, 0]).any()} if error is not None else {},
        "worst_frames": worst_frames(motion)}
    # Last: make's target, so an interrupted job leaves no trial.json and reruns.
    write_atomically(os.path.join(out_dir, "trial.json"), json.dumps(summary, indent=1, sort_keys=True))

