#!/usr/bin/env bash
# Runs short scenes of every kind (element tests, interface tests, 2D and 3D boundary-value
# problems with generated and Gmsh meshes, small strain and updated Lagrangian, fields) through
# an ifsim built with ASan + UBSan. Any sanitizer report, leak or failed run fails the script.
# Usage: scripts/run-sanitized-scenes.sh IFSIM OUT_DIR   (from the source tree's root)
set -euo pipefail
ifsim=$1
out=$2
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

runs=(
  "element-hypo-triaxial-drained-dense"
  "element-hypo-cyclic-undrained"
  "element-hypo-oedometer"
  "element-sanisand-triaxial-undrained"
  "element-sanisand-cyclic-undrained"
  "element-sanisand-simple-shear"
  "simple-shear-cnl-coulomb"
  "simple-shear-cnl --set stage.1.steps=40 --set stage.1.du_t1=0.001 --set interface.subincrement=adaptive"
  "hard-cases/interface-sanisand-loose-cns --set normal.stiffness=500.0 --set stage.1.steps=40 --set stage.2.steps=1 --set stage.2.du_t1=0.0 --set stage.3.steps=1 --set stage.3.du_t1=0.0 --set stage.4.steps=1 --set stage.4.du_t1=0.0 --set stage.5.steps=1 --set stage.5.du_t1=0.0"
  "appendix-c-continuum"
  "interface-point-probe"
  "appendix-c-stutz-continuum"
  "cyclic-cns-stutz"
  "fe-contact-patch-2d"
  "fe-lift-off-and-back-2d"
  "fe-sliding-block-2d"
  "fe-simple-shear-coulomb-2d"
  "fe-rough-and-smooth-2d --fields"
  "fe-simple-shear-cns-2d --set mesh.kinematics=\"updated-lagrangian\" --set mesh.integration=\"reduced\""
  "fe-simple-shear-cnl-2d-gmsh --set stage.2.steps=20 --set stage.2.displacement.1.change=0.0002"
  "fe-simple-shear-cnl-3d --set stage.2.steps=10 --set stage.2.displacement.1.change=0.0002 --fields"
)
failed=0
mkdir -p "$out"
for i in "${!runs[@]}"; do
  read -r -a words <<< "${runs[$i]}"
  name=${words[0]}
  args=("${words[@]:1}")
  run=$(printf "%02d-%s" "$i" "$(basename "$name")")
  log=$out/$run.log
  start=$(date +%s)
  if "$ifsim" run "scenes/$name.toml" --out "$out/$run" --replace -q "${args[@]}" >"$log" 2>&1 \
     && ! grep -q -E "runtime error|AddressSanitizer|LeakSanitizer" "$log"; then
    echo "ok      $run ($(( $(date +%s) - start )) s)"
  else
    echo "FAILED  $run (log: $log)"
    tail -n 40 "$log"
    failed=1
  fi
done
exit $failed
