//! How each command shown in README.md and docs/*.md is run by `tests/docs_commands.rs`.
//!
//! Every command of a ```sh block must have a row here (the test fails on a command it does not
//! know, and on a row no document shows), keyed by its text with comments dropped and spaces
//! collapsed. The commands run in a temporary folder holding small inputs named as the docs name
//! them (see `fixtures` in the test): `frame.ply`, `frames/frame_0000.ply`..`0002`, `frame_m.ply`
//! (thickness in metres), `scene.toml` (the docs' own), `out/0`, `out/1` (a thin-film SPH frame
//! folder), `mesh_0000.ply`, `mesh_0001.ply`, `tests/` (the repository's) and `samples/*.toml`
//! (copies, with 3000 particles instead of 200000). `filmsplat` is the release binary.
//!
//! `{root}` in an `Instead` command is the repository's folder.
//!
//! To add a command to the docs, add its row: prefer `Small` or `AsIs`; use `Instead` for the
//! same command at test scale; `NotRun` only with the reason.

/// How one documented command is run.
pub enum How {
    /// As written.
    AsIs,
    /// As written, plus `--size 64x48 --spp 1` (a render at test scale).
    Small,
    /// This command instead: the same one, at test scale (fewer frames, particles, pixels).
    Instead(&'static str),
    /// `filmsplat view`: this command (at test scale) started with `--port 0` appended, its
    /// page fetched with the printed token, then stopped with Ctrl-C (SIGINT), which must exit 0.
    View(&'static str),
    /// Not run, and why.
    NotRun(&'static str),
}

use How::*;

const SMALL: &str = "--size 64x48 --spp 1";

/// Each documented command and how it is run.
pub const TABLE: &[(&str, How)] = &[
    // sequences: turntables and camera paths
    (
        "filmsplat render tests/data/melp/foam3/50 --frames 0..120 --orbit 360 -o 'turn/{:04}.png'",
        Instead(
            "filmsplat render tests/data/melp/foam3/50 --frames 0..3 --orbit 360 -o turn/{:04}.png --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat render 'frames/frame_{:04}.ply' --frames 0..3 --orbit 30 -o 'spin/{:04}.png'",
        Small,
    ),
    // sequences: motion blur
    (
        "filmsplat render tests/data/thin-film-sph/bursting_bubble/snapshot/100 --shutter 0.5 --frame-time 0.02 -o blurred.png",
        Instead(
            "filmsplat render tests/data/thin-film-sph/bursting_bubble/snapshot/100 --shutter 0.5 --frame-time 0.02 -o blurred.png --size 64x48 --spp 2",
        ),
    ),
    (
        "farm-bench -n 5 --vs 'filmsplat render snapshot/50 -o sharp.png --size 320x180 --spp 8 --quiet' -- filmsplat render snapshot/50 -o blur.png --size 320x180 --spp 8 --quiet --shutter 0.5 --frame-time 0.02",
        NotRun("a benchmark: farm-bench times whole runs on the real frames of /work/shared"),
    ),
    (
        "FILMSPLAT_BENCH_SIZE=320x180 cargo bench --bench colour_visibility -- FRAME...",
        NotRun("a benchmark over the real frames of /work/shared (FRAME... stands for them)"),
    ),
    (
        "farm-bench -n 5 --timeout 400 --vs 'filmsplat-before render drops_floor.toml -o b.png --quiet' -- filmsplat render drops_floor.toml -o a.png --quiet",
        NotRun("a benchmark: farm-bench times two builds on a real frame of /work/shared"),
    ),
    (
        "filmsplat render path.toml --frames 0..48 -o 'path/{:04}.png'",
        Instead(
            "filmsplat render path.toml --frames 22..26 -o path/{:04}.png --size 64x48 --spp 1",
        ),
    ),
    // README: set-up and install
    (
        "cargo run --release -- render samples/bubble.toml -o bubble.png",
        Instead("filmsplat render samples/bubble.toml -o bubble.png --size 64x48 --spp 1"),
    ),
    (
        "bash .ci/run",
        NotRun("the test command itself (this test is part of it)"),
    ),
    (
        "cargo install --path .",
        NotRun("a second full build into ~/.cargo/bin; checked by hand from a clean clone"),
    ),
    (
        "filmsplat convert tests/data/thin-film-sph/bursting_bubble/60 -o f60.ply",
        AsIs,
    ),
    // formats-and-simulators: droplets and bulk liquid
    (
        "filmsplat render tests/data/thin-film-sph/drops_on_film/105 -o drops.png",
        Small,
    ),
    (
        "filmsplat render tests/data/thin-film-sph/drops_on_film/105 --liquid droplets -o dust.png",
        Small,
    ),
    (
        "filmsplat render tests/data/thin-film-sph/drops_on_film/105 --liquid-field exact -o exact.png",
        Small,
    ),
    // README: movies
    (
        "filmsplat render 'out/{}' --frames 0..131 -o burst.mp4 --size 640x360",
        Instead("filmsplat render 'out/{}' --frames 0..2 -o burst.mp4 --size 64x48 --spp 1"),
    ),
    (
        "ffmpeg -i burst.mp4 -vf 'select=eq(n\\,60)' -frames:v 1 burst_60.png",
        Instead(
            "ffmpeg -v error -y -i burst.mp4 -vf 'select=eq(n\\,1)' -frames:v 1 burst_60.png && test -s burst_60.png",
        ),
    ),
    (
        "filmsplat render tests/data/melp/foam3/50 --frames 0..120 --orbit 360 -o foam_turn.mp4",
        Instead(
            "filmsplat render tests/data/melp/foam3/50 --frames 0..2 --orbit 360 -o foam_turn.mp4 --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat render path.toml --frames 0..48 -o path.mp4",
        Instead("filmsplat render path.toml --frames 23..25 -o path.mp4 --size 64x48 --spp 1"),
    ),
    // sequences: movies and encode
    (
        "filmsplat render 'frames/frame_{:04}.ply' --frames 0..240 -o movie.mp4",
        Instead(
            "filmsplat render 'frames/frame_{:04}.ply' --frames 0..3 -o movie.mp4 --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat render samples/oscillating-bubble.toml --frames 0..48 -o osc.webm --fps 12 --crf 35",
        Instead(
            "filmsplat render samples/oscillating-bubble.toml --frames 0..2 -o osc.webm --fps 12 --crf 35 --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..240 --shard 0/2",
        Instead(
            "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..3 --shard 0/2 --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..240 --shard 1/2",
        Instead(
            "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..3 --shard 1/2 --size 64x48 --spp 1",
        ),
    ),
    ("filmsplat encode 'out/{:04}.png' -o movie.mp4", AsIs),
    // benchmarks: movies
    (
        "filmsplat render 'out/{}' --frames 0..48 -o 'png/{:03}.png' --size 640x360 -q",
        Instead(
            "filmsplat render 'out/{}' --frames 0..2 -o 'png/{:03}.png' --size 64x48 --spp 1 -q",
        ),
    ),
    ("filmsplat encode 'png/{:03}.png' -o b1.mp4 -q", AsIs),
    (
        "filmsplat render 'out/{}' --frames 0..48 -o b2.mp4 --size 640x360 -q",
        Instead("filmsplat render 'out/{}' --frames 0..2 -o b2.mp4 --size 64x48 --spp 1 -q"),
    ),
    // first render, own data
    ("filmsplat render samples/bubble.toml -o bubble.png", Small),
    (
        "filmsplat render samples/bubble.toml --preset preview -o quick.png",
        Instead("filmsplat render samples/bubble.toml --preset preview -o quick.png --size 64x48"),
    ),
    (
        "filmsplat render samples/bubble.toml --view thickness -o thickness.png",
        Small,
    ),
    (
        "filmsplat sample bubble -o frame.ply --particles 50000",
        Instead("filmsplat sample bubble -o frame.ply --particles 2000"),
    ),
    ("filmsplat render frame.ply -o frame.png", Small),
    ("filmsplat info frame.ply", AsIs),
    ("filmsplat render frame.ply -o frame.exr", Small),
    (
        "filmsplat render frame.ply --primitive sphere -o balls.png",
        Small,
    ),
    (
        "filmsplat render frame.ply --primitive mls -o mls.png",
        Small,
    ),
    (
        "filmsplat render tests/data/thin-film-sph/bursting_bubble/60 -o f60.png",
        Small,
    ),
    (
        "filmsplat render tests/data/melp/foam3/50 -o foam.png",
        Small,
    ),
    (
        "filmsplat render tests/data/thin-film-sph/bursting_bubble/snapshot/100 --view attribute:vrt -o vrt.png",
        Small,
    ),
    (
        "filmsplat render frame_m.ply --thickness-unit m --thickness-attr rh -o frame_m.png",
        Small,
    ),
    // sequences
    (
        "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..240 --resume",
        Instead(
            "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..3 --resume --size 64x48 --spp 1",
        ),
    ),
    ("filmsplat render 'frames/*.ply' -o 'out/{stem}.png'", Small),
    (
        "filmsplat render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..240 --shard \"$SLURM_ARRAY_TASK_ID/8\" --resume --keep-going -q",
        Instead(
            "export SLURM_ARRAY_TASK_ID=1; filmsplat render 'frames/frame_{:04}.ply' -o 'shard/{:04}.png' --frames 0..3 --shard \"$SLURM_ARRAY_TASK_ID/2\" --resume --keep-going -q --size 64x48 --spp 1 && test -f shard/0001.png && test ! -e shard/0000.png",
        ),
    ),
    (
        "filmsplat sample catenoid -o 'cat/{:04}.ply' --frames 0..48 --sparse 0.2",
        Instead(
            "filmsplat sample catenoid -o 'cat/{:04}.ply' --frames 0..2 --sparse 0.2 --particles 2000",
        ),
    ),
    (
        "cat frame.ply | filmsplat render - -o - > frame.png",
        Instead(
            "cat frame.ply | filmsplat render - -o - --size 64x48 --spp 1 > frame.png && test -s frame.png",
        ),
    ),
    (
        "filmsplat render samples/bubble.toml -o 'seq/{:04}.exr' --frames 0..48 --size 320x180",
        Instead(
            "filmsplat render samples/bubble.toml -o 'seq/{:04}.exr' --frames 0..3 --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat stability 'seq/{:04}.exr' --frames 0..48",
        Instead("filmsplat stability 'seq/{:04}.exr' --frames 0..3"),
    ),
    // the viewer
    (
        "filmsplat view samples/bubble.toml",
        View("filmsplat view samples/bubble.toml"),
    ),
    (
        "filmsplat view 'frames/frame_{:04}.ply' --frames 0..240",
        View("filmsplat view 'frames/frame_{:04}.ply' --frames 0..3"),
    ),
    (
        "filmsplat view 'frames/*.ply' --primitive mls --view thickness",
        View("filmsplat view 'frames/*.ply' --primitive mls --view thickness"),
    ),
    (
        "ssh -L 8765:localhost:8765 node17",
        NotRun("needs a remote machine"),
    ),
    // Python
    (
        "pip install ./python",
        NotRun("python/run_tests.sh installs the package this way, in its own venv"),
    ),
    ("pip install tqdm", NotRun("an optional package from PyPI")),
    // formats and simulators
    (
        "filmsplat info tests/data/splishsplash_sphere_shell.ply",
        AsIs,
    ),
    (
        "filmsplat info tests/data/thin-film-sph/bursting_bubble/60",
        AsIs,
    ),
    (
        "filmsplat convert tests/data/dam_break_frame_9_6859_particles.bgeo -o dam.ply",
        AsIs,
    ),
    (
        "filmsplat render 'out/{}' -o 'burst/{:03}.png' --frames 0..131",
        Instead(
            "filmsplat render 'out/{}' -o 'burst/{:03}.png' --frames 0..2 --size 64x48 --spp 1",
        ),
    ),
    (
        "filmsplat render tests/data/melp/bubble/l_particles_0100.vtp -o melp.png",
        Small,
    ),
    (
        "filmsplat render tests/data/thin-film-sph/bursting_bubble/snapshot/100 --view attribute:v -o speed.png",
        Small,
    ),
    (
        "filmsplat render frame.ply tests/data/splishsplash_sphere_shell.ply -o both.png",
        Small,
    ),
    // hostile input
    (
        "filmsplat render frame.ply --max-memory 8G -o frame.png",
        Small,
    ),
    (
        "FILMSPLAT_MEMORY_LIMIT=512M filmsplat render frame.ply -o frame.png",
        Small,
    ),
    // rendering, scene files, views
    (
        "filmsplat render frame.ply --primitive sphere -o spheres.png",
        Small,
    ),
    (
        "filmsplat render samples/studio.toml --shading spectral --wavelengths 16 -o studio.png",
        Small,
    ),
    (
        "filmsplat render samples/bubble.toml --aperture 0.05 --white-balance 4000 --contrast 1.2 -o graded.png",
        Small,
    ),
    ("filmsplat render scene.toml", Small),
    (
        "filmsplat render scene.toml --spp 16 --size 1920x1080 -o big.png",
        Instead("filmsplat render scene.toml --spp 2 --size 96x54 -o big.png"),
    ),
    (
        "filmsplat render samples/bubble.toml --preset preview -o preview.png",
        Instead(
            "filmsplat render samples/bubble.toml --preset preview -o preview.png --size 64x48",
        ),
    ),
    ("filmsplat chart -o chart.png --max-thickness 1500", AsIs),
    ("filmsplat film --thickness 0,100,300 --angle 0,45,89", AsIs),
    ("filmsplat film --rgb --thickness 0:1500:25 --angle 0", AsIs),
    // compare
    (
        "filmsplat sample bubble -o bubble.ply --particles 50000",
        Instead("filmsplat sample bubble -o bubble.ply --particles 2000"),
    ),
    (
        "filmsplat sample bubble-mesh -o sphere.ply --subdivisions 6",
        Instead("filmsplat sample bubble-mesh -o sphere.ply --subdivisions 3"),
    ),
    (
        "filmsplat compare disk mesh:sphere.ply bubble.ply -o cmp.png",
        Small,
    ),
    ("filmsplat compare disk sphere bubble.ply --json", Small),
    (
        "filmsplat compare disk mesh:'mesh_{:04}.ply' 'frames/frame_{:04}.ply' --frames 0..240 -o 'cmp_{:04}.png'",
        Instead(
            "filmsplat compare disk mesh:'mesh_{:04}.ply' 'frames/frame_{:04}.ply' --frames 0..2 -o 'cmp_{:04}.png' --size 64x48 --spp 1 && test -s cmp_0001.png",
        ),
    ),
    (
        "cargo build --release --features reconstruct",
        NotRun("an optional feature with ~90 extra crates, never built by CI"),
    ),
    (
        "target/release/filmsplat compare disk reconstructed bubble.ply --shell merge",
        NotRun("needs the build with --features reconstruct"),
    ),
    // architecture
    (
        "cargo test --release --test architecture --test code_shape",
        NotRun("cargo inside cargo test would wait for the build lock; .ci/run runs these tests"),
    ),
    (
        "bash .ci/sample-hashes",
        NotRun("renders 34 sample images at full size: minutes"),
    ),
    // benchmarks: measurements that take minutes to hours, and the peers' Python packages
    (
        "cargo build --release --all-targets && cargo bench --no-run",
        NotRun("builds every benchmark: a benchmark set-up, not a test"),
    ),
    (
        "PEERS_PY=peers-venv/bin/python bash benches/remeasure.sh cli pipeline mls fixed studio optics io tradeoffs suite shadings cycles mesh",
        NotRun("the whole benchmark pass: about an hour on a quiet machine"),
    ),
    (
        "python3 -m venv peers-venv && peers-venv/bin/pip install bpy pysplashsurf colour-science numpy OpenEXR matplotlib",
        NotRun("downloads Blender's bpy and the peers' packages for the comparisons"),
    ),
    (
        "python3 benches/suite.py --particles 100000,1000000,4000000,10000000 --size 1280x720 --primitives disk,mls,sphere --shadings lut",
        NotRun("a benchmark up to 10M particles"),
    ),
    (
        "python3 benches/suite.py --particles 1000000 --size 1280x720 --primitives disk,mls,sphere --shadings lut,rgb:4,rgb:8,rgb:16,rgb:32,spectral:8,spectral:16",
        NotRun("a benchmark at 1M particles"),
    ),
    (
        "FILMSPLAT_BENCH_PARTICLES=100000 FILMSPLAT_BENCH_SIZE=320x180 FILMSPLAT_BENCH_PRIMITIVES=disk,mls,sphere cargo bench --bench tradeoffs",
        NotRun("a benchmark (cargo inside cargo test)"),
    ),
    (
        "benches/peers/cycles_bubble.py --particles 200000 --size 320x240 --roulette 0,0.3 --png samples/images/peers_cycles.png",
        NotRun("needs Blender's bpy (PEERS_PY) and minutes of Cycles"),
    ),
    (
        "git clone /path/to/filmsplat /tmp/fresh && cd /tmp/fresh && time bash .ci/run",
        NotRun("the whole test command from scratch (this test is part of it)"),
    ),
    (
        "bash benches/headline.sh",
        Instead("HEADLINE_SIZE=64x48 FILMSPLAT=filmsplat bash {root}/benches/headline.sh 1"),
    ),
];

/// `SMALL`, for the test.
pub fn small_args() -> &'static str {
    SMALL
}
