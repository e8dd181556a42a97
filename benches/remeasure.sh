#!/usr/bin/env bash
# Re-measures the figures of docs/benchmarks.md, one section at a time, and logs what
# each printed with the load average before and after. Run it on a quiet machine; nothing is
# asserted. Usage:
#
#   cargo build --release --all-targets
#   bash benches/remeasure.sh [SECTION...]      # default: all, in the order below
#
# Sections: cli (whole-process renders of the README's first table, 3 runs each), pipeline
# (primary rays/s, 1 and 16 spp), mls, fixed (fixed_costs stages), suite (100k-10M, every
# primitive), shadings (each shading mode at 1M), tradeoffs, studio, optics, io, cycles, mesh.
# Output: $OUT (default /tmp/filmsplat-remeasure)/SECTION.log, and the clouds it made.
set -uo pipefail
cd "$(dirname "$0")/.."
bin=target/release/filmsplat
out=${OUT:-/tmp/filmsplat-remeasure}
mkdir -p "$out"
[ -x "$bin" ] || { echo "build first: cargo build --release --all-targets" >&2; exit 2; }

# The peer sections need bpy, pysplashsurf, colour-science, numpy and OpenEXR, and the suite's
# plot matplotlib: PEERS_PY names a python that has them (python3 -m venv V && V/bin/pip install
# bpy pysplashsurf colour-science numpy OpenEXR matplotlib; default python3).
peers_py=${PEERS_PY:-python3}

cloud() { # N -> path of the bubble sample with N particles, made once
  local f="$out/bubble_$1.ply"
  [ -f "$f" ] || "$bin" sample bubble --particles "$1" -o "$f" >/dev/null
  echo "$f"
}

timed() { # label, args... : wall and CPU of one whole process, then its summary line
  local label=$1; shift
  /usr/bin/time -f "$label: wall %e s, user %U s, sys %S s, peak %M KiB" "$bin" "$@" 2>&1 \
    | grep -E "particles \(|wall " | tr '\n' ' '
  echo
}

section_cli() {
  local b1m shell=tests/data/splishsplash_sphere_shell.ply
  b1m=$(cloud 1000000)
  for i in 1 2 3; do
    timed "1M preview" render "$b1m" --preset preview --size 960x540 -o "$out/p.png"
    timed "1M preview raw radii" render "$b1m" --preset preview --size 960x540 --raw-radii -o "$out/p.png"
    timed "1M balanced" render "$b1m" --size 960x540 -o "$out/p.png"
    timed "12k shell preview" render "$shell" --preset preview --size 960x540 -o "$out/p.png"
    timed "12k shell preview 320x180" render "$shell" --preset preview --size 320x180 -o "$out/p.png"
  done
  local scene="$out/bubble_1M.toml"
  sed 's/^particles *=.*/particles = 1000000/' samples/bubble.toml > "$scene"
  for i in 1 2 3; do
    timed "1M generated preview" render "$scene" --preset preview --size 960x540 -o "$out/p.png"
  done
  for f in $shell tests/data/thin-film-sph/bursting_bubble/60 \
    tests/data/thin-film-sph/bursting_bubble/snapshot/100 \
    tests/data/melp/bubble/l_particles_0100.vtp tests/data/melp/foam3/50; do
    for prim in disk mls sphere; do
      timed "$f $prim 640x360 1spp" render "$f" --primitive "$prim" --size 640x360 --spp 1 -o "$out/p.png"
    done
  done
}

section_pipeline() {
  FILMSPLAT_BENCH_SPP=1 cargo bench --quiet --bench pipeline
  cargo bench --quiet --bench pipeline
  cargo bench --quiet --bench render_primary
}

section_mls() {
  FILMSPLAT_BENCH_SIZE=640x360 FILMSPLAT_BENCH_SPP=1 cargo bench --quiet --bench mls
}

section_fixed() {
  local f
  for n in 1000000 4000000; do
    f=$(cloud $n)
    cargo bench --quiet --bench fixed_costs -- "$f"
  done
  cargo bench --quiet --bench fixed_costs -- tests/data/splishsplash_sphere_shell.ply
}

section_suite() {
  for n in 100000 1000000 4000000 10000000; do cloud $n >/dev/null; done
  "$peers_py" benches/suite.py --particles 100000,1000000,4000000,10000000 --size 1280x720 \
    --primitives disk,mls,sphere --shadings lut --out "$out"
  [ -f "$out/suite.png" ] && cp "$out/suite.png" samples/images/suite.png
}

section_shadings() {
  cloud 1000000 >/dev/null
  mkdir -p "$out/shadings"
  python3 benches/suite.py --particles 1000000 --size 1280x720 --primitives disk,mls,sphere \
    --shadings lut,rgb:4,rgb:8,rgb:16,rgb:32,spectral:8,spectral:16 --out "$out/shadings"
}

section_tradeoffs() {
  FILMSPLAT_BENCH_PARTICLES=100000 FILMSPLAT_BENCH_SIZE=320x180 \
    FILMSPLAT_BENCH_PRIMITIVES=disk,mls,sphere cargo bench --quiet --bench tradeoffs
  cp target/tradeoffs.png samples/images/tradeoffs.png
}

section_studio() { cargo bench --quiet --bench studio; }
section_optics() { cargo bench --quiet --bench optics; }
section_io() {
  cargo bench --quiet --bench io_ply
  cargo bench --quiet --bench io_formats
}

section_cycles() {
  "$peers_py" benches/peers/cycles_bubble.py --particles 200000 --size 320x240 --roulette 0,0.3 \
    --out "$out/cycles" --png samples/images/peers_cycles.png
}

section_mesh() { "$peers_py" benches/peers/mesh_pipeline.py --cases bubble,shell,melp --out "$out/mesh"; }

all="cli pipeline mls fixed suite shadings tradeoffs studio optics io cycles mesh"
for s in ${@:-$all}; do
  declare -F "section_$s" >/dev/null || { echo "unknown section $s (know: $all)" >&2; exit 2; }
  {
    echo "## $s — $(date -u +%FT%TZ), load before: $(cut -d' ' -f1-3 /proc/loadavg)"
    "section_$s"
    echo "## $s done — $(date -u +%FT%TZ), load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  } 2>&1 | tee "$out/$s.log"
done
