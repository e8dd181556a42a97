//! Who may hold a connection of the preview server, and for how long.
//!
//! A connection starts *pending*: it has until its deadline (`App::request_deadline`, 10 s,
//! counted from its opening) to send one whole request.
//! Pending connections have a quota of their own ([`MAX_PENDING`]); when it is full, a new
//! connection closes the oldest pending one, so clients that trickle bytes (slowloris) can
//! delay nobody for long and can never fill the slots of token holders. A connection whose
//! request carries the token takes one of the [`MAX_CONNECTIONS`](super::server::MAX_CONNECTIONS)
//! *trusted* slots and keeps it while it is kept alive; every later request on it must also
//! arrive whole within the deadline, counted from its first byte.

use std::collections::VecDeque;
use std::io::Read;
use std::net::{Shutdown, TcpStream};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Most connections at once that have not yet sent a request with the token.
pub const MAX_PENDING: usize = 64;

/// The pending connections, oldest first.
#[derive(Default)]
pub struct Pending {
    next: AtomicU64,
    list: Mutex<VecDeque<(u64, TcpStream)>>,
}

impl Pending {
    /// Registers `stream` as pending and returns its id; if [`MAX_PENDING`] are pending
    /// already, the oldest is shut down (its reader sees the end of the connection). A stream
    /// that cannot be cloned is registered under an id and never evicted (its own deadline
    /// still closes it).
    pub fn admit(&self, stream: &TcpStream) -> u64 {
        let id = self.next.fetch_add(1, Ordering::Relaxed);
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        while list.len() >= MAX_PENDING {
            if let Some((_, oldest)) = list.pop_front() {
                let _ = oldest.shutdown(Shutdown::Both);
            }
        }
        if let Ok(clone) = stream.try_clone() {
            list.push_back((id, clone));
        }
        id
    }

    /// Forgets connection `id` (it became trusted or closed); does nothing if it is gone.
    pub fn leave(&self, id: u64) {
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        list.retain(|(i, _)| *i != id);
    }

    /// Shuts every pending connection down (the server stops).
    pub fn close_all(&self) {
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        for (_, s) in list.drain(..) {
            let _ = s.shutdown(Shutdown::Both);
        }
    }

    /// How many connections are pending now.
    pub fn len(&self) -> usize {
        self.list.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    /// True if no connection is pending.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A stream whose reads all end by one instant: each read waits at most the time left (and at
/// most `per_read`), and once the instant has passed every read fails with
/// [`std::io::ErrorKind::TimedOut`]. This bounds the whole time to receive a request, however
/// slowly its bytes trickle in.
pub struct Deadlined {
    stream: TcpStream,
    /// Reads fail from this instant on.
    pub until: Instant,
    per_read: Option<Duration>,
}

impl Deadlined {
    /// `stream` with no time left until [`Deadlined::until`] is set.
    pub fn new(stream: TcpStream, per_read: Option<Duration>) -> Deadlined {
        Deadlined {
            stream,
            until: Instant::now(),
            per_read,
        }
    }
}

impl Read for Deadlined {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let left = self.until.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(std::io::ErrorKind::TimedOut.into());
        }
        let wait = self.per_read.map_or(left, |p| p.min(left));
        self.stream
            .set_read_timeout(Some(wait.max(Duration::from_millis(1))))?;
        self.stream.read(buf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;

    fn pair(l: &TcpListener) -> (TcpStream, TcpStream) {
        let c = TcpStream::connect(l.local_addr().unwrap()).unwrap();
        let (s, _) = l.accept().unwrap();
        (c, s)
    }

    #[test]
    fn a_full_quota_closes_the_oldest_pending_connection() {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let p = Pending::default();
        let conns: Vec<_> = (0..MAX_PENDING + 1).map(|_| pair(&l)).collect();
        let ids: Vec<u64> = conns.iter().map(|(_, s)| p.admit(s)).collect();
        assert_eq!(p.len(), MAX_PENDING);
        // The first server side was shut down: its client reads the end.
        let mut buf = [0u8; 1];
        let mut first = &conns[0].0;
        first
            .set_read_timeout(Some(Duration::from_secs(30)))
            .unwrap();
        assert_eq!(first.read(&mut buf).unwrap(), 0);
        p.leave(ids[5]);
        assert_eq!(p.len(), MAX_PENDING - 1);
        p.close_all();
        assert!(p.is_empty());
    }

    #[test]
    fn a_deadlined_read_fails_once_the_instant_has_passed() {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let (mut c, s) = pair(&l);
        let mut d = Deadlined::new(s, Some(Duration::from_secs(10)));
        std::io::Write::write_all(&mut c, b"ab").unwrap();
        d.until = Instant::now() + Duration::from_secs(30);
        let mut buf = [0u8; 8];
        assert!(d.read(&mut buf).unwrap() > 0);
        d.until = Instant::now();
        let e = d.read(&mut buf).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::TimedOut);
    }
}
