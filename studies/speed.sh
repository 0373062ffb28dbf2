#!/usr/bin/env bash
# Speed against accuracy for Case I, Case III and the conformal R = 51.2
# (results/speed/speed.{md,csv,png}): errors against the converged references
# (results/references/, studies/references.sh), wall time from the paper's start on one core.
# Every run is the `fast` tier's numerics with the row's mesh and step and the changes named.
# ≈ 3 min on one core; time it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p texopt-lab
bin="target/release/texopt-lab speed"
settings=(
  # The tiers as the product runs them.
  "384x8 5.4e-4 tol=1e-3" "512x8 4e-4" "512x32 4e-4 scheme=be tol=1e-5 approach=512x8@4e-4"
  "1024x16 2e-4 tol=1e-5"
  # Courant number 1 on a coarser mesh.
  "256x8 8e-4"
  # Meshes and steps.
  "128x8 1.6e-3" "256x8 4e-4" "512x8 2e-4" "512x16 4e-4" "512x16 2e-4" "1024x8 4e-4"
  "1024x8 2e-4" "1024x16 1e-4"
  # What each accelerator and the time scheme bring at the fast tier.
  "512x8 4e-4 scheme=be" "512x8 4e-4 accelerate=no" "512x8 4e-4 approach=off"
  "512x8 4e-4 accelerate=no approach=off scheme=be" "512x8 4e-4 tol=1e-5"
)
for c in case-I case-III conformal-R51.2; do
  for s in "${settings[@]}"; do
    # shellcheck disable=SC2086
    $bin run "$c" $s
  done
done
$bin report
