#!/usr/bin/env bash
# Prints the README's headline figures on this machine: each command three times, as wall and
# CPU (user + system) seconds of the whole process, with the machine (CPUs, model, memory) and
# the load average before and after, so a figure is never quoted without what it ran on. Nothing
# is asserted. Usage (from the repository's folder):
#
#   cargo build --release
#   bash benches/headline.sh [RUNS]        # default 3 runs of each command
#
# Set FILMSPLAT=path/to/filmsplat to time another binary (default target/release/filmsplat, or
# `filmsplat` on PATH when that does not exist); HEADLINE_SIZE=64x48 renders smaller, for a
# quick check that the script works (the figures are then not the README's).
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
bin=${FILMSPLAT:-target/release/filmsplat}
[ -x "$bin" ] || bin=$(command -v filmsplat) || {
    echo "headline: build first (cargo build --release) or put filmsplat on PATH" >&2
    exit 2
}
size=${HEADLINE_SIZE:-960x540}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

load() { cut -d' ' -f1-3 /proc/loadavg; }
model=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//' || echo unknown)
mem=$(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo)
echo "machine: $(nproc) CPUs available to this process ($model), $mem; $(uname -sr)"
echo "load average before: $(load)"

measure() { # label, args...: RUNS whole-process runs, wall and CPU seconds each
    local label=$1 i wall user sys
    shift
    for i in $(seq "$runs"); do
        /usr/bin/time -o "$out/time" -f '%e %U %S' "$bin" "$@" --size "$size" -q >/dev/null
        read -r wall user sys <"$out/time"
        awk -v l="$label" -v i="$i" -v w="$wall" -v c="$user + $sys" -v u="$user" -v s="$sys" \
            -v load="$(load | cut -d' ' -f1)" \
            'BEGIN { printf "%s, run %d: wall %.2f s, CPU %.2f s (load %s)\n", l, i, w, u + s, load }'
    done
}

measure "render samples/bubble.toml (200k particles, $size, 4 spp)" \
    render samples/bubble.toml -o "$out/bubble.png"
measure "render tests/data/splishsplash_sphere_shell.ply --preset preview (12k particles, $size, 1 spp)" \
    render tests/data/splishsplash_sphere_shell.ply --preset preview -o "$out/shell.png"
echo "load average after: $(load)"
