//! Decorators, as BehaviorTree.CPP's `decorators/`: Inverter, the
//! Force*, KeepRunningUntilFailure, Timeout, Delay, RunOnce, the
//! blackboard checks, Precondition, Retry, Repeat, Loop and SubTree.

use super::*;

impl<L: Leaves> Executor<'_, L> {
    pub(super) fn tick_subtree(&mut self, uid: Uid) -> R<Status> {
        if self.status(uid) == Status::Idle {
            self.set_status(uid, Status::Running);
        }
        let child = self.tree.node(uid).children[0];
        let s = self.exec(child)?;
        if s.is_completed() {
            self.halt_child(child);
        }
        Ok(s)
    }

    /// Inverter: SUCCESS and FAILURE swapped.
    pub(super) fn tick_inverter(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        Ok(match s {
            Status::Success => {
                self.halt_child(children[0]);
                Status::Failure
            }
            Status::Failure => {
                self.halt_child(children[0]);
                Status::Success
            }
            other => other,
        })
    }

    /// ForceSuccess and ForceFailure: a completed child's status replaced.
    pub(super) fn tick_force(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        if s.is_completed() {
            self.halt_child(children[0]);
            return Ok(if b == Builtin::ForceSuccess {
                Status::Success
            } else {
                Status::Failure
            });
        }
        Ok(s)
    }

    /// KeepRunningUntilFailure: RUNNING while the child succeeds.
    pub(super) fn tick_keep_running(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        match s {
            Status::Failure => {
                self.halt_child(children[0]);
                Ok(Status::Failure)
            }
            Status::Success => {
                self.halt_child(children[0]);
                Ok(Status::Running)
            }
            // A skipped child leaves the node's own RUNNING.
            Status::Skipped => Ok(Status::Running),
            other => Ok(other),
        }
    }

    /// Timeout: the child halted and FAILURE once `msec` pass.
    pub(super) fn tick_timeout(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.rt(uid).started {
            let ms = self.port_int(uid, &["msec"], None)?;
            self.start_timer(uid, ms);
            // No timeout at all when msec <= 0.
            self.rt(uid).fired = false;
        }
        if self.rt(uid).fired {
            let r = self.rt(uid);
            r.started = false;
            r.fired = false;
            return Ok(Status::Failure);
        }
        let s = self.exec(children[0])?;
        if s.is_completed() {
            let r = self.rt(uid);
            r.started = false;
            r.deadline = None;
            self.halt_child(children[0]);
        }
        Ok(s)
    }

    /// Delay: the child ticked once `delay_msec` pass.
    pub(super) fn tick_delay(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.rt(uid).started {
            let ms = self.port_int(uid, &["delay_msec"], None)?;
            self.start_timer(uid, ms);
        }
        if !self.rt(uid).fired {
            return Ok(Status::Running);
        }
        let s = self.exec(children[0])?;
        if s.is_completed() {
            let r = self.rt(uid);
            r.started = false;
            r.fired = false;
            self.halt_child(children[0]);
        }
        Ok(s)
    }

    /// RunOnce: the child's first completion, kept (or skipped after it).
    pub(super) fn tick_run_once(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let skip = self
            .port_str(uid, "then_skip")
            .is_none_or(|s| s.trim() != "false");
        if self.rt(uid).started {
            return Ok(if skip {
                Status::Skipped
            } else {
                self.rt(uid).cached
            });
        }
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        if s.is_completed() {
            let r = self.rt(uid);
            r.started = true;
            r.cached = s;
            self.halt_child(children[0]);
        }
        Ok(s)
    }

    /// BlackboardCheckInt, Double, String and Bool: the child ticked while
    /// the entry equals the value, else `return_on_mismatch`.
    pub(super) fn tick_blackboard_check(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let a = self.port_str(uid, "value_A");
        let bv = self.port_str(uid, "value_B");
        let equal = match (a, bv, b) {
            (Some(a), Some(bv), Builtin::BlackboardCheckInt | Builtin::BlackboardCheckDouble) => {
                match (a.trim().parse::<f64>(), bv.trim().parse::<f64>()) {
                    (Ok(x), Ok(y)) => x == y,
                    _ => a == bv,
                }
            }
            (Some(a), Some(bv), _) => a.trim() == bv.trim(),
            _ => false,
        };
        if equal {
            return self.exec(children[0]);
        }
        if self.status(children[0]) == Status::Running {
            self.halt_child(children[0]);
        }
        let ret = self
            .port_str(uid, "return_on_mismatch")
            .unwrap_or_else(|| "FAILURE".into());
        Status::parse(&ret)
            .ok_or_else(|| self.err(uid, format!("return_on_mismatch=\"{ret}\" is not a status")))
    }

    /// Precondition: the child ticked while `if` holds, else the `else` status.
    pub(super) fn tick_precondition(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let child = children[0];
        let code = self.port_str(uid, "if").unwrap_or_default();
        if self.status(child) == Status::Running || self.script_test(uid, &code, "if")? {
            let s = self.exec(child)?;
            if s.is_completed() {
                self.halt_child(child);
            }
            return Ok(s);
        }
        let otherwise = self
            .port_str(uid, "else")
            .unwrap_or_else(|| "FAILURE".into());
        Status::parse(&otherwise)
            .ok_or_else(|| self.err(uid, format!("else=\"{otherwise}\" is not a status")))
    }

    /// BehaviorTree.CPP 4's wake-up path (`requiresWakeUp() && prev_status
    /// == IDLE`): a node whose child started and completed within one tick
    /// returns RUNNING instead of going on, and goes on at the next tick.
    /// Every tree a v4 factory builds has a wake-up instance; v3 has none.
    pub(super) fn wakes_up(&self, prev: Status) -> bool {
        self.tree.version == crate::model::Version::V4 && prev == Status::Idle
    }

    /// A Retry or Repeat that ticks its child this often within one tick
    /// is making no progress (v3 has no wake-up path to end the loop): the
    /// run stops with an error instead of looping forever.
    pub(super) fn check_progress(&self, uid: Uid, child: Uid) -> R<()> {
        let n = self.calls[(child - 1) as usize];
        if n >= CHILD_TICKS_IN_A_TICK_MAX {
            return Err(self.err(
                uid,
                format!(
                    "ticked its child {} {n} times within tick {} without the tick ending; a loop that makes no progress is stopped (at most {CHILD_TICKS_IN_A_TICK_MAX} ticks of a child within one tick)",
                    self.tree.description(child),
                    self.tick
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn tick_retry(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let max = self.port_int(uid, &["num_attempts"], None)?;
        self.set_status(uid, Status::Running);
        let mut do_loop = self.rt(uid).count < max || max == -1;
        while do_loop {
            self.check_progress(uid, child)?;
            let prev = self.status(child);
            match self.exec(child)? {
                Status::Success => {
                    self.rt(uid).count = 0;
                    self.halt_child(child);
                    return Ok(Status::Success);
                }
                Status::Failure => {
                    let r = self.rt(uid);
                    r.count += 1;
                    do_loop = r.count < max || max == -1;
                    self.halt_child(child);
                    if do_loop && self.wakes_up(prev) {
                        return Ok(Status::Running);
                    }
                }
                Status::Running => return Ok(Status::Running),
                Status::Skipped => {
                    self.halt_child(child);
                    return Ok(Status::Skipped);
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
            }
        }
        self.rt(uid).count = 0;
        Ok(Status::Failure)
    }

    /// BehaviorTree.CPP 4's `LoopNode<T>` (`loop_node.h`): each tick pops
    /// the next value of `queue` into `value` and ticks the child once,
    /// RUNNING until the queue is empty, then `if_empty` (SUCCESS by
    /// default); a child's FAILURE fails it. A queue written in the tree
    /// (`queue="1;2;3"`) is copied afresh each time the node starts; one on
    /// the blackboard is a typed `std::deque` the robot's code puts there,
    /// which btx cannot make.
    pub(super) fn tick_loop(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        let n = tree.node(uid);
        let child = n.children[0];
        let queue = match n.ports.iter().find(|p| p.name == "queue").map(|p| &p.value) {
            Some(PortValue::Literal(q)) => q.clone(),
            Some(v) => {
                return Err(self.err(
                    uid,
                    format!(
                        "{} reads its queue from the blackboard ({}): a typed std::deque the robot's code puts there, which btx cannot make; write the values in the tree to run it, queue=\"1;2;3\"",
                        tree.type_name(uid),
                        v.to_xml()
                    ),
                ))
            }
            None => return Err(self.err(uid, "the port queue is missing")),
        };
        let items: Vec<&str> = queue.split(';').filter(|x| !x.is_empty()).collect();
        if self.status(uid) == Status::Idle {
            let r = self.rt(uid);
            r.idx = 0;
            r.started = false;
        }
        let child_running = self.rt(uid).started;
        if !child_running {
            let Some(raw) = items.get(self.rt(uid).idx).copied() else {
                let e = self
                    .port_str(uid, "if_empty")
                    .unwrap_or_else(|| "SUCCESS".into());
                return Status::parse(&e)
                    .ok_or_else(|| self.err(uid, format!("if_empty=\"{e}\" is not a status")));
            };
            let v = match b {
                Builtin::LoopInt => raw.trim().parse::<i64>().map(Value::from).ok(),
                Builtin::LoopDouble => raw.trim().parse::<f64>().ok().map(Value::from),
                Builtin::LoopBool => match raw.trim() {
                    "true" | "TRUE" | "True" | "1" => Some(Value::Bool(true)),
                    "false" | "FALSE" | "False" | "0" => Some(Value::Bool(false)),
                    _ => None,
                },
                _ => Some(Value::from(raw)),
            }
            .ok_or_else(|| {
                self.err(
                    uid,
                    format!(
                        "queue item \"{raw}\" is not a {}",
                        tree.type_name(uid)
                            .trim_start_matches("Loop")
                            .to_lowercase()
                    ),
                )
            })?;
            self.rt(uid).idx += 1;
            self.write_output(uid, "value", v);
        }
        self.set_status(uid, Status::Running);
        let s = self.exec(child)?;
        self.rt(uid).started = s == Status::Running;
        if s.is_completed() {
            self.halt_child(child);
        }
        Ok(if s == Status::Failure {
            Status::Failure
        } else {
            Status::Running
        })
    }

    pub(super) fn tick_repeat(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let max = self.port_int(uid, &["num_cycles"], None)?;
        self.set_status(uid, Status::Running);
        let mut do_loop = self.rt(uid).count < max || max == -1;
        let mut all_skipped = true;
        while do_loop {
            self.check_progress(uid, child)?;
            let prev = self.status(child);
            let s = self.exec(child)?;
            all_skipped &= s == Status::Skipped;
            match s {
                Status::Success => {
                    let r = self.rt(uid);
                    r.count += 1;
                    do_loop = r.count < max || max == -1;
                    self.halt_child(child);
                    if do_loop && self.wakes_up(prev) {
                        return Ok(Status::Running);
                    }
                }
                Status::Failure => {
                    self.rt(uid).count = 0;
                    self.halt_child(child);
                    return Ok(Status::Failure);
                }
                Status::Running => return Ok(Status::Running),
                Status::Skipped => {
                    self.halt_child(child);
                    return Ok(Status::Skipped);
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
            }
        }
        self.rt(uid).count = 0;
        Ok(if all_skipped {
            Status::Skipped
        } else {
            Status::Success
        })
    }
}
