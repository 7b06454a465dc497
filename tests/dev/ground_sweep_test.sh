#!/usr/bin/env bash
# CTest ground_sweep: tools/dev/ground_sweep.sh (make ground-sweep) on a two-walk index made from the shared
# CMU index: 02_01, and 09_12, whose label holds quoted commas. Checks its report against the logs it keeps
# (each walk's line is the stage's own verdict, the count is the walks up), that a second sweep reuses the
# retargets and a newer input redoes one, the RUNS ensemble's tallies against its runs' logs, and its
# refusals. Exit 77 = skipped (no shared datasets).
set -euo pipefail
cd "$(dirname "$0")/../.."
build_dir=${1:-build}
fail() { echo "FAIL: $*"; exit 1; }
shared=../shared/datasets
if [ ! -f $shared/cmu_bvh/index.csv ]; then
  echo "SKIP: $shared/cmu_bvh/index.csv is absent"
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/ground_sweep_test.XXXXXX")
trap 'rm -rf "$work"' EXIT

# A datasets folder with the index's header and two of its walks, the BVH files linked.
mkdir -p $work/datasets/cmu_bvh
index=$shared/cmu_bvh/index.csv
{ head -n 1 $index; grep -E '^[0-9]+,(02_01|09_12),' $index; } > $work/datasets/cmu_bvh/index.csv
[ "$(wc -l < $work/datasets/cmu_bvh/index.csv)" = 3 ] || fail "02_01 or 09_12 missing from $index"
grep -q '"navigate - walk forward, backward, sideways"' $work/datasets/cmu_bvh/index.csv ||
  fail "09_12's label no longer holds commas: pick another walk for the CSV check"
# 09_12 copied, so that touching it below leaves the shared file alone.
mkdir -p $work/datasets/cmu_bvh/02 $work/datasets/cmu_bvh/09
ln -s "$(realpath $shared/cmu_bvh/02/02_01.bvh)" $work/datasets/cmu_bvh/02/02_01.bvh
cp $shared/cmu_bvh/09/09_12.bvh $work/datasets/cmu_bvh/09/09_12.bvh

out=$work/sweep
CMU_BVH=$work/datasets/cmu_bvh JOBS=2 tools/dev/ground_sweep.sh $build_dir/bin $out > $work/report.txt 2> $work/stderr.txt ||
  fail "the sweep failed: $(cat $work/report.txt $work/stderr.txt)"
cat $work/report.txt
# Each walk's line is what its syn-simulate -v log says: up with the log's real-time figure, or the fall's time.
for trial in 02_01 09_12; do
  log=$out/simulate/$trial.log
  [ -f $log ] && [ -f $out/retarget/$trial.g1.h5 ] || fail "$trial: no log or retarget kept"
  line=$(grep "^$trial " $work/report.txt) || fail "$trial: no line in the report"
  if fell=$(grep -o "fell at t = [0-9.]* s\(, after [0-9]* of the take's [0-9]* steps\)\?" $log | head -n 1); then
    [ "$line" = "$trial $fell" ] || fail "$trial: the report says '$line', its log '$fell'"
    # The steps, counted here from the retarget's contact flags: touchdowns (a foot planted after a frame it
    # was not) in the take, and in its frames up to the fall.
    "${PYTHON:-/usr/bin/python3}" - "$out/retarget/$trial.g1.h5" "$fell" <<'STEPS' || fail "$trial: '$fell' does not count the retarget's steps"
import re, sys
import h5py, numpy as np
with h5py.File(sys.argv[1], "r") as file:
    time, contact = file["time"][()], np.asarray(file["contact"][()]).astype(bool)
fell = re.fullmatch(r"fell at t = ([0-9.]+) s, after (\d+) of the take's (\d+) steps", sys.argv[2])
assert fell, sys.argv[2]
touchdown = contact[1:] & ~contact[:-1]
before = time[1:] <= float(fell.group(1))
assert int(fell.group(3)) == touchdown.sum(), (fell.group(0), touchdown.sum())
# The stage counts the frames up to the last one recorded before the fall (t rounded to 3 digits here).
assert abs(int(fell.group(2)) - touchdown[before].sum()) <= 1, (fell.group(0), touchdown[before].sum())
STEPS
    [ ! -e $out/simulate/$trial.sim.h5 ] || fail "$trial fell but has an output"
  else
    speed=$(grep -o '[0-9.]*x real time' $log | tail -n 1)
    [ -n "$speed" ] && [ "$line" = "$trial up $speed" ] || fail "$trial: the report says '$line', its log ends: $(tail -n 2 $log)"
    [ -f $out/simulate/$trial.sim.h5 ] || fail "$trial up but no output"
  fi
done
up=$(grep -c -E '^[0-9_]+ up ' $work/report.txt || true)
tail -n 1 $work/report.txt | grep -qx "ground mode: $up of 2 CMU walks stay up" ||
  fail "the count line does not match the $up walks reported up"

# Flags reach syn-simulate (its parameters line), and the retargets are reused unless an input is newer.
before=$(stat -c %.9Y $out/retarget/02_01.g1.h5)
before_changed=$(stat -c %.9Y $out/retarget/09_12.g1.h5)
sleep 1
touch $work/datasets/cmu_bvh/09/09_12.bvh  # newer than its retarget
CMU_BVH=$work/datasets/cmu_bvh JOBS=2 tools/dev/ground_sweep.sh $build_dir/bin $out --balance-gain 4 > $work/report2.txt 2>&1 ||
  fail "the second sweep failed: $(cat $work/report2.txt)"
[ "$(stat -c %.9Y $out/retarget/02_01.g1.h5)" = "$before" ] || fail "02_01's retarget was redone with nothing newer"
[ "$(stat -c %.9Y $out/retarget/09_12.g1.h5)" != "$before_changed" ] || fail "09_12's retarget was not redone after its BVH changed"
grep -q '"balance_gain":4.0' $out/simulate/02_01.log || fail "--balance-gain 4 did not reach syn-simulate"
tail -n 1 $work/report2.txt | grep -q "^ground mode (--balance-gain 4): [0-2] of 2 CMU walks stay up$" ||
  fail "the count line does not name the flags: $(tail -n 1 $work/report2.txt)"

# RUNS=2: two sweeps with the gain, then kv, moved by 10⁻⁹ of the value the flags give (the user's --kv 30
# replaced, --swing-lift kept); each walk's tally, fall times, falls per 100 steps and where its falls
# began, and the mean, agree with the runs' logs.
CMU_BVH=$work/datasets/cmu_bvh JOBS=2 RUNS=2 tools/dev/ground_sweep.sh $build_dir/bin $out --kv 30 --swing-lift 0.05 \
  > $work/report3.txt 2>&1 || fail "the ensemble failed: $(cat $work/report3.txt)"
cat $work/report3.txt
python3 - "$out/runs" "$work/report3.txt" <<'CHECK' || fail "the ensemble's report does not match its runs' logs"
import json, pathlib, re, sys
runs, report = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]).read_text()
expected = {1: (3.5 * (1 + 1e-9), 30.0), 2: (3.5, 30.0 * (1 + 1e-9))}
counts = {1: 0, 2: 0}
walked, falls = 0, 0
for trial in ("02_01", "09_12"):
    up, times, taken, onsets = 0, [], [], []
    trial_walked, trial_falls = 0, 0
    for k in (1, 2):
        log = (runs / str(k) / "simulate" / f"{trial}.log").read_text()
        p = json.loads(re.search(r"^syn-simulate: parameters (\{.*\})$", log, re.M).group(1))
        gain, kv = expected[k]
        assert abs(p["balance_gain"] - gain) < 1e-15 * gain and abs(p["kv"] - kv) < 1e-15 * kv, (k, trial, p)
        assert p["swing_lift"] == 0.05, p
        fell = re.search(r"fell at t = ([0-9.]+) s", log)
        take = re.search(r"the take's (\d+) steps", log)
        assert take, f"{trial}'s log does not give the take's steps"
        after = re.search(r"after (\d+) of the take's", log)
        trial_walked += int(after.group(1)) if fell else int(take.group(1))
        trial_falls += 1 if fell else 0
        if fell:
            times.append(float(fell.group(1)))
            steps = re.search(r"fell at t = [0-9.]+ s, after (\d+) of the take's (\d+) steps", log)
            assert steps, f"{trial}'s fall does not say after how many steps"
            taken.append((int(steps.group(1)), int(steps.group(2))))
            onset = re.search(r"left the balance plan at t = ([0-9.]+) s", log)
            turn = re.search(r"and ([0-9]+) deg in the [0-9.]+ s before it", log)
            if onset:
                onsets.append((float(onset.group(1)), int(turn.group(1)) if turn else None))
        else:
            up += 1
            counts[k] += 1
    line = re.search(rf"^{trial} up in (\d+) of 2 runs(?: \(fell at ([0-9.]+)(?:-([0-9.]+))? s, "
                     rf"after (\d+)(?:-(\d+))? of (\d+) steps; ([0-9.]+) falls per 100 steps"
                     rf"(?:; (\d+) of (\d+) left the balance plan (?:at ([0-9.]+)|within ([0-9.]+)-([0-9.]+)) s"
                     rf"(?:, the reference turning (\d+) deg(?: \(median\))? in the lead-up)?)?\))?$", report, re.M)
    assert line, f"no line for {trial}"
    assert int(line.group(1)) == up, (trial, line.group(0), up)
    if times:
        assert float(line.group(2)) == min(times) and float(line.group(3) or line.group(2)) == max(times), (line.group(0), times)
        assert int(line.group(4)) == min(s for s, _ in taken) and int(line.group(5) or line.group(4)) == max(s for s, _ in taken), (line.group(0), taken)
        assert int(line.group(6)) == taken[0][1] and all(total == taken[0][1] for _, total in taken), (line.group(0), taken)
        assert line.group(7) == f"{100 * trial_falls / trial_walked:.1f}", (line.group(0), trial_falls, trial_walked)
        # The window of the falls' onsets: the one second, from an onset on, that holds the most of them.
        if onsets:
            assert int(line.group(9)) == len(onsets), (line.group(0), onsets)
            windows = [[o for o in onsets if start <= o[0] < start + 1] for start, _ in sorted(onsets)]
            inside = max(windows, key=len)
            assert int(line.group(8)) == len(inside), (line.group(0), onsets)
            first, last = min(t for t, _ in inside), max(t for t, _ in inside)
            shown = (float(line.group(10)),) * 2 if line.group(10) else (float(line.group(11)), float(line.group(12)))
            assert shown == (first, last), (line.group(0), onsets)
            turns = sorted(turn for _, turn in inside if turn is not None)
            if turns:
                assert int(line.group(13)) == turns[(len(turns) - 1) // 2], (line.group(0), onsets)
        else:
            assert line.group(8) is None, (line.group(0), "no onset in the logs")
    else:
        assert line.group(2) is None, line.group(0)
    walked, falls = walked + trial_walked, falls + trial_falls
for k in (1, 2):
    assert re.search(rf"^run {k} \(.*\): {counts[k]} of 2 up$", report, re.M), (k, counts[k])
mean = (counts[1] + counts[2]) / 2
assert re.search(rf"^falls per 100 steps taken: {100 * falls / walked:.2f} \({falls} falls in {walked} steps\)$", report, re.M), (falls, walked)
last = report.strip().splitlines()[-1]
error = abs(counts[1] - counts[2]) / 2  # two runs: the sample deviation |a − b|/√2, over √2
assert last == (f"ground mode (--swing-lift 0.05), 2 rounding-level runs: {mean:.2f} of 2 CMU walks stay up on average "
                f"({min(counts.values())}-{max(counts.values())}, standard error {error:.2f})"), last
CHECK
set +e
RUNS=two tools/dev/ground_sweep.sh $build_dir/bin $out > $work/refusal.txt 2>&1
status=$?
set -e
[ $status = 2 ] && grep -q "RUNS must be a positive whole number, got 'two'" $work/refusal.txt ||
  fail "RUNS=two: exit $status, $(cat $work/refusal.txt)"

# Refusals: exit 2 and why, for a missing index and a missing stage.
set +e
CMU_BVH=$work/nowhere/cmu_bvh tools/dev/ground_sweep.sh $build_dir/bin $work/x > $work/refusal.txt 2>&1
status=$?
set -e
[ $status = 2 ] && grep -q "no CMU index at $work/nowhere/cmu_bvh/index.csv" $work/refusal.txt ||
  fail "a missing index: exit $status, $(cat $work/refusal.txt)"
set +e
CMU_BVH=$work/datasets/cmu_bvh tools/dev/ground_sweep.sh $work $work/x > $work/refusal.txt 2>&1
status=$?
set -e
[ $status = 2 ] && grep -q "syn-ingest not built" $work/refusal.txt || fail "no stages: exit $status, $(cat $work/refusal.txt)"
echo "PASS"
