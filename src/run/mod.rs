//! Runs: executing a tree tick by tick with BehaviorTree.CPP's semantics,
//! with leaves driven by a plan, a domain file or a built-in world.

pub mod blackboard;
pub mod domain;
pub mod exec;
pub mod plan;
pub mod replay;
pub mod script;
pub mod status;
pub mod world;

pub use exec::{
    CallRecord, Event, Executor, Flow, Forced, LeafCall, LeafOutcome, Leaves, Parked, RunError,
    RunOptions,
};
pub use status::Status;

use crate::model::{Kind, Tree, Uid, Version};

/// The keys a leaf is matched by in plans and domain files, in order: its
/// fullPath (v4 only), its instance name, its registration ID, the default.
pub fn leaf_keys(tree: &Tree, uid: Uid) -> Vec<String> {
    leaf_keys_under(tree, None, uid)
}

/// `leaf_keys`, given the path of the leaf's scope when it is known.
pub fn leaf_keys_under(tree: &Tree, scope_path: Option<&str>, uid: Uid) -> Vec<String> {
    let n = tree.node(uid);
    let mut keys = Vec::with_capacity(4);
    if tree.version == Version::V4 {
        keys.push(match scope_path {
            Some(p) => tree.full_path_in(p, uid),
            None => tree.full_path(uid),
        });
    }
    if !n.name.is_empty() {
        keys.push(n.name.clone());
    }
    keys.push(n.id.clone());
    keys.push(
        if n.kind == Kind::Condition {
            "@default_condition"
        } else {
            "@default_action"
        }
        .to_string(),
    );
    keys
}
