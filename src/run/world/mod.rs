//! Built-in worlds: the taxi domain and the kitting task.

pub mod kitting;
pub mod random;
pub mod taxi;
