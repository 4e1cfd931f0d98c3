#!/usr/bin/env bash
# Sets up and builds ifsim, then runs every test (all CTest labels: fast and long).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --preset release -j "$(nproc)" "$@"
