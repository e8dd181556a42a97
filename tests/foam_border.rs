//! A double bubble's Plateau border drawn with disks (MELP's foam driver, our run of
//! `-driver 2 -test 3`, frame 40: tests/data/melp/double40): where the wall the two bubbles
//! share meets their outer films, the disks must not draw film that the MLS surface of the
//! same particles does not.
//!
//! Property: along each camera ray, the number of film crossings the disks give is at most the
//! MLS surface's. The reference is the MLS surface of the same merged particles (a smooth
//! field, not splats): a crossing more with disks is a splat standing off the sheet.

use filmsplat::geometry::FilmGeometry;
use filmsplat::pipeline;
use filmsplat::scene::SceneDesc;
use std::path::{Path, PathBuf};

/// Pixels of the test view (64×48).
const SIZE: (usize, usize) = (64, 48);

/// The film crossings along each pixel's centre ray, for `primitive`, looking from outside the
/// big bubble at the shared wall just inside the border (top left of the border ring, where
/// the wall bends into the big bubble's outer film).
fn crossings(primitive: &str) -> Vec<usize> {
    let mut desc = SceneDesc::default();
    desc.input.cloud = Some(PathBuf::from(format!(
        "{}/tests/data/melp/double40",
        env!("CARGO_MANIFEST_DIR")
    )));
    desc.render.preset = Some("preview".into());
    desc.film.primitive = Some(primitive.into());
    desc.camera.position = Some([2.8, 1.0, 2.2]);
    desc.camera.look_at = Some([0.35, 0.40, 0.30]);
    desc.camera.fov = Some(8.0);
    desc.render.width = Some(SIZE.0);
    desc.render.height = Some(SIZE.1);
    let p = pipeline::prepare(&desc, Path::new(""), false).expect("prepare");
    let g: &FilmGeometry = &p.scene.geometry;
    let (w, h) = SIZE;
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let (sx, sy) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let ray = p.shot.camera.ray(sx, sy, w as f32 / h as f32);
            let (mut t_min, mut n) = (1e-4, 0);
            while let Some(hit) = g.intersect(&ray, t_min, f32::INFINITY) {
                n += 1;
                t_min = hit.t_exit + 1e-4;
                if n > 16 {
                    break;
                }
            }
            out.push(n);
        }
    }
    out
}

#[test]
fn disks_draw_no_layer_at_a_plateau_border_that_the_mls_surface_lacks() {
    let (disk, mls) = (crossings("disk"), crossings("mls"));
    let more = disk.iter().zip(&mls).filter(|(d, m)| d > m).count();
    let fewer = disk.iter().zip(&mls).filter(|(d, m)| d < m).count();
    let n = disk.len();
    eprintln!("disks cross more layers than MLS at {more} of {n} px, fewer at {fewer}");
    // Wall particles near the border left off the merged wall (half their neighbours across
    // the border): their disks stood up to 1 cm off it and drew pale scallops, a layer the MLS
    // surface lacks: 294 of 3,072 px (9.6 %). Merged in proportion: 55 (1.8 %).
    assert!(more * 25 < n, "{more} of {n} px");
    // Not by drawing less film: crossings the disks miss stay few (84 before, 132 after).
    assert!(fewer * 20 < n, "{fewer} of {n} px");
}
