#!/usr/bin/env bash
# Set up, then run the whole test suite: in parallel, one worker per CPU core
# (PDBFS_TEST_WORKERS=N to choose; 0 runs it in this process), each test file on one
# worker (its module fixtures built once), the slowest files first. The time it
# took is the last line.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
workers=${PDBFS_TEST_WORKERS:-auto}
SECONDS=0
rc=0
# -rs: each skipped test with its reason (a missing tool says which)
if [ "$workers" = 0 ]; then python -m pytest -q -rs "$@" || rc=$?
else python -m pytest -q -rs -n "$workers" --dist loadfile "$@" || rc=$?
fi
echo "test.sh: the whole suite took $((SECONDS / 60)) min $((SECONDS % 60)) s"
exit $rc
