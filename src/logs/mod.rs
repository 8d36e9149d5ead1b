//! Logs that robots already write, opened as sessions.

pub mod btcm;
pub mod btlog;
mod cdr;
pub mod db3;
pub mod fbl;
pub mod rosbag;
pub mod ticks;

mod import;
mod numbered;
mod open;

/// The cores this process may use, asked once: the standard library reads
/// the cgroup's files each time, and a bag's thousands of runs are each
/// numbered (and its pieces each handed out) on their own.
pub(crate) fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

pub use import::*;
pub use numbered::*;
pub use open::*;
