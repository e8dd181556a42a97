//! `filmsplat view`: an interactive preview in the browser, served by filmsplat itself and
//! rendered by the same engine as `filmsplat render`.
//!
//! A small, strict HTTP/1.1 server on `std::net` and threads ([`server`], [`http`]) serves one
//! page embedded in the binary (`assets/`: HTML, CSS and JavaScript, nothing fetched from the
//! network) and an API the page drives:
//!
//! | route | answers |
//! |---|---|
//! | `/` | the page |
//! | `/api/scene` | JSON: frames, starting camera, views, primitives, presets, defaults |
//! | `/api/render` | a PNG of one frame from one camera ([`params::job`]: `pos`, `look`, `up`, `fov`, `w`, `h`, `frame`, `view`, `primitive`, `preset`, `pass`, `exposure`, `client`) |
//! | `/api/save` | the same at full quality, as a download (sides up to [`params::MAX_SAVE_SIDE`]) |
//! | `/api/camera` | the `[camera]` lines of a scene file for `pos`, `look`, `up`, `fov` |
//!
//! Every route needs the access token ([`token`]): `?token=` or the `X-Filmsplat-Token`
//! header. Geometry is built once per frame, primitive and preset and kept while memory allows
//! ([`session`]); a client's new picture cancels its previous one, and a closed connection
//! cancels its own ([`watch`]). All calls into the engine are in [`engine`].
//!
//! ```no_run
//! use filmsplat::view::{App, Frames, Server, token::Token};
//! use filmsplat::scene::SceneDesc;
//! use std::sync::{Arc, atomic::AtomicBool};
//! let frames = Frames {
//!     labels: vec!["0".into()],
//!     scene: Box::new(|_| {
//!         let d = SceneDesc::from_toml("[input]\nsample = \"bubble\"\n", "inline")?;
//!         Ok((d, std::path::PathBuf::new()))
//!     }),
//!     title: "bubble".into(),
//! };
//! let app = App::new(frames, Token::random().unwrap(), 1 << 30).unwrap();
//! let server = Server::bind("127.0.0.1:0".parse().unwrap(), app, Arc::new(AtomicBool::new(false))).unwrap();
//! println!("{}", server.url());
//! server.run();
//! ```

pub mod admission;
pub mod api;
pub mod engine;
pub mod http;
pub mod params;
pub mod picture;
pub mod server;
pub mod session;
pub mod token;
pub mod watch;

pub use api::{App, Frames};
pub use server::Server;
