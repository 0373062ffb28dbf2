#!/usr/bin/env bash
# Stops the single-node Slurm of ci/slurm-up.sh by its daemons' pid files, and waits until
# they have exited.
#
#     ci/slurm-down.sh [DIR]
DIR=${1:-/tmp/texopt-slurm}
pids=()
for f in "$DIR/run/slurmd.pid" "$DIR/run/slurmctld.pid" "$DIR/munge/munged.pid"; do
    if [ -s "$f" ]; then
        pid=$(cat "$f")
        kill "$pid" 2>/dev/null && pids+=("$pid")
    fi
done
for pid in "${pids[@]}"; do
    for _ in $(seq 1 50); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.1
    done
done
