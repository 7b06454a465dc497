#!/bin/bash
# make ground-sweep: syn-simulate's ground mode on every shared CMU walk onto the G1, a line per walk and
# how many stay up: the count `GroundMode.SomeCmuWalksStayUp` guards, for any syn-simulate flags.
#
#   tools/dev/ground_sweep.sh BIN_DIR OUT_DIR [syn-simulate flags ...]
#
# The walks are index.csv's motion_class "walk" in $CMU_BVH (default ../shared/datasets/cmu_bvh),
# ingested and retargeted as the pipeline does for CMU BVH (manifests/demo.toml: --drop-first-frame, the
# cmu-bvh marker set). Retargets are kept in OUT_DIR/retarget and redone only when an input or a stage is
# newer, so a sweep over settings pays for them once. $JOBS walks at a time (default: the cores).
# Prints per walk "up" or the fall's time, and the simulation's speed; each walk's -v log is in
# OUT_DIR/simulate/NAME.log.
set -euo pipefail

if [ $# -lt 2 ]; then
  echo "usage: $0 BIN_DIR OUT_DIR [syn-simulate flags ...]" >&2
  exit 2
fi
bin=$(realpath "$1")
out=$2
shift 2
cmu=${CMU_BVH:-../shared/datasets/cmu_bvh}
index=$cmu/index.csv
if [ ! -f "$index" ]; then
  echo "ground-sweep: no CMU index at $index (set CMU_BVH to the shared CMU BVH folder)" >&2
  exit 2
fi
for stage in syn-ingest syn-retarget syn-simulate; do
  [ -x "$bin/$stage" ] || { echo "ground-sweep: $bin/$stage not built (make build)" >&2; exit 2; }
done
mkdir -p "$out/retarget" "$out/simulate"
rm -f "$out"/simulate/*.log "$out"/simulate/*.result

# trial and BVH path per walk, in index order (the label column may hold quoted commas: read it as CSV).
walks=$(python3 -c 'import csv, sys
for row in csv.DictReader(open(sys.argv[1])):
    if row["motion_class"] == "walk": print(row["trial"], row["file"])' "$index")
if [ -z "$walks" ]; then
  echo "ground-sweep: $index lists no walk" >&2
  exit 2
fi

export bin out cmu
export SIMULATE_FLAGS="$*"
run_walk() {
  local name=$1 file=$2
  local bvh=$cmu/$file motion=$out/retarget/$name.g1.h5 markers=$out/retarget/$name.markers.h5
  local model=datasets/robots/unitree_g1/g1_29dof.urdf map=manifests/robots/g1.toml markerset=manifests/markersets/cmu-bvh.toml
  local stale=0 input
  for input in "$bvh" "$model" "$map" "$markerset" "$bin/syn-ingest" "$bin/syn-retarget"; do
    [ -f "$motion" ] && [ "$motion" -nt "$input" ] || stale=1
  done
  if [ $stale = 1 ]; then
    "$bin/syn-ingest" "$bvh" --drop-first-frame -o "$markers" 2> "$out/retarget/$name.log" &&
      "$bin/syn-retarget" "$markers" -o "$motion" --model "$model" --robot-map "$map" --markerset "$markerset" \
        2>> "$out/retarget/$name.log" ||
      { echo "$name retarget-failed (see $out/retarget/$name.log)" > "$out/simulate/$name.result"; return 0; }
  fi
  local log=$out/simulate/$name.log
  # shellcheck disable=SC2086  # the flags are words
  if "$bin/syn-simulate" "$motion" -o "$out/simulate/$name.sim.h5" --model "$model" --robot-map "$map" \
      --contact ground -v $SIMULATE_FLAGS > "$log" 2>&1; then
    echo "$name up $(grep -o '[0-9.]*x real time' "$log" | tail -n 1)" > "$out/simulate/$name.result"
  else
    local fell
    fell=$(grep -o 'fell at t = [0-9.]* s' "$log" | head -n 1)
    echo "$name ${fell:-failed (see $log)}" > "$out/simulate/$name.result"
  fi
}
export -f run_walk
echo "$walks" | xargs -P "${JOBS:-$(nproc)}" -L 1 bash -c 'run_walk "$0" "$1"'

cat "$out"/simulate/*.result
up=$(cat "$out"/simulate/*.result | awk '$2 == "up"' | wc -l)
echo "ground mode${*:+ ($*)}: $up of $(echo "$walks" | wc -l) CMU walks stay up"
