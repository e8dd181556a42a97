//! The preview server's routes: the page, the scene's description, pictures, saved images and
//! camera lines. Every route but `/favicon.ico` needs the token.

use super::engine::{self, Defaults};
use super::http::{Request, Response};
use super::params::{self, MAX_SAVE_SIDE, MAX_SIDE, Pass, Refusal, ViewCamera};
use super::session::{SceneFn, Session};
use super::token::Token;
use super::watch::Watcher;
use crate::scene::SceneDesc;
use std::net::TcpStream;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The page, assembled from its parts at start-up.
fn page() -> String {
    include_str!("assets/index.html")
        .replace("/*STYLE*/", include_str!("assets/style.css"))
        .replace("/*SCRIPT*/", include_str!("assets/app.js"))
}

/// The frames a server shows.
pub struct Frames {
    /// One label a frame (its number, or its file's name), in order.
    pub labels: Vec<String>,
    /// The scene of frame `i`.
    pub scene: Box<SceneFn>,
    /// What the page's title says (the first input).
    pub title: String,
}

/// Everything the routes share.
pub struct App {
    token: Token,
    session: Session,
    page: String,
    scene_json: String,
    /// Frame 0's scene description (its lens keys go into the camera lines).
    first: SceneDesc,
    title: String,
    labels: Vec<String>,
    /// The connection's read timeout, restored after a watched render.
    pub request_timeout: Option<Duration>,
    /// The whole time a client has to send one request: from the connection's opening for its
    /// first request, from the first byte for later ones (default 10 s). A client that misses
    /// it is answered 408 (or dropped, if it sent nothing) and its connection closed.
    pub request_deadline: Duration,
    /// Film particles of the first frame.
    pub particles: usize,
}

/// `s` as a JSON string literal (serde_json's escaping: quote, backslash and control
/// characters escaped, everything else as UTF-8).
pub fn json_str(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_default()
}

/// The page's description of the scene (`/scene.json`), written by serde_json: frames,
/// starting camera, choices and defaults.
#[derive(serde::Serialize)]
struct SceneJson<'a> {
    title: &'a str,
    frames: &'a [String],
    camera: CameraJson,
    /// Image size, pixels.
    size: [usize; 2],
    primitive: &'a str,
    view: &'a str,
    /// Exposure, EV.
    exposure: f32,
    views: Vec<String>,
    primitives: Vec<&'a str>,
    presets: &'a [&'a str],
    /// Film particles of frame 0.
    particles: usize,
    /// Largest picture side, pixels.
    max_side: usize,
    /// Largest saved image side, pixels.
    max_save_side: usize,
}

/// The starting camera: scene units, field of view in degrees.
#[derive(serde::Serialize)]
struct CameraJson {
    position: [f32; 3],
    look_at: [f32; 3],
    up: [f32; 3],
    fov: f32,
}

/// The page's description of the scene: frames, starting camera, choices and defaults.
fn scene_json(
    (title, labels): (&str, &[String]),
    cam: &ViewCamera,
    d: &Defaults,
    attributes: &[String],
    particles: usize,
) -> String {
    let mut views: Vec<String> = params::VIEWS.iter().map(|v| v.to_string()).collect();
    views.extend(attributes.iter().map(|a| format!("attribute:{a}")));
    let json = SceneJson {
        title,
        frames: labels,
        camera: CameraJson {
            position: cam.position,
            look_at: cam.look_at,
            up: cam.up,
            fov: cam.fov,
        },
        size: [d.size.0, d.size.1],
        primitive: d.primitive.name(),
        view: &d.view,
        exposure: d.exposure,
        views,
        primitives: params::PRIMITIVES.map(|p| p.name()).to_vec(),
        presets: &params::PRESETS,
        particles,
        max_side: MAX_SIDE,
        max_save_side: MAX_SAVE_SIDE,
    };
    // Serialising plain strings, numbers and arrays cannot fail (non-finite floats become null).
    serde_json::to_string(&json).unwrap_or_default()
}

impl App {
    /// Prepares frame 0 (its default variant), decides the starting camera and lists the
    /// attributes, so a bad input fails here, before the server serves. `budget` bytes of
    /// prepared variants are kept.
    ///
    /// # Errors
    /// Frame 0's scene, build or camera error.
    pub fn new(frames: Frames, token: Token, budget: u64) -> crate::Result<App> {
        let n = frames.labels.len();
        if n == 0 {
            return Err(crate::Error::invalid("view: no frames to show"));
        }
        let (first, base) = (frames.scene)(0)?;
        let defaults = engine::defaults(&first);
        let Frames {
            labels,
            scene,
            title,
        } = frames;
        let session = Session::new(scene, n, budget);
        let variant = params::Variant {
            frame: 0,
            primitive: None,
            preset: None,
            attribute: None,
        };
        let built = session
            .built(&variant)
            .map_err(|(_, m)| crate::Error::invalid(m))?;
        let camera = engine::start_camera(&first, &built)?;
        let attributes = engine::attribute_names(&first, &base)?;
        let scene_json = scene_json(
            (&title, &labels),
            &camera,
            &defaults,
            &attributes,
            built.particles,
        );
        Ok(App {
            token,
            session,
            page: page(),
            scene_json,
            first,
            title,
            labels,
            request_timeout: Some(Duration::from_secs(10)),
            request_deadline: Duration::from_secs(10),
            particles: built.particles,
        })
    }

    /// The session (prepared variants, clients).
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// The token clients must present.
    pub fn token(&self) -> &Token {
        &self.token
    }

    /// True if `req` carries the token (`?token=` or the `X-Filmsplat-Token` header).
    pub fn authorized(&self, req: &Request) -> bool {
        let given = req.param("token").or(req.header("x-filmsplat-token"));
        given.is_some_and(|t| self.token.matches(t))
    }

    /// Answers `req`; `peer` is its connection, watched while a picture renders (a closed
    /// connection cancels it).
    pub fn handle(&self, req: &Request, peer: Option<&TcpStream>) -> Response {
        if req.path == "/favicon.ico" {
            return Response::new(204, "image/x-icon", Vec::new());
        }
        let given = req.param("token").or(req.header("x-filmsplat-token"));
        match given {
            None => {
                return Response::error(
                    403,
                    "missing token: open the URL that `filmsplat view` printed (it ends in ?token=...)",
                );
            }
            Some(t) if !self.token.matches(t) => {
                return Response::error(
                    403,
                    "wrong token: open the URL that `filmsplat view` printed",
                );
            }
            Some(_) => {}
        }
        let result = match req.path.as_str() {
            "/" | "/index.html" => Ok(Response::new(
                200,
                "text/html; charset=utf-8",
                self.page.as_str(),
            )),
            "/api/scene" => Ok(Response::new(
                200,
                "application/json",
                self.scene_json.as_str(),
            )),
            "/api/camera" => self.camera_lines(req),
            "/api/render" => self.picture(req, peer, false),
            "/api/prepare" => self.prepare(req),
            "/api/save" => self.picture(req, peer, true),
            _ => Err((404, format!("no such page: {}", req.path))),
        };
        result.unwrap_or_else(|(status, message)| Response::error(status, &message))
    }

    /// The scene-file lines of the page's camera: `[camera]` lines, or with `frame` (the
    /// index of a numbered frame) a camera path's key at that frame's number
    /// (`[[camera.key]]`).
    fn camera_lines(&self, req: &Request) -> Result<Response, (u16, String)> {
        let c = params::camera(req)?;
        let text = match req.param("frame") {
            None => engine::camera_lines(&self.first, &c),
            Some(i) => {
                let number = i
                    .parse::<usize>()
                    .ok()
                    .and_then(|i| self.labels.get(i))
                    .and_then(|l| l.parse::<u64>().ok())
                    .ok_or_else(|| {
                        (
                            400,
                            format!("frame: '{i}' is not the index of a numbered frame"),
                        )
                    })?;
                engine::key_lines(&self.first, &c, number)
            }
        };
        Ok(Response::new(200, "text/plain; charset=utf-8", text))
    }

    /// Prepares a variant ahead of its first picture (`frame`, `primitive`, `preset`, `view`
    /// as for a picture): 200 with `built`, `cached` or `skipped` (the memory budget would not
    /// keep it beside the prepared ones), and the seconds it took in `X-Build-Ms`.
    fn prepare(&self, req: &Request) -> Result<Response, Refusal> {
        let v = params::variant(req, self.session.frames())?;
        let start = std::time::Instant::now();
        let ahead = self.session.prepare_ahead(&v)?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(Response::new(
            200,
            "text/plain; charset=utf-8",
            ahead.word().as_bytes().to_vec(),
        )
        .with("X-Build-Ms", format!("{ms:.1}")))
    }

    /// A picture (`save`: the full-quality download).
    fn picture(
        &self,
        req: &Request,
        peer: Option<&TcpStream>,
        save: bool,
    ) -> Result<Response, Refusal> {
        let max = if save { MAX_SAVE_SIDE } else { MAX_SIDE };
        let mut job = params::job(req, self.session.frames(), max)?;
        if save {
            job.pass = Pass::Final;
        }
        engine::check_pixels(job.width, job.height).map_err(|m| (413, m))?;
        let client = params::client(req)?;
        let cancel = self.session.begin(client.as_deref());
        let built = self.session.built(&job.variant)?;
        let stats = &self.session.stats;
        stats.active.fetch_add(1, Ordering::SeqCst);
        let rendered = {
            let _watch = Watcher::start(peer, cancel.clone(), self.request_timeout);
            engine::render(&built, &job, cancel)
        };
        stats.active.fetch_sub(1, Ordering::SeqCst);
        let counter = match &rendered {
            Err(crate::Error::Cancelled) => &stats.cancelled,
            _ => &stats.rendered,
        };
        counter.fetch_add(1, Ordering::SeqCst);
        let picture = rendered.map_err(|e| super::session::refusal(&e))?;
        let png = picture.png(job.pass == Pass::Move).map_err(|m| (500, m))?;
        let mut resp = Response::new(200, "image/png", png)
            .with("X-Spp", picture.spp.to_string())
            .with("X-Render-Ms", format!("{:.1}", picture.seconds * 1e3))
            .with("X-Particles", built.particles.to_string());
        if save {
            let safe = |s: &str| -> String {
                s.chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || c == '-' {
                            c
                        } else {
                            '_'
                        }
                    })
                    .collect()
            };
            let stem = std::path::Path::new(&self.title)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let (stem, frame) = (safe(&stem), safe(&self.labels[job.variant.frame]));
            resp = resp.with(
                "Content-Disposition",
                format!(
                    "attachment; filename=\"{stem}-{frame}-{}x{}.png\"",
                    job.width, job.height
                ),
            );
        }
        Ok(resp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A title and labels needing every kind of escaping (quote, backslash, control
    /// characters, non-ASCII, the JavaScript line separator) come back intact from the JSON.
    #[test]
    fn scene_json_escapes_and_parses_back() {
        let title = "run \"7\" C:\\sims\\é\u{1}\n\t\u{2028}end";
        let labels = vec!["0".to_string(), "frame\u{7f}\"1\"".to_string()];
        let cam = ViewCamera {
            position: [1.0, -2.5, 3.25],
            look_at: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov: 35.0,
        };
        let d = Defaults {
            size: (64, 36),
            primitive: crate::geometry::Primitive::Disk,
            view: "shaded".into(),
            exposure: -0.5,
        };
        let text = scene_json((title, &labels), &cam, &d, &["a\\b".into()], 12);
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["title"], title);
        assert_eq!(v["frames"], serde_json::json!(labels));
        assert_eq!(
            v["camera"]["position"],
            serde_json::json!([1.0, -2.5, 3.25])
        );
        assert_eq!(v["size"], serde_json::json!([64, 36]));
        assert_eq!(v["exposure"], -0.5);
        assert_eq!(v["particles"], 12);
        assert_eq!(
            v["views"].as_array().unwrap().last().unwrap(),
            "attribute:a\\b"
        );
        assert_eq!(v["max_side"], MAX_SIDE);
        let lit = json_str(title);
        assert!(!lit.contains('\n') && !lit.contains('\u{1}'), "{lit}");
        assert_eq!(serde_json::from_str::<String>(&lit).unwrap(), title);
    }
}
