#!/usr/bin/env bash
# The film under the ring over one texture period for the paper's three cases (its
# Figs. 7–10): maps of p, θ and h, centre-line profiles, Z(t) and f(t) with the instants a–j
# marked, and an animation of Case III, at the paper's numerics (512×32, dt = 4e-4) from the
# paper's start. ≈ 10 s on one core. The fields' CSV files are written beside the pictures
# and not committed (≈ 1 MB a case).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release
bin=target/release/texopt
out=results/snapshots
mkdir -p "$out"
run() { # name R l1 per depth [more flags]
  local name=$1 r=$2 l1=$3 per=$4 depth=$5
  shift 5
  "$bin" simulate --R "$r" --l1 "$l1" --per "$per" --depth "$depth" --fidelity paper \
    --start paper --snapshots "$out/$name" "$@" | tee "$out/$name/summary.txt"
}
mkdir -p "$out/case_I" "$out/case_II" "$out/case_III"
run case_I 0.8 0.01 0.06 5
run case_II 51.2 0.01 0.06 5
run case_III 3.2 0.03 0.06 10 --animate "$out/case_III.gif"
