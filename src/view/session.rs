//! The server's state between requests: prepared scene variants (geometry built once per frame,
//! primitive and preset, kept while the memory budget allows, least recently used dropped
//! first) and one cancel flag per client, so a tab's new picture stops its previous one.

use super::engine::{self, Built};
use super::params::{Refusal, Variant};
use crate::Error;
use crate::scene::SceneDesc;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

/// The scene of frame `i` of the server's frames: its description and the folder its paths
/// are relative to.
pub type SceneFn = dyn Fn(usize) -> crate::Result<(SceneDesc, PathBuf)> + Send + Sync;

/// Most clients whose cancel flags are remembered.
const MAX_CLIENTS: usize = 256;

/// One variant's place in the cache: built by the first request that needs it, while later
/// ones wait for it.
#[derive(Default)]
struct Slot {
    built: Mutex<Option<Arc<Built>>>,
    used: AtomicU64,
}

impl Slot {
    /// The estimated memory of the prepared variant; `None` while it is being built or if it
    /// is not (yet) prepared.
    fn prepared_bytes(&self) -> Option<u64> {
        Some(self.built.try_lock().ok()?.as_ref()?.bytes)
    }
}

/// What a session has done so far (for tests, benches and the status line).
#[derive(Debug, Default)]
pub struct Stats {
    /// Variants prepared.
    pub builds: AtomicU64,
    /// Pictures rendered to the end.
    pub rendered: AtomicU64,
    /// Pictures cancelled (by a newer one of the same client, a closed connection or the
    /// server stopping).
    pub cancelled: AtomicU64,
    /// Pictures rendering now.
    pub active: AtomicU64,
}

/// What [`Session::prepare_ahead`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ahead {
    /// Prepared now (or by another request that was building it, which this one waited for).
    Built,
    /// Already prepared.
    Cached,
    /// Not prepared: keeping it would exceed the memory budget.
    Skipped,
}

impl Ahead {
    /// The word the API answers with.
    pub fn word(self) -> &'static str {
        match self {
            Ahead::Built => "built",
            Ahead::Cached => "cached",
            Ahead::Skipped => "skipped",
        }
    }
}

/// Prepared variants and client flags.
pub struct Session {
    /// Counters.
    pub stats: Stats,
    scene: Box<SceneFn>,
    frames: usize,
    budget: u64,
    cache: Mutex<HashMap<Variant, Arc<Slot>>>,
    clock: AtomicU64,
    clients: Mutex<HashMap<String, (u64, Arc<AtomicBool>)>>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// The HTTP status for an engine error: bad input 422, a cancelled render 409, else 500.
pub fn refusal(e: &Error) -> Refusal {
    let status = match e {
        Error::Cancelled => 409,
        Error::Internal(_) => 500,
        _ => 422,
    };
    (status, e.to_string())
}

impl Session {
    /// A session over `frames` frames described by `scene`, keeping prepared variants while
    /// their estimated memory stays below `budget` bytes (the most recent one is always kept).
    pub fn new(scene: Box<SceneFn>, frames: usize, budget: u64) -> Session {
        Session {
            stats: Stats::default(),
            scene,
            frames,
            budget,
            cache: Mutex::new(HashMap::new()),
            clock: AtomicU64::new(0),
            clients: Mutex::new(HashMap::new()),
        }
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// The scene description of frame `i`.
    ///
    /// # Errors
    /// The frame's scene error, prefixed with the frame.
    pub fn scene(&self, i: usize) -> Result<(SceneDesc, PathBuf), Refusal> {
        (self.scene)(i).map_err(|e| refusal(&e))
    }

    /// The prepared variant `v`: from the cache, or built now (a second request for it waits
    /// for the first one's build instead of building again).
    ///
    /// # Errors
    /// The frame's scene or build error (not cached: the next request tries again).
    pub fn built(&self, v: &Variant) -> Result<Arc<Built>, Refusal> {
        let now = self.clock.fetch_add(1, Ordering::Relaxed);
        let slot = lock(&self.cache).entry(v.clone()).or_default().clone();
        slot.used.store(now, Ordering::Relaxed);
        let mut built = lock(&slot.built);
        if let Some(b) = built.as_ref() {
            return Ok(b.clone());
        }
        let result = self
            .scene(v.frame)
            .and_then(|(desc, base)| engine::build(&desc, &base, v).map_err(|e| refusal(&e)));
        match result {
            Ok(b) => {
                self.stats.builds.fetch_add(1, Ordering::Relaxed);
                let b = Arc::new(b);
                *built = Some(b.clone());
                drop(built);
                self.evict(v);
                Ok(b)
            }
            Err(e) => {
                drop(built);
                lock(&self.cache).remove(v);
                Err(e)
            }
        }
    }

    /// Prepares `v` ahead of its first picture (the page asks for the next frame of a
    /// sequence while the current one is looked at), unless keeping it would push a prepared
    /// variant out of the memory budget: [`Ahead::Skipped`] when the variants held plus the
    /// largest of them (a frame of a sequence costs about what its neighbours do) exceed it.
    ///
    /// # Errors
    /// As [`Session::built`].
    pub fn prepare_ahead(&self, v: &Variant) -> Result<Ahead, Refusal> {
        let sizes: Vec<u64> = {
            let cache = lock(&self.cache);
            if cache.get(v).is_some_and(|s| s.prepared_bytes().is_some()) {
                return Ok(Ahead::Cached);
            }
            cache.values().filter_map(|s| s.prepared_bytes()).collect()
        };
        let held: u64 = sizes.iter().sum();
        let largest = sizes.iter().copied().max().unwrap_or(0);
        if held.saturating_add(largest) > self.budget {
            return Ok(Ahead::Skipped);
        }
        self.built(v).map(|_| Ahead::Built)
    }

    /// Drops least recently used variants (never `keep`) until the cache fits the budget.
    fn evict(&self, keep: &Variant) {
        let mut cache = lock(&self.cache);
        loop {
            let sizes: Vec<(Variant, u64, u64)> = cache
                .iter()
                .filter_map(|(k, s)| {
                    let b = s.prepared_bytes()?;
                    Some((k.clone(), b, s.used.load(Ordering::Relaxed)))
                })
                .collect();
            let total: u64 = sizes.iter().map(|s| s.1).sum();
            let oldest = sizes
                .iter()
                .filter(|s| &s.0 != keep)
                .min_by_key(|s| s.2)
                .map(|s| s.0.clone());
            match oldest {
                Some(k) if total > self.budget => {
                    cache.remove(&k);
                }
                _ => return,
            }
        }
    }

    /// The variants prepared now.
    pub fn cached(&self) -> Vec<Variant> {
        lock(&self.cache)
            .iter()
            .filter(|(_, s)| s.prepared_bytes().is_some())
            .map(|(k, _)| k.clone())
            .collect()
    }

    /// A cancel flag for a new picture of `client`, raising the flag of the client's previous
    /// picture (a request without a client is a client of its own).
    pub fn begin(&self, client: Option<&str>) -> Arc<AtomicBool> {
        let flag = Arc::new(AtomicBool::new(false));
        let now = self.clock.fetch_add(1, Ordering::Relaxed);
        // `#` cannot start a client's name (see params::client).
        let key = client.map_or_else(|| format!("#{now}"), str::to_string);
        let mut clients = lock(&self.clients);
        if let Some((_, old)) = clients.insert(key, (now, flag.clone())) {
            old.store(true, Ordering::Relaxed);
        }
        if clients.len() > MAX_CLIENTS
            && let Some(k) = clients
                .iter()
                .min_by_key(|(_, (t, _))| *t)
                .map(|(k, _)| k.clone())
        {
            clients.remove(&k);
        }
        flag
    }

    /// Raises every client's flag (the server is stopping).
    pub fn cancel_all(&self) {
        for (_, f) in lock(&self.clients).values() {
            f.store(true, Ordering::Relaxed);
        }
    }
}
