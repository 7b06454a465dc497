#!/usr/bin/env python3
"""Link world positions by the numpy FK (tools/report/urdf_fk.py) at the player frames the watch-page test
compares player.js against: the first, the middle and the last of each motion's player samples.

  watch_fk.py URDF OUT_JSON MOTION.h5 [MOTION.h5 ...]
"""
import json
import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
from trial_report import PLAYER_RATE_HZ, read_motion  # noqa: E402
from urdf_fk import Robot  # noqa: E402
from watch import motion_id  # noqa: E402


def main():
    urdf, out_path, motions = sys.argv[1], sys.argv[2], sys.argv[3:]
    robot = Robot(urdf)
    expected = {}
    for path in motions:
        motion = read_motion(path)
        time = motion["time"]
        _, positions = robot.forward_kinematics(motion["q"], motion["coordinate_names"])
        rate = (len(time) - 1) / (time[-1] - time[0]) if len(time) > 1 else PLAYER_RATE_HZ
        stride = max(1, int(round(rate / PLAYER_RATE_HZ)))
        samples = (len(time) - 1) // stride + 1
        expected[motion_id(path)] = {str(k): positions[k * stride].tolist() for k in (0, (samples - 1) // 2, samples - 1)}
    with open(out_path, "w") as file:
        json.dump({"links": [link["name"] for link in robot.links], "frames": expected}, file)
    return 0


if __name__ == "__main__":
    sys.exit(main())
