//! Runs: executing a tree tick by tick with BehaviorTree.CPP's semantics,
//! with leaves driven by a plan, a domain file or a built-in world.

pub mod blackboard;
pub mod domain;
pub mod exec;
pub mod plan;
pub mod script;
pub mod status;
pub mod world;

pub use exec::{Event, Executor, LeafCall, LeafOutcome, Leaves, RunError, RunOptions};
pub use status::Status;
