#!/usr/bin/env bash
# Installs the Debian 12 packages ifsim needs (only the missing ones), then configures and builds
# with the release preset. Sourced by run-examples.sh and run-tests.sh; safe to run on its own.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake ninja-build git pkg-config
          libeigen3-dev libtbb-dev libxsimd-dev libsuitesparse-dev
          libopenblas0-pthread  # UMFPACK's BLAS: 3.7x faster factorisations than the reference BLAS
          libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libfmt-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          zlib1g-dev
          libopenmpi-dev openmpi-bin  # `mpirun -np N ifsim sweep` across ranks and machines
          libceres-dev  # `ifsim calibrate`: Levenberg-Marquardt within bounds
          pybind11-dev python3-dev python3-numpy  # the Python module: import ifsim
          python3 python3-matplotlib python3-meshio python3-vtk9  # field files read back in tests
          gmsh  # meshes of scripts/study_fe_meshes.py from scenes/meshes/*.geo
          clang libclang-rt-14-dev)  # the sanitize preset: ASan + UBSan builds and libFuzzer harnesses

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    echo "ifsim setup: installing missing Debian packages: ${missing[*]}"
    sudo_cmd=()
    if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
    export DEBIAN_FRONTEND=noninteractive
    "${sudo_cmd[@]}" apt-get update -qq
    "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

preset=${IFSIM_PRESET:-release}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$(nproc)"
