#!/usr/bin/env bash
# The hard-case suite (docs/reliability.md): every case of scenes/hard-cases/cases.toml run
# and checked, one table. Builds ifsim first if needed. Options go to scripts/hard_cases.py:
#   --quick (the CI subset), --only NAME, --list, --json FILE, --work DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ ! -x build/ifsim ]]; then
    cmake --preset release >/dev/null && cmake --build --preset release -j "$(nproc)" --target ifsim
fi
exec python3 scripts/hard_cases.py build/ifsim "$@"
