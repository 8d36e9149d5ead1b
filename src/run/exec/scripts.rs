//! A node's scripts: `_skipIf`, `_successIf`, `_failureIf`, `_while`
//! before its tick, `_onSuccess`, `_onFailure`, `_post`, `_onHalted` after.

use super::*;

/// A node's view of the blackboard, for its scripts.
struct NodeEnv<'a> {
    tree: &'a Tree,
    bb: &'a mut Blackboard,
    scope: crate::model::ScopeId,
    writes: &'a mut Vec<(EntryId, Value)>,
    enums: &'a [(String, i64)],
}

impl NodeEnv<'_> {
    fn entry(&self, name: &str) -> EntryId {
        match name.strip_prefix('@') {
            Some(root) => EntryId {
                scope: 0,
                key: root.to_string(),
            },
            None => self.bb.resolve(self.tree, self.scope, name),
        }
    }
}

impl crate::run::script::Env for NodeEnv<'_> {
    fn get(&self, name: &str) -> Option<Value> {
        self.bb.get(&self.entry(name)).cloned()
    }
    fn set(&mut self, name: &str, v: Value) {
        let e = self.entry(name);
        self.bb.set(&e, v.clone());
        self.writes.push((e, v));
    }
    fn enum_value(&self, name: &str) -> Option<Value> {
        self.enums
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| Value::from(*v))
    }
    fn declared(&self, name: &str) -> bool {
        let e = self.entry(name);
        self.tree.nodes.iter().any(|n| {
            n.ports
                .iter()
                .any(|p| self.bb.port_entry(self.tree, n.scope, &p.value).as_ref() == Some(&e))
        })
    }
}

impl<L: Leaves> Executor<'_, L> {
    pub(super) fn script(&mut self, uid: Uid, code: &str, what: &str) -> R<Value> {
        let tree = self.tree;
        let mut writes = Vec::new();
        let r = {
            let mut env = NodeEnv {
                tree,
                bb: &mut self.bb,
                scope: tree.node(uid).scope,
                writes: &mut writes,
                enums: self.leaves.enums(),
            };
            crate::run::script::run(code, &mut env)
        };
        for (entry, value) in writes {
            self.events.push(Event::Write {
                tick: self.tick,
                uid,
                entry,
                value,
            });
        }
        r.map_err(|e| {
            self.err(
                uid,
                format!("{what}=\"{}\": {e}", crate::text::clip(code, QUOTED_MAX)),
            )
        })
    }

    pub(super) fn script_test(&mut self, uid: Uid, code: &str, what: &str) -> R<bool> {
        let v = self.script(uid, code, what)?;
        Ok(match v {
            Value::Bool(b) => b,
            Value::Number(n) => n.as_f64().is_some_and(|x| x != 0.0),
            Value::String(s) => !s.is_empty() && s != "false",
            _ => false,
        })
    }

    pub(super) fn script_attr(&self, uid: Uid, name: &str) -> Option<String> {
        self.tree
            .node(uid)
            .scripts
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.clone())
    }

    /// `checkPreConditions`: `_failureIf`, `_successIf`, `_skipIf` while the
    /// node is IDLE, `_while` while IDLE or RUNNING.
    pub(super) fn pre_conditions(&mut self, uid: Uid) -> R<Option<Status>> {
        if self.tree.node(uid).scripts.is_empty() {
            return Ok(None);
        }
        let status = self.status(uid);
        if status == Status::Idle {
            for (attr, result) in [
                ("_failureIf", Status::Failure),
                ("_successIf", Status::Success),
                ("_skipIf", Status::Skipped),
            ] {
                if let Some(code) = self.script_attr(uid, attr) {
                    if self.script_test(uid, &code, attr)? {
                        return Ok(Some(result));
                    }
                }
            }
        }
        if matches!(status, Status::Idle | Status::Running) {
            if let Some(code) = self.script_attr(uid, "_while") {
                if !self.script_test(uid, &code, "_while")? {
                    if status == Status::Running {
                        self.halt_node(uid);
                    }
                    return Ok(Some(Status::Skipped));
                }
            }
        }
        Ok(None)
    }

    /// `_onSuccess`, `_onFailure` and `_post` after a node completes.
    pub(super) fn post_conditions(&mut self, uid: Uid, s: Status) -> R<()> {
        let which = match s {
            Status::Success => "_onSuccess",
            Status::Failure => "_onFailure",
            _ => return Ok(()),
        };
        for attr in [which, "_post"] {
            if let Some(code) = self.script_attr(uid, attr) {
                self.script(uid, &code, attr)?;
            }
        }
        Ok(())
    }
}
