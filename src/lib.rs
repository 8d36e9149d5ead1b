//! btx: explain behaviour-tree runs.
//!
//! The pipeline, in module order: the tree model and its XML (`model`, `xml`),
//! then views and explanations over it (`frame`, `pick`, `explain`), then
//! renderings (`export`). No module imports a later stage.

pub mod model;
pub mod rank;
pub mod source;
pub mod xml;

pub mod frame;
pub mod pick;

pub mod explain;

pub mod export;

pub use model::{Kind, Tree, Uid, Version};
pub use source::{Located, Warning};
