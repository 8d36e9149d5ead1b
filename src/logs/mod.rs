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

pub use import::*;
pub use numbered::*;
pub use open::*;
