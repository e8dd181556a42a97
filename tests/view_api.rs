//! `filmsplat view`'s HTTP API, in-process: the token, the page, the scene description, and
//! pictures that are exactly what `render` makes of the copied camera lines.

mod view_support;

use filmsplat::pipeline;
use filmsplat::scene::SceneDesc;
use std::path::Path;
use view_support::*;

/// What `filmsplat render` writes for `toml` (a full scene file) with `view`, decoded.
fn rendered_by_the_pipeline(toml: &str, view: Option<&str>) -> (u32, u32, Vec<u8>) {
    let mut desc = SceneDesc::from_toml(toml, "oracle.toml").unwrap();
    desc.render.view = view.map(str::to_string);
    desc.input.time = Some(0.0);
    let p = pipeline::prepare(&desc, Path::new("."), false).unwrap();
    let path = temp("oracle.png");
    match pipeline::render_view(&p, &p.shot).unwrap() {
        Some(v) => pipeline::write_view(&v, &path).unwrap(),
        None => {
            pipeline::write_image(&p.shot, &pipeline::render(&p, &p.shot).unwrap(), &path).unwrap()
        }
    }
    let decoded = decode(&std::fs::read(&path).unwrap());
    std::fs::remove_file(&path).unwrap();
    decoded
}

#[test]
fn every_route_but_the_icon_needs_the_exact_token() {
    let s = start(SCENE);
    for path in [
        "/",
        "/api/scene",
        "/api/render",
        "/api/save",
        "/api/camera",
        "/api/prepare",
        "/nothing",
    ] {
        let r = get_no_token(s.addr, path);
        assert_eq!(r.status, 403, "{path}");
        assert!(r.text().contains("missing token"), "{path}: {}", r.text());
        let r = get_no_token(s.addr, &format!("{path}?token=0123"));
        assert_eq!(r.status, 403, "{path}");
        assert!(r.text().contains("wrong token"), "{path}: {}", r.text());
    }
    assert_eq!(get_no_token(s.addr, "/favicon.ico").status, 204);
    let header = raw(
        s.addr,
        format!(
            "GET /api/scene HTTP/1.1\r\nX-Filmsplat-Token: {TOKEN}\r\nConnection: close\r\n\r\n"
        )
        .as_bytes(),
    );
    assert_eq!(header.status, 200);
    assert_eq!(get(s.addr, "/nothing").status, 404);
}

#[test]
fn the_page_is_one_self_contained_document() {
    let s = start(SCENE);
    let r = get(s.addr, "/");
    assert_eq!(r.status, 200);
    assert_eq!(r.header("content-type"), Some("text/html; charset=utf-8"));
    let page = r.text();
    // The style and the script are inlined; nothing is loaded from anywhere else.
    assert!(
        page.contains("function orbit") && page.contains("#stage"),
        "assets inlined"
    );
    assert!(!page.contains("/*SCRIPT*/") && !page.contains("/*STYLE*/"));
    for outside in ["<script src", "<link", "http://", "https://", "@import"] {
        assert!(!page.contains(outside), "the page refers to {outside}");
    }
    let csp = r.header("content-security-policy").unwrap();
    assert!(csp.contains("default-src 'none'") && csp.contains("connect-src 'self'"));
    assert_eq!(get(s.addr, "/index.html").body, r.body);
}

#[test]
fn the_scene_description_names_frames_camera_and_choices() {
    let s = start_frames(frames(SCENE, 3), u64::MAX);
    let r = get(s.addr, "/api/scene");
    assert_eq!(r.status, 200);
    let j: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    assert_eq!(j["frames"], serde_json::json!(["0", "1", "2"]));
    assert_eq!(j["size"], serde_json::json!([64, 36]));
    assert_eq!(j["particles"], 2000);
    assert_eq!(j["view"], "shaded");
    let views: Vec<&str> = j["views"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    for v in [
        "shaded",
        "thickness",
        "normal",
        "coverage",
        "attribute:thickness",
    ] {
        assert!(views.contains(&v), "{v} in {views:?}");
    }
    // The auto-framed camera looks at the bubble's centre from outside it.
    let pos: Vec<f64> = serde_json::from_value(j["camera"]["position"].clone()).unwrap();
    let look: Vec<f64> = serde_json::from_value(j["camera"]["look_at"].clone()).unwrap();
    let dist = (0..3)
        .map(|i| (pos[i] - look[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        dist > 1.5 && look.iter().all(|c| c.abs() < 0.1),
        "{pos:?} {look:?}"
    );
}

#[test]
fn a_final_picture_is_exactly_what_render_makes_of_the_copied_camera_lines() {
    let s = start(SCENE);
    let lines = get(s.addr, &format!("/api/camera?{CAMERA}")).text();
    assert!(
        lines.starts_with("[camera]\nposition = [0.9, 0.8, 2.9]\n"),
        "{lines}"
    );
    let scene = format!("{SCENE}{lines}");
    for (view, oracle_view) in [("shaded", None), ("thickness", Some("thickness"))] {
        let r = get(
            s.addr,
            &format!("/api/render?{CAMERA}&w=64&h=36&pass=final&view={view}"),
        );
        assert_eq!(r.status, 200, "{}", r.text());
        assert_eq!(r.header("content-type"), Some("image/png"));
        let served = decode(&r.body);
        let oracle = rendered_by_the_pipeline(&scene, oracle_view);
        assert_eq!(
            served, oracle,
            "{view}: the served picture differs from render's"
        );
    }
}

#[test]
fn moving_and_draft_passes_take_one_sample_and_the_final_the_presets() {
    let s = start(SCENE);
    let spp = |pass: &str, preset: &str| {
        let r = get(
            s.addr,
            &format!("/api/render?{CAMERA}&w=32&h=18&pass={pass}&preset={preset}"),
        );
        assert_eq!(r.status, 200, "{}", r.text());
        assert_eq!(decode(&r.body).0, 32);
        r.header("x-spp").unwrap().to_string()
    };
    assert_eq!(spp("move", "scene"), "1");
    assert_eq!(spp("draft", "scene"), "1");
    assert_eq!(spp("final", "scene"), "4");
    assert_eq!(spp("final", "final"), "16");
    assert_eq!(spp("final", "preview"), "1");
    // Three variants: the scene's, final and preview; each built once.
    assert_eq!(
        s.stats().builds.load(std::sync::atomic::Ordering::Relaxed),
        3
    );
}

#[test]
fn a_moving_picture_differs_from_the_final_one_but_shows_the_same_bubble() {
    let s = start(SCENE);
    let pic = |pass: &str| {
        decode(
            &get(
                s.addr,
                &format!("/api/render?{CAMERA}&w=64&h=36&pass={pass}"),
            )
            .body,
        )
        .2
    };
    let (moving, fin) = (pic("move"), pic("final"));
    assert_ne!(moving, fin);
    let mean = |v: &[u8]| v.iter().map(|&b| b as f64).sum::<f64>() / v.len() as f64;
    assert!(
        (mean(&moving) - mean(&fin)).abs() < 12.0,
        "{} {}",
        mean(&moving),
        mean(&fin)
    );
}

#[test]
fn exposure_brightens_a_shaded_picture() {
    let s = start(SCENE);
    let mean = |ev: f32| {
        let r = get(
            s.addr,
            &format!("/api/render?{CAMERA}&w=32&h=18&exposure={ev}"),
        );
        let px = decode(&r.body).2;
        px.iter().map(|&b| b as f64).sum::<f64>() / px.len() as f64
    };
    assert!(mean(2.0) > mean(0.0) + 10.0);
}

#[test]
fn saving_gives_a_named_download_at_the_asked_size() {
    let s = start_frames(frames(SCENE, 2), u64::MAX);
    let r = get(
        s.addr,
        &format!("/api/save?{CAMERA}&w=80&h=30&frame=1&pass=move"),
    );
    assert_eq!(r.status, 200, "{}", r.text());
    assert_eq!(decode(&r.body).0, 80);
    // A save is always the full quality, whatever pass is asked.
    assert_eq!(r.header("x-spp"), Some("4"));
    assert_eq!(
        r.header("content-disposition"),
        Some("attachment; filename=\"test-1-80x30.png\"")
    );
}

#[test]
fn an_attribute_view_is_its_own_variant_and_other_frames_are_built_on_demand() {
    let s = start_frames(frames(SCENE, 3), u64::MAX);
    let r = get(
        s.addr,
        &format!("/api/render?{CAMERA}&w=48&h=27&view=attribute:thickness&frame=2"),
    );
    assert_eq!(r.status, 200, "{}", r.text());
    let mut cached: Vec<(usize, Option<String>)> = s
        .server
        .app()
        .session()
        .cached()
        .into_iter()
        .map(|v| (v.frame, v.attribute))
        .collect();
    cached.sort();
    assert_eq!(cached, vec![(0, None), (2, Some("thickness".into()))]);
    let r = get(
        s.addr,
        &format!("/api/render?{CAMERA}&w=48&h=27&view=attribute:nothing"),
    );
    assert_eq!(r.status, 422);
    assert!(r.text().contains("no attribute 'nothing'"), "{}", r.text());
}

/// The frames the server holds prepared.
fn cached_frames(s: &Running) -> Vec<usize> {
    let session = s.server.app().session();
    session.cached().iter().map(|v| v.frame).collect()
}

#[test]
fn the_least_recently_used_frames_go_when_the_budget_is_exceeded() {
    // A budget below one frame's size keeps only the newest.
    let s = start_frames(frames(SCENE, 3), 1);
    for f in [1, 2] {
        let r = get(s.addr, &format!("/api/render?{CAMERA}&w=16&h=9&frame={f}"));
        assert_eq!(r.status, 200);
        assert_eq!(cached_frames(&s), vec![f]);
    }
    // A generous budget keeps every frame: asking again builds nothing.
    let s = start_frames(frames(SCENE, 3), u64::MAX);
    for f in [1, 2, 1, 2, 0] {
        assert_eq!(
            get(s.addr, &format!("/api/render?{CAMERA}&w=16&h=9&frame={f}")).status,
            200
        );
    }
    assert_eq!(
        s.stats().builds.load(std::sync::atomic::Ordering::Relaxed),
        3
    );
}

#[test]
fn copy_camera_at_a_frame_gives_a_camera_path_key_that_reads_back() {
    let s = start(SCENE);
    let lines = get(s.addr, &format!("/api/camera?{CAMERA}&frame=0")).text();
    assert!(lines.starts_with("[[camera.key]]\nframe = 0\n"), "{lines}");
    let back = SceneDesc::from_toml(&format!("{SCENE}{lines}"), "pasted").unwrap();
    let key = &back.camera.key[0];
    assert_eq!(key.position, [0.9, 0.8, 2.9]);
    assert_eq!((key.look_at, key.fov), (Some([0.0; 3]), Some(40.0)));
    // A frame the server does not show is refused.
    let r = get(s.addr, &format!("/api/camera?{CAMERA}&frame=7"));
    assert_eq!(r.status, 400, "{}", r.text());
}

#[test]
fn the_next_frame_prepared_ahead_gives_its_first_picture_without_a_build() {
    use std::sync::atomic::Ordering::Relaxed;
    let s = start_frames(frames(SCENE, 3), u64::MAX);
    let builds = || s.stats().builds.load(Relaxed);
    assert_eq!(builds(), 1);
    let r = get(s.addr, "/api/prepare?frame=1");
    assert_eq!((r.status, r.text().as_str()), (200, "built"));
    assert!(r.header("X-Build-Ms").is_some());
    assert_eq!(builds(), 2);
    let r = get(s.addr, "/api/prepare?frame=1");
    assert_eq!((r.status, r.text().as_str()), (200, "cached"));
    // The picture of the prepared frame is rendered from it: no build.
    let r = get(s.addr, &format!("/api/render?{CAMERA}&w=16&h=9&frame=1"));
    assert_eq!(r.status, 200);
    assert_eq!(builds(), 2);
    // Its variant is the picture's: another primitive is another variant.
    let r = get(s.addr, "/api/prepare?frame=1&primitive=sphere");
    assert_eq!((r.status, r.text().as_str()), (200, "built"));
    assert_eq!(builds(), 3);
    let r = get(s.addr, "/api/prepare?frame=7");
    assert_eq!(r.status, 400);
    assert!(r.text().contains("frame"), "{}", r.text());
}

#[test]
fn preparing_ahead_never_pushes_out_the_frame_on_screen() {
    use std::sync::atomic::Ordering::Relaxed;
    // A budget below one frame's size: the frame shown stays, the one ahead is not built.
    let s = start_frames(frames(SCENE, 3), 1);
    let r = get(s.addr, "/api/prepare?frame=1");
    assert_eq!((r.status, r.text().as_str()), (200, "skipped"));
    assert_eq!(s.stats().builds.load(Relaxed), 1);
    assert_eq!(cached_frames(&s), vec![0]);
}
