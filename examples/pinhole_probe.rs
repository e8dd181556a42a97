//! The pinholes of one frame, pixel by pixel: what the render summary's figure counts
//! ([`pipeline::pinholes::front_layer_of`]) and why the film was missed there.
//!
//! `cargo run --release --example pinhole_probe -- FRAME [PRIMITIVE [WxH]]` (PRIMITIVE: disk,
//! sphere or mls, default mls; WxH the image size, default the renderer's) renders FRAME with
//! `--preset preview` from the default camera and
//! prints, for each missing pixel whose ray crosses the film the particles hold
//! ([`FilmSpan::crosses`]), one line with the pixel and the depth found (0: nothing), then one
//! line per particle whose tangent plane the ray crosses within a spacing of it before that
//! depth: the crossing's distance from the particle and the particle's own radius √(A/π) (in
//! spacings), the cosine between ray and normal, and for the MLS surface the field sampled
//! along the ray at 13 points a tenth of a spacing apart around the crossing, each as
//! `[f/spacing w<weight/threshold> c<coherence>]` with `F` where a zero would count as film,
//! then the weight at the particle. On stderr: the count and the figure, which is the summary's.

use filmsplat::geometry::{FilmGeometry, MlsSurface, Ray};
use filmsplat::image::pinholes::missing_pixels;
use filmsplat::pipeline;
use filmsplat::pipeline::pinholes::film_particles;
use filmsplat::pointcloud::span::FilmSpan;
use filmsplat::scene::SceneDesc;
use glam::Vec3;
use std::path::{Path, PathBuf};

/// The film particles as read: positions, unit normals, own radii √(A/π).
struct Film {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    own: Vec<f32>,
}

fn main() {
    let frame = PathBuf::from(
        std::env::args()
            .nth(1)
            .expect("usage: pinhole_probe FRAME [PRIMITIVE [WxH]]"),
    );
    let mut desc = SceneDesc::default();
    desc.input.cloud = Some(frame);
    desc.render.preset = Some("preview".into());
    desc.film.primitive = Some(std::env::args().nth(2).unwrap_or_else(|| "mls".into()));
    if let Some(size) = std::env::args().nth(3) {
        let (w, h) = size.split_once('x').expect("size: WxH");
        desc.render.width = Some(w.parse().expect("width"));
        desc.render.height = Some(h.parse().expect("height"));
    }
    let (positions, normals, own) = film_particles(&desc, Path::new("")).expect("load");
    let film = Film {
        positions,
        normals,
        own,
    };
    let span = FilmSpan::new(&film.positions, &film.normals).with_own_radii(film.own.clone());
    let s = span.spacing();
    let p = pipeline::prepare(&desc, Path::new(""), false).expect("prepare");
    let out = pipeline::render(&p, &p.shot).expect("render");
    let (w, h) = (p.shot.settings.width, p.shot.settings.height);
    let droplets: Vec<bool> = out.droplets.iter().map(|c| *c > 0.0).collect();
    let (interior, missing) = missing_pixels(&out.depth, w, h, &droplets);
    let mls = match &p.scene.geometry {
        FilmGeometry::Mls(m) => Some(m),
        _ => None,
    };
    let mut count = 0;
    for &k in &missing {
        let (x, y) = (k % w, k / w);
        let (sx, sy) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let ray = p.shot.camera.ray(sx, sy, w as f32 / h as f32);
        let t_max = match out.depth[k] {
            d if d > 0.0 => d - s,
            _ => f32::INFINITY,
        };
        if !span.crosses(ray.origin, ray.dir, t_max) {
            continue;
        }
        count += 1;
        println!("pixel {x} {y} depth {:.5} spacing {s:.5}", out.depth[k]);
        for i in 0..film.positions.len() {
            if let Some(line) = crossing(&film, i, &ray, (t_max, s), mls) {
                println!("  {line}");
            }
        }
    }
    let percent = 100.0 * count as f64 / interior.max(1) as f64;
    eprintln!("pinholes: {count} of {interior} interior pixels, {percent:.4} %");
}

/// The line for particle `i` if `ray` crosses its tangent plane within a spacing `s` of it
/// before `t_max`.
fn crossing(
    film: &Film,
    i: usize,
    ray: &Ray,
    (t_max, s): (f32, f32),
    mls: Option<&MlsSurface>,
) -> Option<String> {
    let (q, n) = (film.positions[i], film.normals[i]);
    let cos = n.dot(ray.dir);
    if cos.abs() < 1e-4 {
        return None;
    }
    let t = n.dot(q - ray.origin) / cos;
    let d = (ray.at(t) - q).length();
    if !(t > 0.0 && t < t_max && d < s) {
        return None;
    }
    let own = film.own.get(i).copied().unwrap_or(0.0);
    let mut line = format!(
        "particle {i} t {t:.5} off {:.2} own {:.2} cos {cos:+.2}",
        d / s,
        own / s
    );
    if let Some(m) = mls {
        let th = m.weight_threshold();
        line += " |";
        for j in -6..=6 {
            let x = ray.at(t + j as f32 * 0.1 * s);
            line += &match m.field_at(x) {
                Some(f) => format!(
                    " [{:+.2} w{:.2} c{:.1}{}]",
                    f.f / s,
                    f.weight / th,
                    f.coherence,
                    if f.is_film { "F" } else { "" }
                ),
                None => " [-]".into(),
            };
        }
        if let Some(f) = m.field_at(q) {
            line += &format!(" | at the particle f {:+.2} w{:.2}", f.f / s, f.weight / th);
        }
    }
    Some(line)
}
