//! Blackboards scoped per SubTree instance, with BehaviorTree.CPP's
//! remapping: `a="{x}"` aliases the parent's `x`, literals start the child's
//! entry, `{@key}` is the root's, `_autoremap` falls through to the parent.

use crate::model::{PortValue, Remap, ScopeId, Tree};
use serde_json::Value;
use std::collections::BTreeMap;

/// An entry: the scope that owns it and its key there.
#[derive(
    Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct EntryId {
    pub scope: ScopeId,
    pub key: String,
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Blackboard {
    scopes: Vec<BTreeMap<String, Value>>,
}

/// A literal as BehaviorTree.CPP types it: int or double when it parses
/// fully, else a string.
pub fn typed_literal(s: &str) -> Value {
    if let Ok(i) = s.trim().parse::<i64>() {
        return Value::from(i);
    }
    if let Ok(f) = s.trim().parse::<f64>() {
        if f.is_finite() {
            return Value::from(f);
        }
    }
    Value::from(s)
}

impl Blackboard {
    pub fn new(tree: &Tree) -> Blackboard {
        let mut bb = Blackboard {
            scopes: vec![BTreeMap::new(); tree.scopes.len()],
        };
        for (i, s) in tree.scopes.iter().enumerate() {
            for r in &s.remaps {
                if let Remap::Literal { inner, value } = r {
                    bb.scopes[i].insert(inner.clone(), typed_literal(value));
                }
            }
        }
        bb
    }

    /// Which entry `key` names in `scope`.
    pub fn resolve(&self, tree: &Tree, mut scope: ScopeId, key: &str) -> EntryId {
        let mut key = key.to_string();
        'up: loop {
            let s = &tree.scopes[scope];
            let Some(parent) = s.parent else { break };
            if s.shared {
                scope = parent;
                continue;
            }
            for r in &s.remaps {
                match r {
                    Remap::Key { inner, outer } if *inner == key => {
                        key = outer.clone();
                        scope = parent;
                        continue 'up;
                    }
                    Remap::RootKey { inner, outer } if *inner == key => {
                        return EntryId {
                            scope: 0,
                            key: outer.clone(),
                        };
                    }
                    Remap::Literal { inner, .. } if *inner == key => break 'up,
                    _ => {}
                }
            }
            if s.autoremap && !self.scopes[scope].contains_key(&key) {
                scope = parent;
                continue;
            }
            break;
        }
        EntryId { scope, key }
    }

    /// The entry a port refers to, if it is not a literal.
    pub fn port_entry(&self, tree: &Tree, scope: ScopeId, value: &PortValue) -> Option<EntryId> {
        match value {
            PortValue::Literal(_) => None,
            PortValue::Key(k) => Some(self.resolve(tree, scope, k)),
            PortValue::RootKey(k) => Some(EntryId {
                scope: 0,
                key: k.clone(),
            }),
        }
    }

    pub fn get(&self, e: &EntryId) -> Option<&Value> {
        self.scopes.get(e.scope).and_then(|s| s.get(&e.key))
    }

    /// Sets an entry; a scope the tree does not have (from a damaged
    /// session) is ignored here and refused where the session is read.
    pub fn set(&mut self, e: &EntryId, v: Value) {
        if let Some(s) = self.scopes.get_mut(e.scope) {
            s.insert(e.key.clone(), v);
        }
    }

    pub fn remove(&mut self, e: &EntryId) {
        if let Some(s) = self.scopes.get_mut(e.scope) {
            s.remove(&e.key);
        }
    }

    /// Every entry, for snapshots.
    pub fn entries(&self) -> impl Iterator<Item = (EntryId, &Value)> {
        self.scopes.iter().enumerate().flat_map(|(scope, m)| {
            m.iter().map(move |(k, v)| {
                (
                    EntryId {
                        scope,
                        key: k.clone(),
                    },
                    v,
                )
            })
        })
    }
}

impl EntryId {
    /// `key` in the main tree, `subtree path/key` in a subtree.
    pub fn display(&self, tree: &Tree) -> String {
        let p = tree.scope_path(self.scope);
        if p.is_empty() {
            self.key.clone()
        } else {
            format!("{p}/{}", self.key)
        }
    }
}
