//! Watching a client while its picture renders: a tab closed (or a fetch aborted) in mid-render
//! closes its connection, and the render is cancelled instead of finishing for no one.

use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

/// How often the connection is looked at.
const POLL: Duration = Duration::from_millis(20);

/// While alive, raises `cancel` as soon as the peer closes the connection. Dropping it stops
/// the watch (and restores the connection's read timeout to `restore`).
pub struct Watcher {
    done: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

/// True if the peer has closed `stream` (a pipelined request waiting counts as open).
fn closed(stream: &TcpStream) -> bool {
    let mut byte = [0u8; 1];
    match stream.peek(&mut byte) {
        Ok(0) => true,
        Ok(_) => false,
        Err(e) => !matches!(
            e.kind(),
            std::io::ErrorKind::WouldBlock
                | std::io::ErrorKind::TimedOut
                | std::io::ErrorKind::Interrupted
        ),
    }
}

impl Watcher {
    /// Starts watching `stream` (nothing is watched for `None`, e.g. in-process calls).
    pub fn start(
        stream: Option<&TcpStream>,
        cancel: Arc<AtomicBool>,
        restore: Option<Duration>,
    ) -> Watcher {
        let done = Arc::new(AtomicBool::new(false));
        let thread = stream.and_then(|s| s.try_clone().ok()).map(|s| {
            let done = done.clone();
            std::thread::spawn(move || {
                let _ = s.set_read_timeout(Some(POLL));
                while !done.load(Ordering::Relaxed) {
                    if closed(&s) {
                        cancel.store(true, Ordering::Relaxed);
                        break;
                    }
                    // peek waited POLL if nothing came; a pipelined request returns at once.
                    std::thread::sleep(POLL / 4);
                }
                let _ = s.set_read_timeout(restore);
            })
        });
        Watcher { done, thread }
    }
}

impl Drop for Watcher {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
