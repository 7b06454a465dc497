# Sourced by the browser tests (tests/report, tests/studio): skip() (exit 77, CTest's skip code, saying
# why), and $chromium once node, Chromium and tools/report's npm install are all there.
skip() { echo "SKIPPED: $*"; exit 77; }
command -v node >/dev/null || skip "node is not installed (make setup-report, as root)"
chromium=${CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || skip "$chromium is not installed (make setup-report, as root)"
[ -d tools/report/node_modules/playwright-core ] && [ -d tools/report/node_modules/three ] ||
  skip "tools/report/node_modules is missing: make report-npm"
