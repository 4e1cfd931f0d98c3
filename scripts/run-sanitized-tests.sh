#!/usr/bin/env bash
# The sanitizer job of CI: builds the sanitize preset (clang -O1, ASan + UBSan; the suites named
# by IFSIM_TEST_SUBSET in CMakePresets.json and the libFuzzer harnesses), runs those suites and
# scenes of every kind through the instrumented ifsim, then each fuzzer for a bounded time.
# Usage: scripts/run-sanitized-tests.sh [--fuzz-seconds N]   (default 60 per harness)
set -euo pipefail
cd "$(dirname "$0")/.."

fuzz_seconds=60
while (($#)); do
  case $1 in
    --fuzz-seconds) [ $# -ge 2 ] || { echo "run-sanitized-tests: --fuzz-seconds needs a value" >&2; exit 2; }
                    fuzz_seconds=$2; shift 2 ;;
    -h|--help) sed -n '2,5p' "$0"; exit 0 ;;
    *) echo "run-sanitized-tests: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

IFSIM_PRESET=sanitize bash scripts/setup.sh  # packages (clang, libFuzzer), then this build
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --preset sanitize -j "$(nproc)"
bash scripts/run-fuzzers.sh --seconds "$fuzz_seconds"
