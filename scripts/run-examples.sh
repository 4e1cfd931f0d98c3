#!/usr/bin/env bash
# The main job: sets up and builds ifsim, runs every example scene under scenes/ into
# results/<scene>/ and draws its plots. Exits non-zero if any scene failed.
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh || exit 1

out=${IFSIM_RESULTS:-results}
mkdir -p "$out"
failed=()
for scene in scenes/*.toml; do
    name=$(basename "$scene" .toml)
    echo "== $name"
    if ! ./build/ifsim run "$scene" --out "$out/$name" --replace; then
        failed+=("$name")
    fi
done

plot_python=/usr/bin/python3
[ -x "$plot_python" ] || plot_python=python3
"$plot_python" scripts/plot_results.py "$out"/*/

if ((${#failed[@]})); then
    echo "scenes that failed: ${failed[*]}" >&2
    exit 1
fi
echo "results and plots in $out/"
