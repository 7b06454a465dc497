#!/usr/bin/env bash
# CTest watch_page: tools/report/watch.py on a ground-mode fall that the report cannot show (the demo's
# 60_10, a dance on both feet, simulated with `syn-simulate --contact ground --fall-record`) and a
# retargeted demo trial; its errors on bad input; then the page in headless Chromium (watch_page_test.mjs).
# Needs `make demo` first. Exit 77 = skipped, saying why. Screenshots: outputs/watch-test/.
set -euo pipefail
cd "$(dirname "$0")/../.."
build_dir=${1:-build}
python=${PYTHON:-/usr/bin/python3}
fail() { echo "FAIL: $*"; exit 1; }
. tests/report/browser_prerequisites.sh
demo=outputs/demo/trials
[ -f $demo/60_10/motion.h5 ] && [ -f $demo/02_01/motion.h5 ] || skip "the demo's motions are missing: run make demo"
model=datasets/robots/unitree_g1/g1_29dof.urdf
map=manifests/robots/g1.toml

out=outputs/watch-test
rm -rf $out
mkdir -p $out
# The fall: exit 1, no output, the frames before the fall in the record.
set +e
"$build_dir/bin/syn-simulate" $demo/60_10/motion.h5 -o $out/never.h5 --model $model --robot-map $map \
  --contact ground --fall-record $out/60_10_fall.h5 2> $out/simulate.log
status=$?
set -e
grep -q "fell at t = " $out/simulate.log && [ $status = 1 ] || fail "60_10 in ground mode did not fall (exit $status): $(cat $out/simulate.log)"
[ -f $out/60_10_fall.h5 ] && [ ! -e $out/never.h5 ] || fail "the fall record is missing or an output was written"
cp $demo/02_01/motion.h5 $out/02_01.h5

# Bad input: a clear error, exit 1, no page.
if "$python" tools/report/watch.py $out/missing.h5 --model $model --robot-map $map -o $out/bad 2> $out/bad.log; then
  fail "watch.py accepted a missing file"
fi
grep -q "missing.h5" $out/bad.log || fail "watch.py's error does not name the missing file: $(cat $out/bad.log)"
if "$python" tools/report/watch.py $out/02_01.h5 $out/02_01.h5 --model $model --robot-map $map -o $out/bad 2> $out/bad.log; then
  fail "watch.py accepted two motions of one name"
fi
[ ! -e $out/bad/index.html ] || fail "a failed watch.py left a page"

"$python" tools/report/watch.py $out/60_10_fall.h5 $out/02_01.h5 --model $model --robot-map $map -o $out/page
"$python" tests/report/watch_fk.py $model $out/expected_fk.json $out/60_10_fall.h5 $out/02_01.h5
CHROMIUM="$chromium" node tests/report/watch_page_test.mjs $out/page/index.html $out/expected_fk.json $out
