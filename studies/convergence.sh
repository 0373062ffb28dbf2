#!/usr/bin/env bash
# Mesh and time-step convergence study (paper §3.3), outputs in results/convergence*.
# The finest run (1024×64) took 293 s on one core of the 2-core machine in stop 27 (42 min with the first build).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --example convergence
bin=target/release/examples/convergence
$bin run 128x8 1.6e-3
$bin run 256x16 8e-4
$bin run 512x32 4e-4
$bin run 1024x64 2e-4
$bin report
