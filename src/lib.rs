//! btx: explain behaviour-tree runs.
//!
//! The pipeline, in module order: the tree model and its XML, then runs
//! and sessions, then explanations, then questions, then the explorer.
//! No module imports a later stage.

// Load errors carry the file's text so that they can show the offending line;
// they are built once, on a cold path, so their size does not matter.
#![allow(clippy::result_large_err)]

// The pipeline in order: each module imports only those declared above it
// (`tests/layers.rs` checks; docs/contributing.md draws it). Blank lines
// keep rustfmt from sorting a stage's modules out of that order.
// Helpers every stage may use:
pub mod text;

pub mod pages;

pub mod source;

pub mod clock;
pub mod rank;
pub mod table;

// The tree: its model, then its XML.
pub mod model;

pub mod xml;

// Running a tree, and views of it.
pub mod frame;
pub mod pick;
pub mod run;

// Runs recorded: sessions, then the logs read into them, robots watched
// live, and any input opened by its kind.
pub mod session;

pub mod logs;

pub mod live;

pub mod input;

// Explanations: Han et al.'s, then the causal model of Love et al.
pub mod explain;

pub mod causal;

// Questions, and runs compared.
pub mod ask;
pub mod diff;

// Fleets, and what is printed or written.
pub mod export;
pub mod fleet;

// The explorer.
pub mod tui;

pub use model::{Kind, Tree, Uid, Version};
pub use source::{Located, Warning};
