//! Tests of the per-frame camera: orbit angles, and keys against the spline's defining
//! properties (through every key, continuous velocity at keys, hold outside).

use super::*;
use crate::scene::SceneDesc;

fn start() -> CameraDesc {
    CameraDesc {
        position: Some([1.0, 2.0, 5.0]),
        look_at: Some([1.0, 0.5, 1.0]),
        ..CameraDesc::default()
    }
}

/// The angle (degrees, counter-clockwise seen from +y) of `p` about the vertical through `t`.
fn azimuth(p: [f32; 3], t: [f32; 3]) -> f64 {
    let (dx, dz) = ((p[0] - t[0]) as f64, (p[2] - t[2]) as f64);
    // Counter-clockwise from +z toward +x about +y.
    dx.atan2(dz).to_degrees()
}

#[test]
fn an_orbit_turns_frame_i_of_n_by_deg_i_over_n_about_up() {
    let mv = CameraMove::of(&CameraDesc {
        orbit: Some(360.0),
        ..start()
    })
    .unwrap();
    let frames: Vec<u64> = (10..34).collect();
    let s = start();
    let (p0, t) = (s.position.unwrap(), s.look_at.unwrap());
    for &f in &frames {
        let c = mv.at(&s, &frames, f).unwrap().camera;
        let p = c.position.unwrap();
        let want = 360.0 * (f - 10) as f64 / 24.0;
        let turned = (azimuth(p, t) - azimuth(p0, t)).rem_euclid(360.0);
        let err = (turned - want).abs().min(360.0 - (turned - want).abs());
        assert!(err < 1e-3, "frame {f}: turned {turned}, want {want}");
        // Height and distance from the axis are kept; the look-at point stays.
        assert!((p[1] - p0[1]).abs() < 1e-5);
        let r = |p: [f32; 3]| (p[0] - t[0]).hypot(p[2] - t[2]);
        assert!((r(p) - r(p0)).abs() < 1e-5);
        assert_eq!(c.look_at, s.look_at);
    }
    // Frame i of N: a full turn ends one step short of the start (no repeated frame).
    let last = mv.at(&s, &frames, 33).unwrap().camera.position.unwrap();
    assert!((azimuth(last, t) - azimuth(p0, t)).rem_euclid(360.0) > 344.0);
}

#[test]
fn bad_moves_are_refused() {
    let nan = CameraDesc {
        orbit: Some(f32::NAN),
        ..start()
    };
    assert!(
        CameraMove::of(&nan)
            .unwrap_err()
            .to_string()
            .contains("camera.orbit")
    );
    let both = SceneDesc::from_toml(
        "[camera]\norbit = 90\n[[camera.key]]\nframe = 0\nposition = [0, 0, 5]\n",
        "both.toml",
    )
    .unwrap();
    let e = CameraMove::of(&both.camera).unwrap_err().to_string();
    assert!(e.contains("choose one"), "{e}");
    let no_target = CameraDesc {
        position: Some([0.0, 0.0, 5.0]),
        orbit: Some(90.0),
        ..CameraDesc::default()
    };
    assert!(CameraMove::of(&no_target).is_err());
    assert_eq!(CameraMove::of(&start()).unwrap(), CameraMove::Fixed);
}

fn keys() -> Vec<CameraKey> {
    let k = |frame, position, fov| CameraKey {
        frame,
        position,
        look_at: Some([0.0, 0.0, 0.0]),
        fov: Some(fov),
        ..CameraKey::default()
    };
    vec![
        k(0, [0.0, 0.0, 5.0], 40.0),
        k(10, [5.0, 1.0, 0.0], 30.0),
        k(14, [0.0, 2.0, -5.0], 50.0),
        k(40, [-5.0, 0.0, 0.0], 35.0),
    ]
}

fn pos(keys: &[CameraKey], t: f64) -> DVec3 {
    v64(along_keys(keys, t, &CameraDesc::default())
        .camera
        .position
        .unwrap())
}

#[test]
fn keys_pass_through_every_key_and_hold_outside() {
    let ks = keys();
    for k in &ks {
        let c = along_keys(&ks, k.frame as f64, &CameraDesc::default());
        let p = c.camera.position.unwrap();
        for i in 0..3 {
            assert!(
                (p[i] - k.position[i]).abs() < 1e-5,
                "key {}: {p:?}",
                k.frame
            );
        }
        assert!((c.camera.fov.unwrap() - k.fov.unwrap()).abs() < 1e-5);
    }
    assert_eq!(pos(&ks, -30.0), pos(&ks, 0.0));
    assert_eq!(pos(&ks, 100.0), pos(&ks, 40.0));
    // One key: that camera everywhere.
    assert_eq!(pos(&ks[1..2], 3.0), v64(ks[1].position));
}

#[test]
fn keys_are_c1_at_every_key_and_scalars_ease() {
    let ks = keys();
    let h = 1e-4;
    for k in &ks[1..ks.len() - 1] {
        let x = k.frame as f64;
        let left = (pos(&ks, x) - pos(&ks, x - h)) / h;
        let right = (pos(&ks, x + h) - pos(&ks, x)) / h;
        // f32 positions: differences of 1e-4 frames resolve velocities to ~1e-2.
        assert!(
            (left - right).length() < 0.05 * left.length().max(1.0),
            "kink at frame {}: {left} vs {right}",
            k.frame
        );
        // Not a trivially smooth path: the velocity is substantial.
        assert!(left.length() > 0.1);
    }
    // A polyline (what a kink looks like) fails the same check: its velocity jumps at 10.
    let lin = |t: f64| {
        let (a, b, c) = (
            v64(ks[0].position),
            v64(ks[1].position),
            v64(ks[2].position),
        );
        if t <= 10.0 {
            a + (b - a) * t / 10.0
        } else {
            b + (c - b) * (t - 10.0) / 4.0
        }
    };
    let (l, r) = (
        (lin(10.0) - lin(10.0 - h)) / h,
        (lin(10.0 + h) - lin(10.0)) / h,
    );
    assert!((l - r).length() > 0.05 * l.length());
    // Eased: the field of view stands still at a key and is halfway at mid-span.
    let fov = |t: f64| {
        along_keys(&ks, t, &CameraDesc::default())
            .camera
            .fov
            .unwrap() as f64
    };
    assert!((fov(10.0 + 0.01) - fov(10.0)).abs() < 1e-3);
    assert!((fov(5.0) - 35.0).abs() < 1e-4);
    // Exposure not keyed: none set.
    assert_eq!(along_keys(&ks, 5.0, &CameraDesc::default()).exposure, None);
}

#[test]
fn the_printed_path_reads_back_to_the_same_keys() {
    let ks = keys();
    let text = path_toml(&start(), &CameraMove::Keys(ks.clone()));
    let back = SceneDesc::from_toml(&text, "printed").unwrap();
    let strip = |k: &[CameraKey]| -> Vec<CameraKey> {
        k.iter()
            .map(|k| CameraKey {
                line: 0,
                ..k.clone()
            })
            .collect()
    };
    assert_eq!(strip(&back.camera.key), strip(&ks), "{text}");
    let orbit = path_toml(&start(), &CameraMove::Orbit { degrees: 360.0 });
    let back = SceneDesc::from_toml(&orbit, "printed").unwrap();
    assert_eq!(back.camera.orbit, Some(360.0));
    assert_eq!(back.camera.position, start().position);
}
