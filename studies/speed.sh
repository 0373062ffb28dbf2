#!/usr/bin/env bash
# Speed against accuracy for Case I, Case III and the conformal R = 51.2 (and, tabled, the
# deep close-packed pockets)
# (results/speed/speed.{md,csv,png}): errors against the converged references
# (results/references/, studies/references.sh), wall time from the paper's start on one core.
# Every run is the `fast` tier's numerics with the row's mesh and step and the changes named.
# ≈ 2.5 min on one core; time it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p texopt-lab
rm -f results/speed/runs.jsonl
bin="target/release/texopt-lab speed"
settings=(
  # The tiers as the product runs them (c: the characteristic step 2·dx1/u of the mesh;
  # only `fast` goes on on its deep-pocket mesh, which these cases do not need).
  "400x8 c tol=1e-3 deep=off" "700x8 c" "512x32 4e-4 scheme=be tol=1e-5 approach=512x8@4e-4 deep=off"
  "1024x16 2e-4 scheme=bdf2 tol=1e-5 approach=128x4@1.6e-3 deep=off"
  # The characteristic scheme along the sliding direction and across it.
  "300x8 c" "500x8 c" "600x8 c" "800x8 c" "1000x8 c" "600x16 c" "700x16 c"
  # The ring-frame schemes (the Couette flux upwinded in the stencil) on the same meshes.
  "384x8 5.4e-4 scheme=bdf2 tol=1e-3 approach=128x4@1.6e-3"
  "512x8 4e-4 scheme=bdf2 approach=128x4@1.6e-3" "512x8 4e-4 scheme=be approach=128x4@1.6e-3"
  "700x8 5.7142857142857e-4 scheme=bdf2 approach=128x4@1.6e-3"
  "1024x8 2e-4 scheme=bdf2 approach=128x4@1.6e-3" "512x16 4e-4 scheme=bdf2 approach=128x4@1.6e-3"
  # What each accelerator brings at the fast tier.
  "700x8 c accelerate=no" "700x8 c approach=off" "700x8 c approach=128x4@1.6e-3"
  "700x8 c accelerate=no approach=off" "700x8 c tol=1e-5"
)
for c in case-I case-III conformal-R51.2; do
  for s in "${settings[@]}"; do
    # shellcheck disable=SC2086
    $bin run "$c" $s
  done
done
# The deep close-packed pockets (tabled, off the chart's scale): the tiers (`fast` going on on
# its deep-pocket mesh), and cells across on one mesh.
for s in "400x8 c tol=1e-3 deep=off" "700x8 c" "700x8 c deep=off" \
  "512x32 4e-4 scheme=be tol=1e-5 approach=512x8@4e-4 deep=off" \
  "1024x16 2e-4 scheme=bdf2 tol=1e-5 approach=128x4@1.6e-3 deep=off" \
  "512x8 4e-4 scheme=bdf2 approach=128x4@1.6e-3 deep=off" \
  "700x16 c deep=off" "700x24 c" "600x24 c" "700x32 c" \
  "600x24 c solver=multigrid" "600x24 c solver=pt-multigrid"; do
  # shellcheck disable=SC2086
  $bin run deep-close-packed $s
done
# The paper tier's coarse approach: its own step on 512×8 against cheaper ones.
for a in 120x4@3.3333333333333e-3 256x8@1.6e-3 256x8@8e-4; do
  $bin run case-III 512x32 4e-4 scheme=be tol=1e-5 approach=$a deep=off
done
$bin report
