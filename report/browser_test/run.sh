#!/usr/bin/env bash
# CTest's report.browser: rebuilds the fixture's report with `hdrconform report` and writes the
# golden review of its planted constant change with `hdrconform goldens diff`, then runs the
# end-to-end browser test. Exits 77 (CTest: SKIPPED, with this output as the reason) when
# Chromium, Node.js or the test's npm dependencies are missing; scripts/setup.sh installs them.
#   run.sh FIXTURE_DIR ARTIFACT_DIR HDRCONFORM
set -u
here="$(cd "$(dirname "$0")" && pwd)"
chromium="${HDRC_CHROMIUM:-/usr/bin/chromium}"
if ! command -v node >/dev/null 2>&1; then
  echo "SKIPPED: Node.js is not installed (Debian package nodejs; scripts/setup.sh installs it)"
  exit 77
fi
if [ ! -x "$chromium" ]; then
  echo "SKIPPED: Chromium not found at $chromium (Debian package chromium; scripts/setup.sh installs it)"
  exit 77
fi
if [ ! -f "$here/node_modules/playwright-core/package.json" ]; then
  echo "SKIPPED: playwright-core is not installed in $here/node_modules (scripts/setup.sh runs npm ci there)"
  exit 77
fi
"$3" report "$1" || { echo "FAIL: hdrconform report $1"; exit 1; }
# The golden review of the fixture's planted constant change (make_fixture.cpp, goldens-review).
rv="$1/goldens-review"
"$3" goldens diff --cases "$rv/cases" --goldens "$rv/new" --old "$rv/old" --out "$rv/out" ||
  { echo "FAIL: hdrconform goldens diff"; exit 1; }
exec node "$here/report.test.mjs" --results "$1" --artifacts "$2" --chromium "$chromium"
