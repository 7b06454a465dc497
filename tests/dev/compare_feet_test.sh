#!/usr/bin/env bash
# CTest compare_feet: tools/dev/compare_feet.py on CMU 02_01 retargeted onto the G1, against copies of it
# moved by known amounts, so that what it prints is checked by arithmetic of the test's own, not by its FK:
# the motion against itself lands every foot where the reference has it; the whole body moved by
# (0.1, −0.05) m lands each 111.8 mm off and not turned; the whole body turned by 0.3 rad about the vertical
# lands each turned +17.19°, its sole centre 2·r·sin(0.15) off, r its distance from the axis (from the
# reference's own FK, which the turn does not change); the first half of the frames (a fall record) lists
# only the touchdowns within it; frame times that are not the reference's are refused. Exit 77 = skipped
# (no shared datasets).
set -euo pipefail
cd "$(dirname "$0")/../.."
build_dir=${1:-build}
python=${PYTHON:-/usr/bin/python3}
fail() { echo "FAIL: $*"; exit 1; }
bvh=../shared/datasets/cmu_bvh/02/02_01.bvh
if [ ! -f $bvh ]; then
  echo "SKIP: $bvh is absent"
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/compare_feet_test.XXXXXX")
trap 'rm -rf "$work"' EXIT

$build_dir/bin/syn-ingest $bvh --drop-first-frame -o $work/markers.h5 2> $work/ingest.log || fail "ingest: $(cat $work/ingest.log)"
$build_dir/bin/syn-retarget $work/markers.h5 -o $work/reference.h5 --model datasets/robots/unitree_g1/g1_29dof.urdf \
  --robot-map manifests/robots/g1.toml --markerset manifests/markersets/cmu-bvh.toml 2> $work/retarget.log ||
  fail "retarget: $(cat $work/retarget.log)"

# The copies: moved, turned, cut.
"$python" - $work <<'COPIES'
import shutil, sys
import h5py, numpy as np
work = sys.argv[1]
def copy(name, change):
    shutil.copy(f"{work}/reference.h5", f"{work}/{name}.h5")
    with h5py.File(f"{work}/{name}.h5", "r+") as file:
        names = [n.decode() if isinstance(n, bytes) else n for n in file["coordinate_names"][()]]
        q = file["q"][()]
        change(q, {n: i for i, n in enumerate(names)})
        file["q"][...] = q
def moved(q, c):
    q[:, c["base_x"]] += 0.1
    q[:, c["base_y"]] -= 0.05
def turned(q, c):
    angle = 0.3
    cos, sin = np.cos(angle), np.sin(angle)
    x, y = q[:, c["base_x"]].copy(), q[:, c["base_y"]].copy()
    q[:, c["base_x"]], q[:, c["base_y"]] = cos * x - sin * y, sin * x + cos * y
    # The turn's quaternion (cos 0.15, 0, 0, sin 0.15) times the base's (w, x, y, z).
    w0, z0 = np.cos(angle / 2), np.sin(angle / 2)
    w, qx, qy, qz = (q[:, c[k]].copy() for k in ("base_qw", "base_qx", "base_qy", "base_qz"))
    q[:, c["base_qw"]] = w0 * w - z0 * qz
    q[:, c["base_qx"]] = w0 * qx - z0 * qy
    q[:, c["base_qy"]] = w0 * qy + z0 * qx
    q[:, c["base_qz"]] = w0 * qz + z0 * w
copy("moved", moved)
copy("turned", turned)
# The first half of the frames: the datasets a fall record has cut.
with h5py.File(f"{work}/reference.h5", "r") as source, h5py.File(f"{work}/cut.h5", "w") as cut:
    half = len(source["time"]) // 2
    for key in ("time", "q", "coordinate_names", "contact", "contact_feet"):
        data = source[key][()]
        cut[key] = data[:half] if key in ("time", "q", "contact") else data
with h5py.File(f"{work}/shifted.h5", "w") as bad, h5py.File(f"{work}/reference.h5", "r") as source:
    for key in ("q", "coordinate_names"):
        bad[key] = source[key][()]
    bad["time"] = source["time"][()] + 0.001
COPIES

for copy in reference moved turned cut; do
  "$python" tools/dev/compare_feet.py $work/reference.h5 $work/$copy.h5 > $work/$copy.txt 2>&1 ||
    fail "$copy: $(cat $work/$copy.txt)"
done
"$python" tools/dev/compare_feet.py $work/reference.h5 $work/turned.h5 --png $work/turned.png > /dev/null ||
  fail "--png failed"
[ -s $work/turned.png ] || fail "--png wrote no plot"
cat $work/turned.txt

"$python" - $work <<'CHECK' || fail "compare_feet's table does not match the known moves"
import math, os, re, sys
import h5py, numpy as np
work = sys.argv[1]
sys.path.insert(0, os.path.join(os.getcwd(), "tools", "report"))
def table(name):
    rows = re.findall(r"^\s*([0-9.]+)\s+(\w+)\s+([-0-9.]+)\s+([-0-9.]+)\s+([-0-9.]+)$", open(f"{work}/{name}.txt").read(), re.M)
    return [(float(t), side, float(moved), float(turned)) for t, side, moved, turned, _ in rows]
with h5py.File(f"{work}/reference.h5", "r") as file:
    time, contact = file["time"][()], np.asarray(file["contact"][()]).astype(bool)
expected = [(time[t], f) for t in range(1, len(time)) for f in range(contact.shape[1]) if contact[t, f] and not contact[t - 1, f]]
assert len(expected) >= 3, f"02_01 has {len(expected)} touchdowns"
for name in ("reference", "moved", "turned"):
    rows = table(name)
    assert [round(t, 3) for t, *_ in rows] == [round(t, 3) for t, _ in expected], (name, rows, expected)
for _, side, moved, turned in table("reference"):
    assert moved == 0.0 and turned == 0.0, ("itself", side, moved, turned)
for _, side, moved, turned in table("moved"):
    assert abs(moved - 1000 * math.hypot(0.1, 0.05)) <= 0.1 and abs(turned) <= 0.05, ("moved", side, moved, turned)
# Turned: each foot's heading by exactly the turn; its sole centre by the chord of its radius.
from trial_report import read_feet, read_motion
from urdf_fk import Robot
robot, feet, reference = Robot("datasets/robots/unitree_g1/g1_29dof.urdf"), read_feet("manifests/robots/g1.toml"), read_motion(f"{work}/reference.h5")
rotations, positions = robot.forward_kinematics(reference["q"], reference["coordinate_names"])
centre = {side: positions[:, robot.index[link]] + np.einsum("tij,j->ti", rotations[:, robot.index[link]], soles.mean(axis=0)) for side, link, soles in feet}
for (t, side, moved, turned), (time_t, _) in zip(table("turned"), expected):
    k = int(np.argmin(abs(time - time_t)))
    chord = 1000 * 2 * np.linalg.norm(centre[side][k, :2]) * math.sin(0.15)
    assert abs(turned - math.degrees(0.3)) <= 0.05, ("turned", side, turned)
    assert abs(moved - chord) <= 0.1, ("turned", side, moved, chord)
cut = table("cut")
half = len(time) // 2
assert [round(t, 3) for t, *_ in cut] == [round(t, 3) for t, _ in expected if t < time[half]], (cut, expected)
assert all(moved == 0.0 and turned == 0.0 for _, _, moved, turned in cut), cut
print(f"compare_feet: {len(expected)} touchdowns, itself 0 mm / 0 deg, moved 111.8 mm, turned 17.19 deg, cut {len(cut)}")
CHECK

set +e
"$python" tools/dev/compare_feet.py $work/reference.h5 $work/shifted.h5 > $work/refusal.txt 2>&1
status=$?
set -e
[ $status != 0 ] && grep -q "frame times are not" $work/refusal.txt || fail "shifted frame times: exit $status, $(cat $work/refusal.txt)"
echo "compare_feet: ok"
