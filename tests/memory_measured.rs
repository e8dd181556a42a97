//! The peak-memory estimate (`pipeline::memory`) against a measured allocation: this test
//! binary counts every heap byte through its global allocator and renders the bubble sample
//! through the whole pipeline (generate, estimate, build, render, write a PNG).
//!
//! The estimate exists so a render is refused before the operating system kills it, so it must
//! not fall below what is measured; and it must not be so generous that it refuses renders that
//! fit: the measured per-particle cost must be at least half the estimated one, the whole
//! measured peak (heap only: the estimate's fixed part also covers program and stacks) within
//! a factor 2 of the estimate's.

mod scratch;

use filmsplat::pipeline::{memory, prepare, prepare_with, render, write_image};
use filmsplat::pointcloud::PointCloud;
use filmsplat::scene::SceneDesc;
use glam::Vec3;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes live now and the most live since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, layout, new_size) };
        if !q.is_null() {
            if new_size > layout.size() {
                let grown = new_size - layout.size();
                let live = LIVE.fetch_add(grown, Ordering::Relaxed) + grown;
                PEAK.fetch_max(live, Ordering::Relaxed);
            } else {
                LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        q
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One measurement at a time (the counters are global).
static SERIAL: Mutex<()> = Mutex::new(());

/// Whether the process-wide state a render builds once (colour table, thread pool) exists:
/// a measurement made before it would count it, so which test ran first would decide the
/// figures (the image test's smaller render read 1.45 MB more that way, and passed only then).
static WARM: std::sync::Once = std::sync::Once::new();

/// The bubble sample of `particles` at `width`×`height`, rendered to a PNG: (heap bytes live at
/// the peak above those live before, the estimate).
fn measure(particles: usize, width: usize, height: usize) -> (u64, memory::MemoryEstimate) {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    WARM.call_once(|| {
        let toml = "[input]\nsample = \"bubble\"\nparticles = 500\n\
                    [render]\nwidth = 16\nheight = 12\nspp = 1\n";
        let desc = SceneDesc::from_toml(toml, "inline").unwrap();
        let prepared = prepare(&desc, Path::new("."), false).unwrap();
        render(&prepared, &prepared.shot).unwrap();
    });
    let toml = format!(
        "[input]\nsample = \"bubble\"\nparticles = {particles}\n\
         [render]\nwidth = {width}\nheight = {height}\nspp = 1\n"
    );
    let desc = SceneDesc::from_toml(&toml, "inline").unwrap();
    let estimate = memory::estimate_scene(&desc, Path::new("."), false).unwrap();
    let png = scratch::dir("memory").join(format!("{particles}.png"));
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    {
        let prepared = prepare(&desc, Path::new("."), false).unwrap();
        let out = render(&prepared, &prepared.shot).unwrap();
        write_image(&prepared.shot, &out, &png).unwrap();
    }
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(before) as u64;
    let _ = std::fs::remove_file(&png);
    (peak, estimate)
}

/// Both checks in one test, one after the other: the counters are the process's, and another
/// test's allocations or frees during a measurement would move its figures.
#[test]
fn the_estimate_holds_the_measured_peak_and_image_buffers() {
    the_estimate_holds_the_measured_peak_without_wasting_much();
    the_estimate_holds_the_measured_image_buffers();
    the_estimate_holds_motion_blurs_slices();
}

fn the_estimate_holds_the_measured_peak_without_wasting_much() {
    let (small, e_small) = measure(50_000, 64, 48);
    let (big, e_big) = measure(250_000, 64, 48);
    // Per particle: the difference between the two sizes, so fixed costs cancel.
    let measured = (big - small) as f64 / 200_000.0;
    let estimated = (e_big.total() - e_small.total()) as f64 / 200_000.0;
    assert!(
        measured <= estimated && measured >= 0.5 * estimated,
        "measured {measured:.1} B/particle, estimated {estimated:.1}"
    );
    // The whole peak of the larger render, heap only.
    let heap_estimate = (e_big.total() - e_big.fixed) as f64;
    let ratio = big as f64 / heap_estimate;
    eprintln!("{measured:.1} of {estimated:.1} B/particle; peak {ratio:.2} of the estimate");
    assert!(
        (0.5..=1.0).contains(&ratio),
        "measured peak {big} B is {ratio:.2} of the estimate's {heap_estimate} B"
    );
}

fn the_estimate_holds_the_measured_image_buffers() {
    // Few particles, many pixels: the image buffers dominate.
    let (small, e_small) = measure(2_000, 160, 120);
    let (big, e_big) = measure(2_000, 800, 600);
    let pixels = (800.0 * 600.0) - (160.0 * 120.0);
    let measured = (big - small) as f64 / pixels;
    let estimated = (e_big.image - e_small.image) as f64 / pixels;
    eprintln!("{measured:.1} of {estimated:.1} B/pixel; small {small} big {big}");
    assert!(
        measured <= estimated && measured >= 0.5 * estimated,
        "measured {measured:.1} B/pixel, estimated {estimated:.1}"
    );
}

/// A flat square film of `n` particles 0.01 apart, all moving at 1 along +x.
fn moving_grid(n: usize) -> PointCloud {
    let side = (n as f64).sqrt().ceil() as usize;
    let at = |i: usize| Vec3::new((i % side) as f32 * 0.01, (i / side) as f32 * 0.01, 0.0);
    PointCloud {
        positions: (0..n).map(at).collect(),
        normals: Some(vec![Vec3::Z; n]),
        thickness_nm: Some(vec![400.0; n]),
        radius: Some(vec![0.008; n]),
        extra: ["x", "y", "z"]
            .iter()
            .map(|a| (format!("velocity_{a}"), vec![f32::from(*a == "x"); n]))
            .collect(),
    }
}

/// Heap bytes at the peak of preparing and rendering `moving_grid(n)` at 64x48, 8 spp, with
/// `shutter` lines in `[render]`.
fn measure_moving(n: usize, shutter: &str) -> u64 {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let toml = format!("[render]\nwidth = 64\nheight = 48\nspp = 8\n{shutter}");
    let desc = SceneDesc::from_toml(&toml, "inline").unwrap();
    let cloud = moving_grid(n);
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    {
        let prepared = prepare_with(&desc, Path::new("."), false, Some(cloud)).unwrap();
        render(&prepared, &prepared.shot).unwrap();
    }
    PEAK.load(Ordering::Relaxed).saturating_sub(before) as u64
}

/// What 8 motion-blur slices add to the peak is within the estimate's `motion` part and at
/// least half of it (fails if the estimate leaves the slices out: 0 against ~5 MB).
fn the_estimate_holds_motion_blurs_slices() {
    let n = 10_000;
    let sharp = measure_moving(n, "");
    let blurred = measure_moving(n, "shutter = 1.0\nframe_time = 0.01\nshutter_slices = 8\n");
    let measured = blurred.saturating_sub(sharp) as f64;
    let desc = SceneDesc::from_toml(
        "[input]\nsample = \"bubble\"\nparticles = 10000\n[render]\nwidth = 64\nheight = 48\n\
         spp = 8\nshutter = 1.0\nframe_time = 0.01\nshutter_slices = 8\n",
        "inline",
    )
    .unwrap();
    let estimated = memory::estimate_scene(&desc, Path::new("."), false)
        .unwrap()
        .motion as f64;
    eprintln!("motion blur: measured {measured} B, estimated {estimated} B");
    assert!(
        measured <= estimated && measured >= 0.5 * estimated,
        "8 slices added {measured} B at the peak; the estimate says {estimated}"
    );
}
