//! Leaves: a plugin's action or condition, called through `Leaves`, and
//! the built-in leaves (SetBlackboard, Script, AlwaysSuccess, …), as
//! BehaviorTree.CPP's `actions/` are.

use super::*;

/// What a leaf's behaviour is asked to do.
pub struct LeafCall<'a> {
    pub tree: &'a Tree,
    pub uid: Uid,
    pub kind: Kind,
    /// `onRunning` (true) or `onStart` (false); conditions are always false.
    pub resumed: bool,
    pub tick: u32,
    bb: &'a mut Blackboard,
    writes: &'a mut Vec<(EntryId, Value)>,
}

impl LeafCall<'_> {
    /// Whether this leaf is one of Nav2's actions that complete in the tick
    /// they start (`model::nav2`): it takes no RUNNING outcome.
    pub fn completes_at_once(&self) -> bool {
        self.kind == Kind::Action
            && crate::model::nav2::at_once(&self.tree.node(self.uid).id, self.tree.release)
                .is_some()
    }

    /// A port's value: its literal, or the blackboard entry it names.
    pub fn input(&self, port: &str) -> Option<Value> {
        let n = self.tree.node(self.uid);
        let p = n.ports.iter().find(|p| p.name == port)?;
        match &p.value {
            PortValue::Literal(s) => Some(Value::from(s.clone())),
            v => {
                let e = self.bb.port_entry(self.tree, n.scope, v)?;
                self.bb.get(&e).cloned()
            }
        }
    }

    /// Ports this leaf writes to a blackboard entry.
    pub fn output_ports(&self) -> Vec<String> {
        self.tree
            .node(self.uid)
            .ports
            .iter()
            .filter(|p| {
                p.value.key().is_some() && p.assumed_direction() != crate::model::Direction::In
            })
            .map(|p| p.name.clone())
            .collect()
    }

    /// Writes a value through a port; ignored for literal ports.
    pub fn write_port(&mut self, port: &str, v: Value) {
        let n = self.tree.node(self.uid);
        let Some(p) = n.ports.iter().find(|p| p.name == port) else {
            return;
        };
        if let Some(e) = self.bb.port_entry(self.tree, n.scope, &p.value) {
            self.bb.set(&e, v.clone());
            self.writes.push((e, v));
        }
    }

    /// Writes a blackboard entry directly (a domain's state variable).
    pub fn write_entry(&mut self, e: EntryId, v: Value) {
        self.bb.set(&e, v.clone());
        self.writes.push((e, v));
    }

    pub fn blackboard(&self) -> &Blackboard {
        self.bb
    }
}

pub struct LeafOutcome {
    pub status: Status,
    /// The action the leaf chose (Love et al.'s d_i), if it chooses.
    pub decision: Option<String>,
}

/// What the leaves of a tree do: a plan, a domain file, a built-in world.
pub trait Leaves {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome;
    /// `onHalted`: the leaf was RUNNING and is halted.
    fn halt(&mut self, _uid: Uid) {}
    /// Blackboard entries the leaves start with (a domain's state).
    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        Vec::new()
    }
    /// Scripting enums the robot would register (`registerScriptingEnum`),
    /// declared by a plan or a domain: name → value.
    fn enums(&self) -> &[(String, i64)] {
        &[]
    }
    /// Sees every status transition, as a logger would (a replay of a log
    /// follows its position this way).
    fn observe(&mut self, _uid: Uid, _prev: Status, _status: Status) {}
    /// Whether the run is over after a tick that returned `root`: by
    /// default when the root completes; a domain may keep ticking a tree
    /// (a game of several rounds) until a leaf of its own says so.
    fn run_over(&mut self, root: Status) -> bool {
        root != Status::Running
    }
    /// An error the leaves met (a failing script); the run stops on it.
    fn take_error(&mut self) -> Option<crate::source::Located> {
        None
    }
    /// Whether the writes the leaf's last call made, as the leaves gave
    /// them, already hold those of its post-condition scripts (a replay of
    /// a session, which recorded them with the leaf's call): the executor
    /// does not run those scripts again.
    fn post_scripts_recorded(&self, _uid: Uid) -> bool {
        false
    }
}

impl<L: Leaves> Executor<'_, L> {
    pub(super) fn tick_leaf(&mut self, uid: Uid) -> R<Status> {
        let n = self.tree.node(uid);
        let prev = self.status(uid);
        self.leaf_called = false;
        if n.kind == Kind::Action && prev.is_completed() {
            // A StatefulActionNode ticked again before a reset keeps its status.
            return Ok(prev);
        }
        let at_once = if n.kind == Kind::Action {
            crate::model::nav2::at_once(&n.id, self.tree.release)
        } else {
            None
        };
        if at_once == Some(true) && prev == Status::Idle {
            self.set_status(uid, Status::Running);
        }
        let mut writes = Vec::new();
        self.leaf_called = true;
        let out = {
            let mut call = LeafCall {
                tree: self.tree,
                uid,
                kind: n.kind,
                resumed: n.kind == Kind::Action && prev == Status::Running,
                tick: self.tick,
                bb: &mut self.bb,
                writes: &mut writes,
            };
            self.leaves.tick(&mut call)
        };
        for (entry, value) in writes {
            self.events.push(Event::Write {
                tick: self.tick,
                uid,
                entry,
                value,
            });
        }
        if let Some(d) = out.decision {
            if out.status == prev {
                self.events.push(Event::Decision {
                    tick: self.tick,
                    uid,
                    decision: d,
                });
            } else {
                self.pending_decision = Some((uid, d));
            }
        }
        if out.status == Status::Idle {
            return Err(self.err(uid, "the leaf returned IDLE"));
        }
        if at_once.is_some() && out.status == Status::Running {
            return Err(self.err(
                uid,
                format!(
                    "the leaf returned RUNNING, but Nav2's {} completes in the tick it starts (nav2_behavior_tree/plugins/action); give it SUCCESS or FAILURE",
                    n.id
                ),
            ));
        }
        Ok(out.status)
    }

    pub(super) fn tick_builtin_leaf(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        match b {
            Builtin::AlwaysSuccess => Ok(Status::Success),
            Builtin::AlwaysFailure => Ok(Status::Failure),
            Builtin::Sleep => {
                if self.status(uid) == Status::Idle {
                    let ms = self.port_int(uid, &["msec"], None)?;
                    if ms <= 0 {
                        return Ok(Status::Success);
                    }
                    let now = self.now_ms;
                    let r = self.rt(uid);
                    r.deadline = Some(now + ms as u64);
                    r.fired = false;
                    return Ok(Status::Running);
                }
                let r = self.rt(uid);
                if r.fired {
                    r.fired = false;
                    Ok(Status::Success)
                } else {
                    Ok(Status::Running)
                }
            }
            Builtin::SetBlackboard => {
                let value = self
                    .port_str(uid, "value")
                    .ok_or_else(|| self.err(uid, "the port value is missing"))?;
                let n = self.tree.node(uid);
                let key = n
                    .ports
                    .iter()
                    .find(|p| p.name == "output_key")
                    .ok_or_else(|| self.err(uid, "the port output_key is missing"))?;
                let entry = match &key.value {
                    PortValue::Literal(k) => self.bb.resolve(self.tree, n.scope, k),
                    v => self.bb.port_entry(self.tree, n.scope, v).expect("a key"),
                };
                self.write_entry(uid, entry, crate::run::blackboard::typed_literal(&value));
                Ok(Status::Success)
            }
            Builtin::UnsetBlackboard => {
                let n = self.tree.node(uid);
                if let Some(k) = self.port_str(uid, "key") {
                    let e = self.bb.resolve(self.tree, n.scope, &k);
                    self.bb.remove(&e);
                }
                Ok(Status::Success)
            }
            Builtin::Script => {
                let code = self.port_str(uid, "code").unwrap_or_default();
                self.script(uid, &code, "code")?;
                Ok(Status::Success)
            }
            Builtin::ScriptCondition => {
                let code = self.port_str(uid, "code").unwrap_or_default();
                Ok(if self.script_test(uid, &code, "code")? {
                    Status::Success
                } else {
                    Status::Failure
                })
            }
            _ => Err(self.err(
                uid,
                format!(
                    "{} is not run by this version of btx",
                    self.tree.type_name(uid)
                ),
            )),
        }
    }

    /// `setOutput`: writes `v` where output port `port` points (a literal
    /// port is no entry: nothing is written).
    pub(super) fn write_output(&mut self, uid: Uid, port: &str, v: Value) {
        let tree = self.tree;
        let n = tree.node(uid);
        let Some(p) = n.ports.iter().find(|p| p.name == port) else {
            return;
        };
        if let Some(entry) = self.bb.port_entry(tree, n.scope, &p.value) {
            self.write_entry(uid, entry, v);
        }
    }

    /// A node writes an entry: the blackboard, and the event of the run.
    pub(super) fn write_entry(&mut self, uid: Uid, entry: EntryId, v: Value) {
        self.bb.set(&entry, v.clone());
        self.events.push(Event::Write {
            tick: self.tick,
            uid,
            entry,
            value: v,
        });
    }
}
