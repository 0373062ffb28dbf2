#!/usr/bin/env bash
# Mesh and time-step convergence study (paper §3.3), outputs in results/convergence/.
# Run times on one core of the 2-core machine: 2048×128 ≈ 72 min, 1024×64 ≈ 5 min, the others
# ≈ 10 s together.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p texopt-lab
bin="target/release/texopt-lab convergence"
$bin run 128x8 1.6e-3
$bin run 256x16 8e-4
$bin run 512x32 4e-4
$bin run 1024x64 2e-4
# The finest mesh: with the band LU ≈ 4 s a step (≈ 16 h); the p–θ multigrid (same
# discretisation, agrees with direct to the solve tolerance) after a 2048×8 approach instead.
$bin run 2048x128 1e-4 --solver pt-multigrid --approach 2048x8@1e-4
$bin report
