#!/usr/bin/env bash
# The converged references of the four benchmark cases (results/references/): two refinement
# sequences around 1024×16 at dt = 1e-4 per case — along the sliding direction with the time
# step (Courant number 0.5) and across it — then the report, which extrapolates them
# (lab/src/studies/references.rs). ≈ 2 h on one core (the wall times in runs.jsonl); the
# 2048×16 runs take 2–6 min each, the 4096×16 ones 7–25 min, the deep case's 1024×64 ≈ 30 min.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p texopt-lab
bin="target/release/texopt-lab references"
for c in case-I case-III conformal-R51.2 deep-close-packed; do
  # Along: N1 and dt together.
  $bin run "$c" 512x16 2e-4
  $bin run "$c" 1024x16 1e-4
  $bin run "$c" 2048x16 5e-5
  $bin run "$c" 4096x16 2.5e-5
  # Across: N2.
  $bin run "$c" 1024x8 1e-4
  $bin run "$c" 1024x32 1e-4
done
# The deep pockets converge slowly across (first order): one level more.
$bin run deep-close-packed 1024x64 1e-4
$bin report
