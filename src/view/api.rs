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

/// `s` as a JSON string literal.
pub fn json_str(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out += "\\\"",
            '\\' => out += "\\\\",
            c if (c as u32) < 0x20 || c == '\u{2028}' || c == '\u{2029}' => {
                out += &format!("\\u{:04x}", c as u32)
            }
            c => out.push(c),
        }
    }
    out + "\""
}

fn json_list(items: &[String]) -> String {
    let v: Vec<String> = items.iter().map(|s| json_str(s)).collect();
    format!("[{}]", v.join(","))
}

fn json_vec3(v: [f32; 3]) -> String {
    format!("[{:?},{:?},{:?}]", v[0], v[1], v[2])
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
    let strings = |v: &[&str]| json_list(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    format!(
        "{{\"title\":{},\"frames\":{},\"camera\":{{\"position\":{},\"look_at\":{},\"up\":{},\"fov\":{:?}}},\
         \"size\":[{},{}],\"primitive\":{},\"view\":{},\"exposure\":{:?},\"views\":{},\"primitives\":{},\
         \"presets\":{},\"particles\":{particles},\"max_side\":{MAX_SIDE},\"max_save_side\":{MAX_SAVE_SIDE}}}",
        json_str(title),
        json_list(labels),
        json_vec3(cam.position),
        json_vec3(cam.look_at),
        json_vec3(cam.up),
        cam.fov,
        d.size.0,
        d.size.1,
        json_str(d.primitive.name()),
        json_str(&d.view),
        d.exposure,
        json_list(&views),
        strings(&params::PRIMITIVES.map(|p| p.name())),
        strings(&params::PRESETS),
    )
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
