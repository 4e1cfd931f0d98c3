#!/usr/bin/env bash
# Runs the libFuzzer harnesses of the sanitize build (fuzz/) on seed corpora made from scenes/,
# the test meshes and fuzz/regressions/. Exits non-zero when a harness finds a crash, a
# sanitizer report, a leak or a hang; the input is left in BUILD/fuzz/findings/.
#
#   scripts/run-fuzzers.sh                    60 s per harness (the CI run)
#   scripts/run-fuzzers.sh --runs 1000000     the long run of docs/reliability.md
#   scripts/run-fuzzers.sh --seconds 600 --only gmsh_reader
#
# Needs the sanitize build: cmake --preset sanitize && cmake --build --preset sanitize
set -euo pipefail
cd "$(dirname "$0")/.."

build=build-sanitize
limit=(-max_total_time=60)
only=""
while (($#)); do
  case $1 in
    --seconds) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    --only) only=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "run-fuzzers: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

seeds=$build/fuzz/seeds
rm -rf "$seeds"
mkdir -p "$seeds/scene_reader" "$seeds/gmsh_reader" "$build/fuzz/findings"

# Scene seeds: every shipped scene as it is, and some with --set overrides after "%%".
for f in scenes/*.toml scenes/*/*.toml; do
  cp "$f" "$seeds/scene_reader/$(echo "$f" | tr '/' '_')"
done
{ cat scenes/element-sanisand-cyclic-undrained.toml; printf '\n%%%%\nstage.1.steps=3\nmaterial.void_ratio=0.7\n'; } \
  > "$seeds/scene_reader/override-element"
{ cat scenes/simple-shear-cnl-stutz.toml; printf '\n%%%%\ninterface.roughness=0.5\nnormal.control=constant-stiffness\nnormal.stiffness=500.0\n'; } \
  > "$seeds/scene_reader/override-interface"
{ cat scenes/fe-simple-shear-cns-2d.toml; printf '\n%%%%\nmesh.kinematics="updated-lagrangian"\nstage.2.steps=2\n'; } \
  > "$seeds/scene_reader/override-boundary-value"
# Mesh seeds: ASCII and binary test meshes, the shipped meshes but the 0.6 MB fine one.
cp tests/io/mesh/data/*.msh "$seeds/gmsh_reader/"
for f in scenes/meshes/*.msh; do
  [[ $f == *large-shear-fine.msh ]] || cp "$f" "$seeds/gmsh_reader/"
done
for kind in scene_reader gmsh_reader; do
  if [ -d "fuzz/regressions/$kind" ]; then cp fuzz/regressions/$kind/* "$seeds/$kind/" 2>/dev/null || true; fi
done

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
for kind in scene_reader gmsh_reader; do
  [[ -z $only || $only == "$kind" ]] || continue
  corpus=$build/fuzz/corpus/$kind
  mkdir -p "$corpus"
  extra=()
  if [ "$kind" = scene_reader ]; then extra=(-dict=fuzz/scene.dict -max_len=16384); else extra=(-max_len=80000); fi
  echo "== fuzz_$kind ${limit[*]} (corpus $corpus)"
  if "$build/fuzz/fuzz_$kind" "${limit[@]}" "${extra[@]}" -timeout=20 -rss_limit_mb=3072 \
       -print_final_stats=1 -artifact_prefix="$build/fuzz/findings/$kind-" \
       "$corpus" "$seeds/$kind" > "$build/fuzz/$kind.log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|^#[0-9]+.*DONE" "$build/fuzz/$kind.log" || true
  else
    echo "fuzz_$kind: FOUND A PROBLEM (log $build/fuzz/$kind.log, input in $build/fuzz/findings/)"
    grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$build/fuzz/$kind.log" | head -20 || true
    status=1
  fi
done
exit $status
