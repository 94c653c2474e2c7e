#!/usr/bin/env bash
# Install what the tests need and run every test. `.ci/run` runs exactly this.
#   bash scripts/test.sh            all tests
#   IFACE_E2E=1 bash scripts/test.sh   also the real-VS-Code end-to-end test
set -euo pipefail
cd "$(dirname "$0")/.."

# Oracles and editors from Debian: thrift --audit, headless Neovim, graphviz, idlc (Cyclone DDS),
# fastddsgen (eProsima).
need=()
command -v thrift >/dev/null || need+=(thrift-compiler)
command -v nvim >/dev/null || need+=(neovim)
command -v dot >/dev/null || need+=(graphviz)
command -v idlc >/dev/null || need+=(cyclonedds-tools)
command -v fastddsgen >/dev/null || need+=(fastddsgen)
if [ "${IFACE_E2E:-0}" = 1 ] && ! command -v chromium >/dev/null; then need+=(chromium); fi
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
  else
    echo "note: not root; tests needing ${need[*]} will be skipped" >&2
  fi
fi

python3 -m pip install -q --disable-pip-version-check -e '.[test]'
# Bytecode for this checkout, as pip writes it for an installed package: the run starts hundreds of Python processes
# that import iface (the CLI, language servers, managers, ROS tools), and where PYTHONDONTWRITEBYTECODE is set each
# would compile it again (docs/testing.md, "Bytecode").
python3 -m compileall -q -j 0 -x '/golden/' server tests >/dev/null || true  # a speed-up only: a file that does not compile is the tests' to report

if command -v npm >/dev/null; then
  (cd vscode-extension && { [ -d node_modules ] || npm ci --no-audit --no-fund --loglevel=error; })
fi

# One worker per core and one more (pytest-xdist): the ROS modules wait on the processes they start and on
# discovery about as long as they compute, and the extra worker runs meanwhile (docs/testing.md, "Workers").
# tests/conftest.py keeps each module in one worker and hands out the longest first (hence no reordering by xdist).
# IFACE_TEST_WORKERS=N sets the count, 0 runs everything in this process. Built ROS workspaces are kept in the test
# cache ($IFACE_TEST_CACHE, else ~/.cache/iface-tests: docs/testing.md).
cores=$(python3 -c 'import os; print(len(os.sched_getaffinity(0)))')
workers=${IFACE_TEST_WORKERS:-$((cores + 1))}
python3 -m pytest -q -n "$workers" --dist loadgroup --no-loadscope-reorder "$@"
