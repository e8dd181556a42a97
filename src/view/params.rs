//! What a render request asks for, parsed from its query string and checked against strict
//! limits: the camera, the frame, the image size, the view, the preset, the pass.

use super::http::Request;
use crate::geometry::Primitive;

/// The views the page offers besides `attribute:NAME`.
pub const VIEWS: [&str; 6] = [
    "shaded",
    "thickness",
    "normal",
    "depth",
    "coverage",
    "particle-id",
];
/// The primitives the page offers: every one.
pub const PRIMITIVES: [Primitive; Primitive::ALL.len()] = Primitive::ALL;
/// The presets the page offers (`scene`: the scene file's and flags' own settings).
pub const PRESETS: [&str; 4] = ["scene", "preview", "balanced", "final"];
/// Largest side of a picture for the page, pixels.
pub const MAX_SIDE: usize = 4096;
/// Largest side of a saved picture, pixels.
pub const MAX_SAVE_SIDE: usize = 8192;

/// A refused request: the HTTP status and a one-line reason.
pub type Refusal = (u16, String);

/// A camera the page asks for: the scene-file `[camera]` keys.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewCamera {
    /// Eye position, scene units.
    pub position: [f32; 3],
    /// Point looked at, scene units.
    pub look_at: [f32; 3],
    /// Up direction.
    pub up: [f32; 3],
    /// Vertical field of view, degrees (1..170).
    pub fov: f32,
}

/// How much work a picture gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pass {
    /// While the camera moves: 1 sample per pixel, 2 film crossings.
    Move,
    /// The first refinement: 1 sample per pixel, the preview preset's 4 crossings.
    Draft,
    /// The preset's quality: what `filmsplat render` renders for the same scene and camera.
    Final,
}

/// Which prepared scene a picture needs: geometry is built once per variant.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Variant {
    /// Index into the server's frames.
    pub frame: usize,
    /// Primitive replacing the scene's (`None`: the scene's).
    pub primitive: Option<Primitive>,
    /// Preset replacing the scene's settings (`None`: the scene's).
    pub preset: Option<String>,
    /// The attribute of an `attribute:NAME` view (its values are gathered when preparing).
    pub attribute: Option<String>,
}

/// One picture to render.
#[derive(Debug, Clone, PartialEq)]
pub struct Job {
    /// The prepared scene it needs.
    pub variant: Variant,
    /// The camera.
    pub camera: ViewCamera,
    /// Size, pixels.
    pub width: usize,
    /// Size, pixels.
    pub height: usize,
    /// `shaded`, a scientific view, or `attribute:NAME`.
    pub view: String,
    /// How much work.
    pub pass: Pass,
    /// Exposure, EV (`None`: the scene's).
    pub exposure: Option<f32>,
}

fn bad(message: String) -> Refusal {
    (400, message)
}

/// Three comma-separated finite numbers.
fn vec3(req: &Request, key: &str) -> Result<[f32; 3], Refusal> {
    let s = req
        .param(key)
        .ok_or_else(|| bad(format!("missing parameter '{key}' (x,y,z)")))?;
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad(format!("{key}: '{s}' is not three numbers x,y,z")))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([*x, *y, *z]),
        _ => Err(bad(format!(
            "{key}: '{s}' is not three finite numbers x,y,z"
        ))),
    }
}

/// An optional number in `lo..=hi`.
fn number(req: &Request, key: &str, lo: f32, hi: f32) -> Result<Option<f32>, Refusal> {
    let Some(s) = req.param(key) else {
        return Ok(None);
    };
    match s.trim().parse::<f32>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(Some(v)),
        _ => Err(bad(format!("{key}: '{s}' is not a number in {lo}..{hi}"))),
    }
}

/// A whole number in `0..below`, default `default`.
fn index(req: &Request, key: &str, below: usize, default: usize) -> Result<usize, Refusal> {
    let Some(s) = req.param(key) else {
        return Ok(default);
    };
    match s.parse::<usize>() {
        Ok(v) if v < below => Ok(v),
        _ => Err(bad(format!(
            "{key}: '{s}' is not a whole number in 0..{below}"
        ))),
    }
}

/// One of `allowed`, `None` when absent or `scene`.
fn choice(req: &Request, key: &str, allowed: &[&str]) -> Result<Option<String>, Refusal> {
    match req.param(key) {
        None | Some("scene") => Ok(None),
        Some(v) if allowed.contains(&v) => Ok(Some(v.to_string())),
        Some(v) => Err(bad(format!(
            "{key}: unknown '{v}' (expected {})",
            allowed.join(", ")
        ))),
    }
}

/// The primitive a request asks for (`scene` or none: the scene's), by its exact name.
fn primitive(req: &Request) -> Result<Option<Primitive>, Refusal> {
    match req.param("primitive") {
        None | Some("scene") => Ok(None),
        Some(v) => match PRIMITIVES.into_iter().find(|p| p.name() == v) {
            Some(p) => Ok(Some(p)),
            None => Err(bad(format!(
                "primitive: unknown '{v}' (expected {})",
                PRIMITIVES.map(Primitive::name).join(", ")
            ))),
        },
    }
}

/// The camera of a request: `pos`, `look`, `up` and `fov`.
pub fn camera(req: &Request) -> Result<ViewCamera, Refusal> {
    let c = ViewCamera {
        position: vec3(req, "pos")?,
        look_at: vec3(req, "look")?,
        up: vec3(req, "up")?,
        fov: number(req, "fov", 1.0, 170.0)?.unwrap_or(40.0),
    };
    if c.position == c.look_at {
        return Err(bad("pos and look are the same point".into()));
    }
    if c.up == [0.0; 3] {
        return Err(bad("up must not be zero".into()));
    }
    Ok(c)
}

/// The size of a request, `w` and `h`, each side at most `max` pixels (413 beyond).
fn size(req: &Request, max: usize) -> Result<(usize, usize), Refusal> {
    let side = |k: &str| -> Result<u64, Refusal> {
        let s = req
            .param(k)
            .ok_or_else(|| bad(format!("missing parameter '{k}' (pixels)")))?;
        s.parse::<u64>()
            .ok()
            .filter(|v| *v >= 1)
            .ok_or_else(|| bad(format!("{k}: '{s}' is not a whole number of pixels >= 1")))
    };
    let (w, h) = (side("w")?, side("h")?);
    if w > max as u64 || h > max as u64 {
        return Err((
            413,
            format!("requested size {w}x{h} is larger than the limit {max}x{max}"),
        ));
    }
    Ok((w as usize, h as usize))
}

/// The client (browser tab) a request comes from: a new request cancels the client's picture
/// in flight. 1..64 letters, digits, `-` or `_`; absent: a client of its own.
pub fn client(req: &Request) -> Result<Option<String>, Refusal> {
    match req.param("client") {
        None => Ok(None),
        Some(c)
            if (1..=64).contains(&c.len())
                && c.bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_') =>
        {
            Ok(Some(c.to_string()))
        }
        Some(_) => Err(bad(
            "client: 1 to 64 letters, digits, '-' or '_'".to_string()
        )),
    }
}

/// The view and the attribute it needs.
fn view(req: &Request) -> Result<(String, Option<String>), Refusal> {
    let v = req.param("view").unwrap_or("shaded");
    if VIEWS.contains(&v) {
        return Ok((v.to_string(), None));
    }
    match v.strip_prefix("attribute:") {
        Some(name) if (1..=200).contains(&name.len()) => {
            Ok((v.to_string(), Some(name.to_string())))
        }
        _ => Err(bad(format!(
            "view: unknown '{v}' (expected {} or attribute:NAME)",
            VIEWS.join(", ")
        ))),
    }
}

/// The variant (frame, primitive, preset, attribute) of a request; `frames` is the number of
/// frames the server has.
pub fn variant(req: &Request, frames: usize) -> Result<Variant, Refusal> {
    Ok(Variant {
        frame: index(req, "frame", frames, 0)?,
        primitive: primitive(req)?,
        preset: choice(req, "preset", &PRESETS[1..])?,
        attribute: view(req)?.1,
    })
}

/// The whole job of a render request; `max` is the largest side it may ask for.
pub fn job(req: &Request, frames: usize, max: usize) -> Result<Job, Refusal> {
    let (width, height) = size(req, max)?;
    let pass = match req.param("pass").unwrap_or("final") {
        "move" => Pass::Move,
        "draft" => Pass::Draft,
        "final" => Pass::Final,
        p => {
            return Err(bad(format!(
                "pass: unknown '{p}' (expected move, draft or final)"
            )));
        }
    };
    Ok(Job {
        variant: variant(req, frames)?,
        camera: camera(req)?,
        width,
        height,
        view: view(req)?.0,
        pass,
        exposure: number(req, "exposure", -64.0, 64.0)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::view::http::read_request;

    fn req(q: &str) -> Request {
        let text = format!("GET /api/render?{q} HTTP/1.1\r\n\r\n");
        read_request(&mut std::io::BufReader::new(text.as_bytes())).unwrap()
    }

    const OK: &str = "pos=0,0,3&look=0,0,0&up=0,1,0&fov=40&w=96&h=54&frame=1";

    #[test]
    fn a_full_request_gives_its_job() {
        let j = job(
            &req(&format!(
                "{OK}&view=attribute:vrt&pass=move&preset=final&exposure=-1.5"
            )),
            3,
            MAX_SIDE,
        )
        .unwrap();
        assert_eq!(j.camera.position, [0.0, 0.0, 3.0]);
        assert_eq!((j.width, j.height, j.pass), (96, 54, Pass::Move));
        assert_eq!(j.variant.frame, 1);
        assert_eq!(j.variant.attribute.as_deref(), Some("vrt"));
        assert_eq!(j.variant.preset.as_deref(), Some("final"));
        assert_eq!(j.exposure, Some(-1.5));
        let plain = job(&req(OK), 3, MAX_SIDE).unwrap();
        assert_eq!((plain.view.as_str(), plain.pass), ("shaded", Pass::Final));
        assert_eq!(plain.variant.primitive, None);
    }

    #[test]
    fn the_page_offers_every_primitive_and_each_is_accepted() {
        assert_eq!(PRIMITIVES, Primitive::ALL);
        for p in Primitive::ALL {
            let j = job(&req(&format!("{OK}&primitive={}", p.name())), 3, MAX_SIDE).unwrap();
            assert_eq!(j.variant.primitive, Some(p));
        }
        let scene = job(&req(&format!("{OK}&primitive=scene")), 3, MAX_SIDE).unwrap();
        assert_eq!(scene.variant.primitive, None);
    }

    #[test]
    fn every_bad_parameter_is_refused_with_a_reason_naming_it() {
        for (extra, status, names) in [
            ("&pos=1,2", 400, "pos"),
            ("&pos=1,2,nan", 400, "pos"),
            ("&look=0,0,3", 400, "same point"),
            ("&up=0,0,0", 400, "up"),
            ("&fov=0", 400, "fov"),
            ("&w=0", 400, "w:"),
            ("&w=100000&h=100000", 413, "100000x100000"),
            ("&frame=3", 400, "frame"),
            ("&frame=-1", 400, "frame"),
            ("&view=bogus", 400, "view"),
            ("&view=attribute:", 400, "view"),
            ("&primitive=cube", 400, "primitive"),
            ("&preset=fast", 400, "preset"),
            ("&pass=slow", 400, "pass"),
            ("&exposure=99", 400, "exposure"),
        ] {
            // A later duplicate does not override: put the bad value first.
            let q = format!("{}&{OK}", &extra[1..]);
            let (st, message) = job(&req(&q), 3, MAX_SIDE).unwrap_err();
            assert_eq!(st, status, "{extra}: {message}");
            assert!(message.contains(names), "{extra}: {message}");
        }
        assert!(client(&req("client=tab-1_A")).unwrap().is_some());
        assert!(client(&req("client=a%20b")).is_err());
        assert!(client(&req(&format!("client={}", "a".repeat(65)))).is_err());
    }
}
