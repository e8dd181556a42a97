#!/bin/bash
# Runs every fuzz target for SECONDS (default 180) each, one process (one core) at a time, from the committed
# seeds (fuzz/corpus/<target>, read only) into a scratch corpus; logs to $WORK/<target>.log.
# Usage: fuzz/run_all.sh [SECONDS] [WORK]   (needs cargo-fuzz and a nightly toolchain)
set -u
cd "$(dirname "$0")"
SECONDS_EACH=${1:-180}
WORK=${2:-/tmp/filmsplat-fuzz}
mkdir -p "$WORK"
for t in ply vtk vtu bgeo csv frame_bin scene_toml bgeo_gzip vtu_zlib; do
    mkdir -p "$WORK/$t"
    cargo +nightly fuzz run -O "$t" "$WORK/$t" "corpus/$t" -- \
        -max_total_time="$SECONDS_EACH" -print_final_stats=1 \
        > "$WORK/$t.log" 2>&1
    echo "$t: exit $? $(grep -E 'stat::number_of_executed_units' "$WORK/$t.log" | tail -n 1)"
done
