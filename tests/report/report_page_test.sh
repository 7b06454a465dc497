#!/usr/bin/env bash
# CTest report_page: builds the demo's report (make report; the demo pipeline too when outputs/demo is
# missing or stale), checks the report's FK against syn-retarget's (check_fk.py), then loads the page in
# headless Chromium (report_page_test.mjs). Screenshots: outputs/report-test/. Exit 77 = skipped, saying
# why, when node, chromium or tools/report/node_modules (npm ci) is missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
build_dir=${1:-build}
. tests/report/browser_prerequisites.sh

start=$(date +%s.%N)
make --no-print-directory -s report MANIFEST=manifests/demo.toml BUILD_DIR="$build_dir" JOBS=2
echo "report_page_test: make report took $(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN{printf "%.1f", e-s}') s"
mkdir -p outputs/report-test
"${PYTHON:-/usr/bin/python3}" tests/report/check_fk.py manifests/demo.toml outputs outputs/report-test/expected_fk.json
CHROMIUM="$chromium" node tests/report/report_page_test.mjs outputs/demo/report/index.html \
  outputs/report-test/expected_fk.json outputs/report-test
