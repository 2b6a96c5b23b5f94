#!/usr/bin/env bash
# A sweep spread over the cores of one machine with GNU parallel: N shards
# of `nearmiss sweep`, then `nearmiss merge` writes the table, sweep.csv and
# chart one run would have written (wall times apart).
#   scripts/sweep-shards-parallel.sh SCENE N OUT -- SWEEP_OPTIONS...
#   e.g. scripts/sweep-shards-parallel.sh scenes/falling_box.ron 2 output -- \
#          --dt 0.004,0.002,0.001 --kernel exact,dyop-heron --integrator symplectic-euler,rk4
# Needs GNU parallel (Debian: apt-get install parallel) and a built nearmiss
# (cargo build --release). Wall times are measured per shard: run no more
# shards at once than there are cores.
set -euo pipefail
scene=${1:?give a scene file}
n=${2:?give the number of shards}
out=${3:?give the output folder}
shift 3
[ "${1:-}" = "--" ] && shift
nearmiss=${NEARMISS:-target/release/nearmiss}
mkdir -p "$out/shards"
parallel --jobs "$n" "$nearmiss" sweep "$scene" "$@" --shard {}/"$n" --json "$out"/shards/sweep-{}.json \
  '>' "$out"/shards/sweep-{}.log ::: $(seq 1 "$n")
"$nearmiss" merge "$out"/shards/sweep-*.json --out "$out"
