//! Reading and writing BehaviorTree.CPP XML.

mod load;
mod parse;
mod write;

pub use load::{load_file, load_str, LoadOptions, Loaded};
pub use write::{sanitize_id, to_instantiated_xml, to_v4_xml};
