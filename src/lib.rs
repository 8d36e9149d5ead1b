//! btx: explain behaviour-tree runs.
//!
//! The pipeline, in module order: the tree model and its XML (`model`, `xml`),
//! then views and explanations over it (`frame`, `pick`, `explain`), then
//! renderings (`export`). No module imports a later stage.

// Load errors carry the file's text so that they can show the offending line;
// they are built once, on a cold path, so their size does not matter.
#![allow(clippy::result_large_err)]

pub mod model;
pub mod rank;
pub mod source;
pub mod table;
pub mod text;
pub mod xml;

pub mod frame;
pub mod pick;
pub mod run;
pub mod session;

pub mod live;
pub mod logs;

pub mod input;

pub mod explain;

pub mod causal;

pub mod ask;

pub mod diff;

pub mod fleet;

pub mod export;

pub mod tui;

pub use model::{Kind, Tree, Uid, Version};
pub use source::{Located, Warning};
