#!/usr/bin/env bash
# CTest studio_page: syn-studio on the demo library (outputs/demo/library.h5, `make demo`) on a free loopback
# port, its page in headless Chromium (studio_page_test.mjs: load, move a slider, see the pose and the plot
# change, save the script), then the saved script composed in batch by syn-compose must give the page's q to
# 1e-12. Screenshots and files: outputs/studio-test/. Exit 77 = skipped, saying why.
set -euo pipefail
cd "$(dirname "$0")/../.."
build_dir=${1:-build}
out=outputs/studio-test
library=${LIBRARY:-outputs/demo/library.h5}
. tests/report/browser_prerequisites.sh
[ -f "$library" ] || skip "no demo library at $library: make demo"

rm -rf "$out" && mkdir -p "$out"
"$build_dir/bin/syn-studio" --library "$library" --model datasets/robots/unitree_g1/g1_29dof.urdf \
  --robot-map manifests/robots/g1.toml --script manifests/scripts/dance_phrase.toml --port 0 2> "$out/studio.log" &
studio=$!
trap 'kill $studio 2>/dev/null; wait $studio 2>/dev/null || true' EXIT
for _ in $(seq 100); do grep -q 'serving' "$out/studio.log" && break; kill -0 $studio || { cat "$out/studio.log"; exit 1; }; sleep 0.1; done
url=$(sed -n 's/.* on \(http:[^ ]*\) .*/\1/p' "$out/studio.log")
echo "studio_page_test: $url"
CHROMIUM="$chromium" node tests/studio/studio_page_test.mjs "$url" "$out"

"$build_dir/bin/syn-compose" "$out/saved.toml" --library "$library" -o "$out/saved.motion.h5"
"${PYTHON:-/usr/bin/python3}" - "$out/page_motion.json" "$out/saved.motion.h5" <<'PY'
import json, sys
import h5py, numpy as np
page = json.load(open(sys.argv[1]))
with h5py.File(sys.argv[2], "r") as f:
    time, q = f["time"][...], f["q"][...]
page_time, page_q = np.array(page["time"]), np.array(page["q"])
assert page_q.shape == q.shape, f"page q {page_q.shape} vs batch {q.shape}"
dq, dt = np.abs(page_q - q).max(), np.abs(page_time - time).max()
print(f"studio_page_test: saved script in batch: {q.shape[0]} frames, max |q_page - q_batch| = {dq:.3g}, time {dt:.3g}")
assert dq <= 1e-12 and dt <= 1e-12, "the saved script composes to another motion in batch"
PY
echo "studio_page_test: passed"
