//! Control nodes, as BehaviorTree.CPP's `controls/`: the sequences,
//! fallbacks and their reactive forms, Parallel, ParallelAll, IfThenElse,
//! WhileDoElse, TryCatch and Switch.

use super::*;

impl<L: Leaves> Executor<'_, L> {
    /// IfThenElse: the condition, then its branch until that completes.
    pub(super) fn tick_if_then_else(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        if self.rt(uid).idx == 0 {
            match self.exec(children[0])? {
                Status::Running => return Ok(Status::Running),
                Status::Success => self.rt(uid).idx = 1,
                Status::Failure if children.len() == 3 => self.rt(uid).idx = 2,
                Status::Failure => return Ok(Status::Failure),
                // BehaviorTree.CPP keeps the index at 0 and throws.
                _ => return Err(self.err(uid, "its condition was skipped; BehaviorTree.CPP throws \"Something unexpected happened in IfThenElseNode\"")),
            }
        }
        let i = self.rt(uid).idx;
        let s = self.exec(children[i])?;
        if s == Status::Running {
            return Ok(s);
        }
        self.reset_children(uid);
        self.rt(uid).idx = 0;
        Ok(s)
    }

    /// WhileDoElse: the condition every tick, and the branch it chooses (the other halted).
    pub(super) fn tick_while_do_else(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let c = self.exec(children[0])?;
        let s = match c {
            Status::Running => return Ok(Status::Running),
            Status::Success => {
                if children.len() == 3 {
                    self.halt_child(children[2]);
                }
                self.exec(children[1])?
            }
            Status::Failure if children.len() == 3 => {
                self.halt_child(children[1]);
                self.exec(children[2])?
            }
            Status::Failure => Status::Failure,
            // BehaviorTree.CPP returns IDLE, and setting it throws.
            _ => return Err(self.err(uid, "its condition was skipped; BehaviorTree.CPP throws \"you are not allowed to set manually the status to IDLE\"")),
        };
        if s == Status::Running {
            return Ok(s);
        }
        self.reset_children(uid);
        Ok(s)
    }

    /// Sequence (`goes_on` = SUCCESS) and Fallback (FAILURE), mirrors of
    /// each other; the Async variants return after a child that completed
    /// at once, so that one child runs per tick.
    pub(super) fn tick_sequential(&mut self, uid: Uid, asynch: bool, goes_on: Status) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.status(uid).is_active() {
            self.rt(uid).skipped = 0;
        }
        self.set_status(uid, Status::Running);
        while self.rt(uid).idx < children.len() {
            let c = children[self.rt(uid).idx];
            let prev = self.status(c);
            match self.exec(c)? {
                Status::Running => return Ok(Status::Running),
                Status::Skipped => {
                    let r = self.rt(uid);
                    r.idx += 1;
                    r.skipped += 1;
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
                s if s == goes_on => {
                    self.rt(uid).idx += 1;
                    if asynch && prev == Status::Idle && self.rt(uid).idx < children.len() {
                        return Ok(Status::Running);
                    }
                }
                s => {
                    self.reset_children(uid);
                    self.rt(uid).idx = 0;
                    return Ok(s);
                }
            }
        }
        // The count starts again once the node completes: a node that
        // returned SKIPPED stays RUNNING, and ticked again it counts anew.
        let all_skipped = self.rt(uid).skipped == children.len();
        self.reset_children(uid);
        let r = self.rt(uid);
        r.idx = 0;
        r.skipped = 0;
        Ok(if all_skipped {
            Status::Skipped
        } else {
            goes_on
        })
    }

    pub(super) fn tick_sequence_with_memory(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.status(uid).is_active() {
            self.rt(uid).skipped = 0;
        }
        self.set_status(uid, Status::Running);
        while self.rt(uid).idx < children.len() {
            let i = self.rt(uid).idx;
            let prev = self.status(children[i]);
            match self.exec(children[i])? {
                Status::Running => return Ok(Status::Running),
                Status::Failure => {
                    // The index is kept: the next tick resumes at the failed child.
                    for &c in &children[i..] {
                        self.halt_child(c);
                    }
                    return Ok(Status::Failure);
                }
                Status::Success => {
                    self.rt(uid).idx += 1;
                    if self.rt(uid).idx < children.len() && self.wakes_up(prev) {
                        return Ok(Status::Running);
                    }
                }
                Status::Skipped => {
                    let r = self.rt(uid);
                    r.idx += 1;
                    r.skipped += 1;
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
            }
        }
        let all_skipped = self.rt(uid).skipped == children.len();
        self.reset_children(uid);
        let r = self.rt(uid);
        r.idx = 0;
        r.skipped = 0;
        Ok(if all_skipped {
            Status::Skipped
        } else {
            Status::Success
        })
    }

    /// ReactiveSequence (`goes_on` = SUCCESS) and ReactiveFallback (FAILURE).
    pub(super) fn tick_reactive(&mut self, uid: Uid, goes_on: Status) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if self.status(uid) == Status::Idle {
            self.rt(uid).idx = 0;
        }
        self.set_status(uid, Status::Running);
        let mut all_skipped = true;
        for (i, &c) in children.iter().enumerate() {
            let s = self.exec(c)?;
            all_skipped &= s == Status::Skipped;
            match s {
                Status::Running => {
                    for (j, &other) in children.iter().enumerate() {
                        if j != i {
                            self.halt_child(other);
                        }
                    }
                    if self.rt(uid).idx == 0 {
                        self.rt(uid).idx = i + 1;
                    }
                    return Ok(Status::Running);
                }
                Status::Skipped => self.halt_child(c),
                s if s == goes_on => {}
                s => {
                    self.reset_children(uid);
                    return Ok(s);
                }
            }
        }
        self.reset_children(uid);
        Ok(if all_skipped {
            Status::Skipped
        } else {
            goes_on
        })
    }

    pub(super) fn tick_parallel(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let n = children.len() as i64;
        let v3 = self.tree.version == crate::model::Version::V3;
        let success = self.port_int(
            uid,
            &["success_count", "success_threshold"],
            Some(if v3 { n } else { -1 }),
        )?;
        let failure = self.port_int(uid, &["failure_count", "failure_threshold"], Some(1))?;
        let threshold = |t: i64| if t < 0 { (n + t + 1).max(0) } else { t };
        let (need_s, need_f) = (threshold(success), threshold(failure));
        if n < need_s || n < need_f {
            return Err(self.err(
                uid,
                format!(
                    "{n} children cannot reach the thresholds (success {need_s}, failure {need_f})"
                ),
            ));
        }
        // Skips are counted within the tick (BehaviorTree.CPP's local
        // count): a child skipped in an earlier tick is ticked again.
        self.rt(uid).skipped = 0;
        if self.rt(uid).completed.len() != children.len() {
            self.rt(uid).completed = vec![false; children.len()];
        }
        self.set_status(uid, Status::Running);
        for (i, &c) in children.iter().enumerate() {
            if !self.rt(uid).completed[i] {
                match self.exec(c)? {
                    Status::Skipped => self.rt(uid).skipped += 1,
                    Status::Success => {
                        let r = self.rt(uid);
                        r.completed[i] = true;
                        r.successes += 1;
                    }
                    Status::Failure => {
                        let r = self.rt(uid);
                        r.completed[i] = true;
                        r.failures += 1;
                    }
                    _ => {}
                }
            }
            let r = self.rt(uid);
            let (s, f, k) = (r.successes as i64, r.failures as i64, r.skipped as i64);
            if s >= need_s || (success < 0 && s + k >= need_s) {
                self.clear_parallel(uid);
                self.reset_children(uid);
                return Ok(Status::Success);
            }
            if n - f < need_s || f == need_f {
                self.clear_parallel(uid);
                self.reset_children(uid);
                return Ok(Status::Failure);
            }
        }
        Ok(if self.rt(uid).skipped == children.len() {
            Status::Skipped
        } else {
            Status::Running
        })
    }

    pub(super) fn tick_parallel_all(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let n = children.len() as i64;
        let max_failures = self.port_int(uid, &["max_failures"], Some(1))?;
        let threshold = if max_failures < 0 {
            (n + max_failures + 1).max(0)
        } else {
            max_failures
        };
        if n < threshold {
            return Err(self.err(
                uid,
                format!("{n} children cannot reach max_failures {threshold}"),
            ));
        }
        if self.rt(uid).completed.len() != children.len() {
            self.rt(uid).completed = vec![false; children.len()];
        }
        self.set_status(uid, Status::Running);
        let mut skipped = 0;
        for (i, &c) in children.iter().enumerate() {
            if self.rt(uid).completed[i] {
                continue;
            }
            match self.exec(c)? {
                Status::Success => self.rt(uid).completed[i] = true,
                Status::Failure => {
                    let r = self.rt(uid);
                    r.completed[i] = true;
                    r.failures += 1;
                }
                Status::Skipped => skipped += 1,
                _ => {}
            }
        }
        if skipped == children.len() {
            return Ok(Status::Skipped);
        }
        let done = self.rt(uid).completed.iter().filter(|c| **c).count();
        if skipped + done >= children.len() {
            self.reset_children(uid);
            let failures = self.rt(uid).failures as i64;
            self.clear_parallel(uid);
            return Ok(if failures >= threshold {
                Status::Failure
            } else {
                Status::Success
            });
        }
        Ok(Status::Running)
    }

    pub(super) fn tick_try_catch(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let catch = *children.last().expect("TryCatch has children");
        let body = &children[..children.len() - 1];
        if !self.status(uid).is_active() {
            self.rt(uid).skipped = 0;
        }
        self.set_status(uid, Status::Running);
        if !self.rt(uid).started {
            while self.rt(uid).idx < body.len() {
                let c = body[self.rt(uid).idx];
                match self.exec(c)? {
                    Status::Running => return Ok(Status::Running),
                    Status::Failure => {
                        for &b in body {
                            self.halt_child(b);
                        }
                        let r = self.rt(uid);
                        r.idx = 0;
                        r.started = true;
                        break;
                    }
                    Status::Success => self.rt(uid).idx += 1,
                    Status::Skipped => {
                        let r = self.rt(uid);
                        r.idx += 1;
                        r.skipped += 1;
                    }
                    Status::Idle => unreachable!("exec rejects IDLE"),
                }
            }
            if !self.rt(uid).started {
                let all_skipped = self.rt(uid).skipped == body.len();
                self.reset_children(uid);
                self.rt(uid).idx = 0;
                return Ok(if all_skipped {
                    Status::Skipped
                } else {
                    Status::Success
                });
            }
        }
        match self.exec(catch)? {
            Status::Running => Ok(Status::Running),
            _ => {
                self.reset_children(uid);
                self.rt(uid).started = false;
                Ok(Status::Failure)
            }
        }
    }

    pub(super) fn tick_switch(&mut self, uid: Uid, cases: usize) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let mut matched = cases;
        if let Some(var) = self.port_str(uid, "variable") {
            for i in 0..cases {
                if let Some(v) = self.port_str(uid, &format!("case_{}", i + 1)) {
                    if v.trim() == var.trim() {
                        matched = i;
                        break;
                    }
                }
            }
        }
        let running = self.rt(uid).idx;
        if running != 0 && running - 1 != matched {
            self.halt_child(children[running - 1]);
        }
        let s = self.exec(children[matched])?;
        match s {
            Status::Skipped => self.rt(uid).idx = 0,
            Status::Running => self.rt(uid).idx = matched + 1,
            _ => {
                self.reset_children(uid);
                self.rt(uid).idx = 0;
            }
        }
        Ok(s)
    }
}
