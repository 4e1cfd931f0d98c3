#!/usr/bin/env bash
# The main job: sets up and builds ifsim, runs every example scene under scenes/ into
# results/<scene>/, every sweep under sweeps/ into results/sweep-<name>/ and every calibration
# under calibrations/ into results/calibration-<name>/, and draws their plots. Exits non-zero
# if any of them failed.
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh || exit 1

out=${IFSIM_RESULTS:-results}
mkdir -p "$out"
failed=()
run_dirs=()
for scene in scenes/*.toml; do
    name=$(basename "$scene" .toml)
    echo "== $name"
    run_dirs+=("$out/$name")
    if ! ./build/ifsim run "$scene" --out "$out/$name" --replace; then
        failed+=("$name")
    fi
done

plot_python=/usr/bin/python3
[ -x "$plot_python" ] || plot_python=python3
"$plot_python" scripts/plot_results.py "${run_dirs[@]}"

for sweep in sweeps/*.toml; do
    name=sweep-$(basename "$sweep" .toml)
    echo "== $name"
    rm -rf "${out:?}/$name" # a fresh sweep: runs of an earlier build are not reused here
    if ! ./build/ifsim sweep "$sweep" --out "$out/$name"; then
        failed+=("$name")
    fi
    "$plot_python" scripts/plot_sweep.py "$out/$name"
done

for cal in calibrations/*.toml; do
    name=calibration-$(basename "$cal" .toml)
    echo "== $name"
    rm -rf "${out:?}/$name"
    if ! ./build/ifsim calibrate "$cal" --out "$out/$name"; then
        failed+=("$name")
    fi
    "$plot_python" scripts/plot_calibration.py "$out/$name"
done

if ((${#failed[@]})); then
    echo "scenes that failed: ${failed[*]}" >&2
    exit 1
fi
echo "results and plots in $out/"
