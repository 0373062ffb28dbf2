#!/usr/bin/env bash
# Speed against accuracy for Case I and Case III (results/speed.{md,csv,png}).
# Settings: meshes with dt refined together (the fidelity tiers), time steps at fixed mesh,
# half the cells across (N2), periodic tolerances, the solver variants and the coarse approach.
# The errors are against each case's 2048×128, dt = 1e-4 run (`finer` below for Case III,
# studies/convergence.sh for Case I); the finest settings are the 1024×64, dt = 2e-4 runs
# (Case I's from studies/convergence.sh; Case III's ≈ 22 min on one core).
# Run one case per core: about 30 minutes on the 2-core machine (the 2048×128 runs: hours).
# `bash studies/speed.sh sweep`: the settings only, keeping the 1024×64 runs in runs.jsonl.
# `bash studies/speed.sh finer`: the tiers against 2048 cells along x1, dt = 1e-4: 2048×32
# and 2048×64 for Case I, Case III and R = 51.2, 2048×128 for Case III (Case I's is the
# convergence study's) (results/speed/speed_finer.md).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p texopt-lab
bin="target/release/texopt-lab speed"
settings=(
  "128x8 1.6e-3" "256x16 8e-4" "512x32 4e-4"
  "256x16 1.6e-3" "256x16 4e-4" "512x32 8e-4"
  "256x8 8e-4" "512x16 4e-4"
  "128x8 1.6e-3 1e-4" "256x16 8e-4 1e-4" "512x32 4e-4 1e-4" "256x16 8e-4 1e-6"
  "256x16 8e-4 1e-5 multigrid" "512x32 4e-4 1e-5 multigrid"
  "512x8 4e-4" "512x16 8e-4" "1024x8 4e-4" "1024x16 4e-4" "1024x16 2e-4" "1024x32 2e-4"
  # The tiers as the product runs them: draft and fast at 1e-4, paper and fine with the
  # coarse approach (N2 = 8 first).
  "256x8 8e-4 1e-4" "512x8 4e-4 1e-4"
  "512x32 4e-4 1e-5 direct 8" "512x32 4e-4 1e-4 direct 8" "1024x16 2e-4 1e-5 direct 8"
  # The p–θ multigrid (src/pt_multigrid.rs) at the paper tier's setting.
  "512x32 4e-4 1e-5 pt-multigrid 8"
)
sweep() {
  for s in "${settings[@]}"; do
    # shellcheck disable=SC2086
    $bin run "$1" $s
  done
}
if [ "${1:-}" = finer ]; then
  # The finer reference (results/speed/speed_finer.md): 2048 cells along x1, dt = 1e-4.
  $bin finer-run case-I 2048x32 1e-4 &
  $bin finer-run case-III 2048x32 1e-4
  wait
  # The finest: N2 = 64, with the coarse approach (2048×8 first), one case per core (Case
  # III took ≈ 108 min beside other work, Case I ≈ 32 min).
  $bin finer-run case-I 2048x64 1e-4 1e-5 direct 8 &
  $bin finer-run case-III 2048x64 1e-4 1e-5 direct 8
  wait
  # The 2048×128 references: the band LU would need ≈ 1.5 s a step, the p–θ multigrid (same
  # discretisation) ≈ 0.9 s. Case I's 2048×128 is the convergence study's finest run.
  $bin finer-run case-III 2048x128 1e-4 1e-5 pt-multigrid 8 &
  # The conformal R = 51.2 benchmark case: its tiers and its 2048-cell runs (2048×32 ≈ 4 min,
  # 2048×64 ≈ 18 min, the tiers and 1024×64 ≈ 7 min).
  for s in "256x8 8e-4 1e-4" "512x8 4e-4 1e-4" "512x32 4e-4 1e-5 direct 8" \
    "1024x16 2e-4 1e-5 direct 8" "1024x64 2e-4"; do
    # shellcheck disable=SC2086
    $bin run conformal-R51.2 $s
  done
  $bin finer-run conformal-R51.2 2048x32 1e-4 1e-5 direct 8
  $bin finer-run conformal-R51.2 2048x64 1e-4 1e-5 direct 8
  wait
  $bin finer
  exit 0
fi
if [ "${1:-}" != sweep ]; then
  $bin run case-III 1024x64 2e-4
fi
sweep case-I &
sweep case-III
wait
$bin report
