//! Shared by the tests that guard against unbounded loops.

use std::sync::mpsc::RecvTimeoutError;
use std::time::Duration;

/// Runs `f` on its own thread; fails if it has not finished after `seconds`.
pub fn within<T: Send + 'static>(seconds: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(Duration::from_secs(seconds)) {
        Ok(value) => value,
        Err(RecvTimeoutError::Timeout) => {
            panic!("not finished within {seconds} s: an unbounded loop?")
        }
        Err(RecvTimeoutError::Disconnected) => panic!("the case panicked (message above)"),
    }
}
