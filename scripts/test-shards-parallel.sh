#!/usr/bin/env bash
# A regression suite spread over the cores of one machine with GNU parallel:
# N shards of `nearmiss test`, then `nearmiss merge` writes the JSON and
# JUnit reports one run would have written (wall times apart).
#   scripts/test-shards-parallel.sh SCENES_FOLDER [N] [OUT]
# Needs GNU parallel (Debian: apt-get install parallel) and a built nearmiss
# (cargo build --release). Each shard runs its scenes on one thread (--jobs 1).
set -euo pipefail
scenes=${1:?give a scene folder}
n=${2:-$(nproc)}
out=${3:-shards}
nearmiss=${NEARMISS:-target/release/nearmiss}
mkdir -p "$out"
# A shard's exit code says pass (0), fail (1) or bad scene (2); merge decides.
parallel --jobs "$n" "$nearmiss" test "$scenes" --jobs 1 --shard {}/"$n" --json "$out"/shard-{}.json '>' "$out"/shard-{}.log ::: $(seq 1 "$n") || true
"$nearmiss" merge "$out"/shard-*.json --json "$out"/suite.json --junit "$out"/suite.xml
