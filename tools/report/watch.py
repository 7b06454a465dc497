#!/usr/bin/env python3
"""Watch motion files that are not a report's trials: the 3-D player and a height plot for each.

  watch.py MOTION.h5 [MOTION.h5 ...] --model URDF --robot-map MAP [-o DIR]   (make watch MOTION="...")

The report plays an archive's trials only, and the pipeline stops at a fall, so a ground-mode fall
(`syn-simulate --contact ground --fall-record F.h5`), a simulated motion set beside its kinematic input, or a
single `syn-retarget` or `syn-compose` output could not be looked at. This page plays any of them with the
report's player (the robot from its URDF, its feet green in contact and red while sliding, the landmark
targets in magenta, which for a simulated motion are the retargeter's targets it tracked) and plots, per
motion, by forward kinematics independent of the stages: each foot's lowest sole point and the root link's
height over time, and the vertical sole forces when the file has them (syn-simulate's ground mode).
No network: open DIR/index.html from file://. Outputs are written to temporary names and renamed.
"""
import argparse
import html
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import page  # noqa: E402  (after the path is set)
import plotting  # noqa: E402
from files import THREE, write_atomically  # noqa: E402
from trial_report import DEFAULT_SLIDING, draw_contact, player_motion, read_feet, read_motion, sole_kinematics  # noqa: E402
from urdf_fk import Robot  # noqa: E402



def motion_id(path):
    name = os.path.basename(path)
    return name[:-3] if name.endswith(".h5") else name


def heights_figure(motion_name, motion, soles, root_height, forces, stem):
    """Against time: where the file marks each foot in contact (when it has a contact dataset), each foot's
    lowest sole point (mm), the root link's height (m), and the vertical sole forces when given."""
    time = motion["time"] - motion["time"][0]
    contact = motion.get("contact")
    rows = [row for row, present in (("contact", contact is not None), ("soles", True), ("root", True),
                                      ("forces", forces is not None)) if present]
    ratios = {"contact": 0.35, "soles": 1.0, "root": 1.0, "forces": 1.0}
    figure, axes_list = plotting.new_figure(8.0, 0.4 + sum(1.9 * ratios[r] for r in rows), rows=len(rows), sharex=True,
                                            gridspec_kw={"height_ratios": [ratios[r] for r in rows]})
    axes = dict(zip(rows, np.atleast_1d(axes_list)))
    colours = ["#3b6fb6", "#c0392b", "#2a9d8f", "#8e44ad"]
    sides = [sole["side"] for sole in soles]
    if contact is not None:
        draw_contact(axes["contact"], motion, motion["time"][0])
        axes["contact"].set_ylabel("contact", fontsize=8)
    for f, sole in enumerate(soles):
        axes["soles"].plot(time, sole["lowest"] * 1000.0, color=colours[f % len(colours)], linewidth=0.9,
                           label=f"{sole['side']} foot")
    axes["soles"].axhline(0.0, color="#555", linewidth=0.6)
    axes["soles"].set_ylabel("lowest sole point (mm)")
    axes["soles"].legend(frameon=False, fontsize=7, loc="upper right")
    axes[rows[0]].set_title(f"{motion_name}: feet and root height by forward kinematics (URDF, not the stage's)")
    axes["root"].plot(time, root_height, color="#333", linewidth=0.9)
    axes["root"].set_ylabel("root link height (m)")
    if forces is not None:
        for f in range(forces.shape[1]):
            side = sides[f] if f < len(sides) else str(f)
            axes["forces"].plot(time, forces[:, f], color=colours[f % len(colours)], linewidth=0.8, label=f"{side} foot")
        axes["forces"].set_ylabel("vertical sole force (N)")
        axes["forces"].legend(frameon=False, fontsize=7, loc="upper right")
    axes[rows[-1]].set_xlabel("time (s)")
    plotting.save(figure, stem)


def watch(paths, model_path, robot_map_path, out_dir):
    ids = [motion_id(p) for p in paths]
    repeated = sorted({i for i in ids if ids.count(i) > 1})
    if repeated:
        raise ValueError(f"two motion files are both named {repeated[0]}.h5: the player tells motions apart by name")
    robot = Robot(model_path)
    feet = read_feet(robot_map_path)
    motions = [read_motion(p) for p in paths]
    names = motions[0]["coordinate_names"]
    for path, motion in zip(paths, motions):
        if motion["coordinate_names"] != names:
            raise ValueError(f"{path}: its coordinates are not {paths[0]}'s: one page plays one robot")
        if len(motion["time"]) == 0:
            raise ValueError(f"{path}: no frames")
    os.makedirs(out_dir, exist_ok=True)
    root = next(i for i, link in enumerate(robot.links) if link["joint"] is None)
    rows, trial_list, sections = [], [], []
    for path, motion_name, motion in zip(paths, ids, motions):
        trial_dir = os.path.join(out_dir, "trials", motion_name)
        os.makedirs(trial_dir, exist_ok=True)
        kinematics = robot.forward_kinematics(motion["q"], motion["coordinate_names"])
        soles = sole_kinematics(robot, motion, feet, DEFAULT_SLIDING, kinematics)
        has_contact = "contact" in motion
        player, stride, rate, contact_source, _ = player_motion(motion_name, "", "", motion, soles, has_contact)
        write_atomically(os.path.join(trial_dir, "motion.js"),
                         "SynReport.addTrial(" + json.dumps(player, separators=(",", ":")) + ");\n")
        root_height = kinematics[1][:, root, 2]
        forces = motion["contact_force"][:, :, 2] if "contact_force" in motion else None
        heights_figure(motion_name, motion, soles, root_height, forces, os.path.join(trial_dir, "heights"))
        deepest = min(float(s["lowest"].min()) for s in soles) * 1000.0 if soles else float("nan")
        duration = float(motion["time"][-1] - motion["time"][0])
        trial_list.append({"id": motion_name, "label": motion_name})
        rows.append([f'<a href="#motion-{html.escape(motion_name)}">{html.escape(motion_name)}</a>',
                     html.escape(os.path.relpath(path)), len(motion["time"]), f"{duration:.3f}", f"{rate:.1f}",
                     f"{deepest:.1f}", f"{root_height.min():.3f} – {root_height.max():.3f}",
                     contact_source])
        sections.append(
            f'<article id="motion-{html.escape(motion_name)}"><h3>{html.escape(motion_name)} '
            f'<button class="play" data-trial="{html.escape(motion_name)}" data-time="0">play in 3-D</button></h3>'
            f'<figure><img src="trials/{html.escape(motion_name)}/heights.png" alt="{html.escape(motion_name)} heights">'
            f'<figcaption>Per foot, the lowest of the robot map\'s sole points and, below, the root link\'s height, '
            f'by tools/report/urdf_fk.py from q; on top, the frames the file marks each foot in contact (when it has '
            f'a contact dataset){"; at the bottom, syn-simulate&#39;s vertical ground force per foot" if forces is not None else ""}. '
            f'<a href="trials/{html.escape(motion_name)}/heights.svg">SVG</a></figcaption></figure>'
            f'<p class="note">{len(motion["time"])} frames at {rate:.1f} Hz (the player samples one in {stride}).</p>'
            "</article>")
    page.write_player_assets(out_dir, THREE, HERE, model_path, robot_map_path, names)
    command = "tools/report/watch.py " + " ".join(os.path.relpath(p) for p in paths) + \
        f" --model {model_path} --robot-map {robot_map_path} -o {os.path.relpath(out_dir)}"
    body = [f"<header><h1>synsculpt watch: {len(paths)} motion{'s' if len(paths) != 1 else ''}</h1>",
            f"<p>Robot <code>{html.escape(model_path)}</code>, feet from <code>{html.escape(robot_map_path)}</code>. "
            f"Regenerate: <code>{html.escape(command)}</code>. No captured human is drawn here (the report "
            "draws it beside its trials).</p></header>",
            page.PLAYER_SECTION,
            '<section id="trials"><h2>Motions</h2>',
            page.html_table(["motion", "file", "frames", "duration (s)", "rate (Hz)", "deepest sole point (mm)",
                         "root height (m)", "contacts"], rows, escape=False)]
    body += sections
    body.append("</section>")
    text = ('<!doctype html>\n<html lang="en"><head><meta charset="utf-8"><title>synsculpt watch</title>'
            '<link rel="stylesheet" href="report.css"></head><body>\n' + "\n".join(body) + "\n" +
            page.page_scripts(trial_list) + "</body></html>\n")
    write_atomically(os.path.join(out_dir, "index.html"), text)
    return os.path.join(out_dir, "index.html")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("motions", nargs="+", help="motion files (syn-retarget, syn-simulate, syn-compose, ...)")
    parser.add_argument("--model", required=True, help="the robot URDF the motions were made with")
    parser.add_argument("--robot-map", required=True, help="its robot map (the feet's sole points)")
    parser.add_argument("-o", "--output", default="outputs/watch", help="folder of the page (default outputs/watch)")
    args = parser.parse_args()
    if not os.path.exists(THREE):
        print(f"watch.py: {os.path.relpath(THREE)} is missing: run `make report-npm`", file=sys.stderr)
        return 1
    try:
        index = watch(args.motions, args.model, args.robot_map, args.output)
    except (OSError, KeyError, ValueError, IndexError) as error:  # h5py raises KeyError for missing datasets
        print(f"watch.py: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    print(f"watch.py: open {index}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
