#!/usr/bin/env bash
# Meshes of the large-scale cyclic interface shear test (paper §6) from
# scenes/meshes/large-shear.geo (all hexahedra, Gmsh MSH 4.1, ASCII):
#   scenes/meshes/large-shear-coarse.msh  8 x 3 x 12 soil elements (scenes/large-shear-coarse.toml)
#   scenes/meshes/large-shear-medium.msh 16 x 4 x 23 soil elements (the mesh study of docs/large-scale-test.md)
#   scenes/meshes/large-shear-fine.msh   24 x 5 x 32 soil elements (the four model scenes in scenes/large-shear/)
# Needs gmsh (Debian package gmsh; made with Gmsh 4.8.4). Usage: scripts/make_large_shear_meshes.sh
set -euo pipefail
cd "$(dirname "$0")/../scenes/meshes"
command -v gmsh >/dev/null || { echo "gmsh not found (apt-get install gmsh)" >&2; exit 1; }

mesh() { # OUT, then -setnumber NAME VALUE pairs
    local out=$1
    shift
    local args=()
    while (($#)); do
        args+=(-setnumber "$1" "$2")
        shift 2
    done
    gmsh -3 large-shear.geo -format msh41 "${args[@]}" -o "$out" -v 2
    echo "$out: $(sed -n '/^\$Nodes/{n;p;q}' "$out" | awk '{print $2}') nodes"
}

# Coarse: 288 soil elements, finer towards the moving wall (x) and the rough segment (z).
mesh large-shear-coarse.msh nx 8 ny 3 nz_low 4 nz_rough 5 nz_up 3 rx 0.8 rz 0.8 bump 0.5 \
    nz_seg_top 1 nz_side_top 2
# Medium: 1472 soil elements, 3228 nodes in all (9 684 DOFs), between the two (the mesh study).
mesh large-shear-medium.msh nx 16 ny 4 nz_low 7 nz_rough 10 nz_up 6 rx 0.87 rz 0.86 bump 0.5 \
    nz_seg_top 2 nz_side_top 3
# Fine: 3840 soil elements, 7232 nodes in all (21 696 DOFs); ASCII is ~0.6 MB (no -bin needed).
mesh large-shear-fine.msh nx 24 ny 5 nz_low 10 nz_rough 14 nz_up 8 rx 0.92 rz 0.9 bump 0.5 \
    nz_seg_top 2 nz_side_top 4
