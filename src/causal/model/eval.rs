//! The structural functions (Love et al. Alg. 9–13): the domain's own
//! leaf functions and the executor's control flow, and the Do operator.

use super::flows::*;
use super::*;

impl Model {
    /// Values of every variable, computed from the exogenous ones.
    pub(super) fn evaluate_all(&self) -> Result<Vec<Val>, Located> {
        self.evaluate_with(&[])
    }

    /// Do(v = x for each (v, x)), every other variable recomputed from its
    /// parents, none skipped: the reference the incremental evaluator must
    /// agree with.
    pub fn evaluate_with(&self, dos: &[(VarId, Val)]) -> Result<Vec<Val>, Located> {
        let mut vals = vec![Val::Bool(false); self.vars.len()];
        let mut memo = Memo::default();
        for &v in &self.topo {
            vals[v] = match dos.iter().find(|(d, _)| *d == v) {
                Some((_, x)) => x.clone(),
                None => self.eval(v, &vals, &mut memo)?,
            };
        }
        Ok(vals)
    }

    /// The factual value of an exogenous variable.
    pub(super) fn exogenous(&self, v: VarId) -> Val {
        match self.vars[v].kind {
            VarKind::State { var, copy } => {
                let d = self.domain.as_ref().expect("state variables have a domain");
                let e = EntryId {
                    scope: 0,
                    key: d.vars[var].name.clone(),
                };
                let src = if copy == 0 {
                    &self.facts.state_start
                } else {
                    &self.facts.state_end
                };
                Val::Data(
                    src.get(&e)
                        .cloned()
                        .unwrap_or_else(|| d.vars[var].initial.clone()),
                )
            }
            VarKind::Executed(u) => Val::Bool(self.facts.ticked[u as usize - 1]),
            VarKind::Status(u) => Val::Status(self.facts.returned[u as usize - 1]),
            VarKind::Decision(u) => Val::Action(self.facts.decisions[u as usize - 1].clone()),
            VarKind::Attempts(u) => {
                let i = u as usize - 1;
                Val::Data(Value::from(self.facts.flows[i].count + self.folded[i]))
            }
        }
    }

    pub(super) fn leaf_state(&self, f: LeafFn, uid: Uid, vals: &[Val]) -> State {
        let d = self.domain.as_ref().expect("a domain");
        let mut s: State = vec![Value::Null; d.vars.len()];
        for &(x, c) in &self.reads_of[uid as usize - 1][f as usize] {
            if let Val::Data(v) = &vals[c] {
                s[x] = v.clone();
            }
        }
        s
    }

    /// The memo key of a leaf function on its current inputs, built in
    /// the memo's buffer (no allocation once it has grown).
    pub(super) fn memo_key(
        &self,
        f: LeafFn,
        uid: Uid,
        vals: &[Val],
        extra: Option<&Val>,
        k: &mut Vec<u8>,
    ) {
        k.clear();
        k.push(f as u8);
        k.extend_from_slice(&uid.to_le_bytes());
        for &(_, c) in &self.reads_of[uid as usize - 1][f as usize] {
            vals[c].key(k);
        }
        if let Some(x) = extra {
            x.key(k);
        }
    }

    pub(super) fn action_of(&self, uid: Uid, vals: &[Val]) -> Option<String> {
        match self.d_of[uid as usize - 1].map(|d| &vals[d]) {
            Some(Val::Action(a)) => a.clone(),
            _ => None,
        }
    }

    /// F_v (Algorithm 9) on the current values of v's parents.
    pub(super) fn eval(&self, v: VarId, vals: &[Val], memo: &mut Memo) -> Result<Val, Located> {
        Ok(match &self.vars[v].func {
            Func::Root => Val::Bool(true),
            Func::Exo => self.exogenous(v),
            Func::ExecChild { parent, index } => Val::Bool(self.exec_child(*parent, *index, vals)),
            Func::LeafStatus { uid, leaf } => {
                if !vals[self.e(*uid)].is_true() {
                    return Ok(Val::Status(Status::Idle));
                }
                match leaf {
                    None => Val::Status(self.facts.outcome[*uid as usize - 1]),
                    Some(l) => Val::Status(self.leaf_status(*uid, *l, vals, memo)?),
                }
            }
            Func::CompositeStatus { uid } => Val::Status(self.composite(*uid, vals)),
            Func::Decision { uid, leaf } => {
                if !vals[self.e(*uid)].is_true() {
                    return Ok(Val::Action(None));
                }
                Val::Action(self.decision(*uid, *leaf, vals, memo)?)
            }
            Func::Copy {
                var,
                prev,
                sparents,
                writers,
            } => {
                let mut value = if let Some(p) = prev {
                    vals[*p].clone()
                } else if !sparents.is_empty() {
                    Val::Data(self.derived(*var, sparents, vals, memo)?)
                } else {
                    self.exogenous(v)
                };
                for &w in writers {
                    if vals[self.e(w)].is_true() {
                        if let Some(x) = self.written(w, *var, vals, memo)? {
                            value = Val::Data(x);
                        }
                    }
                }
                value
            }
        })
    }

    /// The status a domain's leaf `l` returns, as `uid`, on its inputs.
    fn leaf_status(
        &self,
        uid: Uid,
        l: usize,
        vals: &[Val],
        memo: &mut Memo,
    ) -> Result<Status, Located> {
        let dv = self.d(uid).map(|d| &vals[d]);
        self.memo_key(LeafFn::Status, uid, vals, dv, &mut memo.buf);
        if let Some(x) = memo.status.get(&memo.buf[..]) {
            return Ok(*x);
        }
        let action = self.action_of(uid, vals);
        let d = self.domain.as_ref().expect("a domain");
        let state = self.leaf_state(LeafFn::Status, uid, vals);
        let s = d.status(l, &state, &action)?;
        memo.status.insert(memo.buf.clone(), s);
        Ok(s)
    }

    /// The action a domain's leaf decides on its inputs.
    fn decision(
        &self,
        uid: Uid,
        leaf: usize,
        vals: &[Val],
        memo: &mut Memo,
    ) -> Result<Option<String>, Located> {
        self.memo_key(LeafFn::Decide, uid, vals, None, &mut memo.buf);
        if let Some(x) = memo.decide.get(&memo.buf[..]) {
            return Ok(x.clone());
        }
        let d = self.domain.as_ref().expect("a domain");
        let a = d.decide(leaf, &self.leaf_state(LeafFn::Decide, uid, vals))?;
        memo.decide.insert(memo.buf.clone(), a.clone());
        Ok(a)
    }

    /// A derived state variable, from its state parents' copies.
    fn derived(
        &self,
        var: usize,
        sparents: &[(usize, VarId)],
        vals: &[Val],
        memo: &mut Memo,
    ) -> Result<Value, Located> {
        let key = &mut memo.buf;
        key.clear();
        key.push(3);
        key.extend_from_slice(&(var as u32).to_le_bytes());
        for &(_, c) in sparents {
            vals[c].key(key);
        }
        if let Some(x) = memo.derive.get(&memo.buf[..]) {
            return Ok(x.clone());
        }
        let d = self.domain.as_ref().expect("a domain");
        let mut s: State = vec![Value::Null; d.vars.len()];
        for &(x, c) in sparents {
            if let Val::Data(val) = &vals[c] {
                s[x] = val.clone();
            }
        }
        let x = d.derive(var, &s)?;
        memo.derive.insert(memo.buf.clone(), x.clone());
        Ok(x)
    }

    /// What the executed leaf `w` writes to state variable `var`, if it
    /// writes it.
    fn written(
        &self,
        w: Uid,
        var: usize,
        vals: &[Val],
        memo: &mut Memo,
    ) -> Result<Option<Value>, Located> {
        let l = self.leaf_of[w as usize - 1].expect("writers have domain leaves");
        let dv = self.d(w).map(|d| &vals[d]);
        self.memo_key(LeafFn::Effect, w, vals, dv, &mut memo.buf);
        let effect = match memo.effect.get(&memo.buf[..]) {
            Some(e) => Arc::clone(e),
            None => {
                let action = self.action_of(w, vals);
                let state = self.leaf_state(LeafFn::Effect, w, vals);
                let d = self.domain.as_ref().expect("a domain");
                let e = Arc::new(d.effect(l, &state, &action)?);
                memo.effect.insert(memo.buf.clone(), Arc::clone(&e));
                e
            }
        };
        Ok(effect
            .iter()
            .find(|(x, _)| *x == var)
            .map(|(_, x)| x.clone()))
    }

    pub(super) fn r_val(&self, uid: Uid, vals: &[Val]) -> Status {
        vals[self.r(uid)].status()
    }

    /// Whether child `k` of `p` is ticked, as the executor ticks it.
    pub(super) fn exec_child(&self, p: Uid, k: usize, vals: &[Val]) -> bool {
        let kids = &self.tree.node(p).children;
        let ep = vals[self.e(p)].is_true();
        let left = |j: usize| self.r_val(kids[j], vals);
        let fi = p as usize - 1;
        match self.flows[fi] {
            Flow::Sequential {
                cont,
                start,
                asynch,
            } => match k.cmp(&start) {
                std::cmp::Ordering::Less => false,
                std::cmp::Ordering::Equal => ep,
                // An asynchronous one yields after a child's first
                // completion: the next is ticked only if that one was
                // running already.
                std::cmp::Ordering::Greater => {
                    continues(left(k - 1), cont)
                        && (!asynch
                            || self.facts.start[kids[k - 1] as usize - 1] == Status::Running)
                }
            },
            Flow::Reactive { cont } => {
                if k == 0 {
                    ep
                } else {
                    continues(left(k - 1), cont)
                }
            }
            Flow::Parallel { .. } | Flow::ParallelAll { .. } => {
                let done = &self.facts.flows[fi].completed;
                if !ep || done.get(k).copied().unwrap_or(false) {
                    return false;
                }
                // Ticked unless the Parallel already decided before child k.
                !matches!(self.parallel(p, vals, k), Some(s) if s != Status::Running)
            }
            Flow::Branch { start } if start > 0 => k == start && ep,
            Flow::Branch { .. } => match k {
                0 => ep,
                1 => left(0) == Status::Success,
                _ => left(0) == Status::Failure,
            },
            Flow::Map(Mapping::Loop { again, max }) => {
                if k == 0 {
                    return ep;
                }
                let spent = self.attempts_val(p, vals) + k as i64;
                ep && left(k - 1) == again && (spent < max || max == -1) && !self.wakes(kids[k - 1])
            }
            Flow::Map(_) => ep,
            Flow::Pipeline { last } => {
                ep && (k == 0
                    || match left(k - 1) {
                        Status::Success => true,
                        Status::Running => k - 1 < last,
                        _ => false,
                    })
            }
            Flow::RoundRobin {
                start,
                failed,
                wraps,
            } => ep && self.round_robin_ticks(p, k, vals, (start, failed, wraps)),
            Flow::Recovery {
                start,
                count,
                retries,
            } => {
                ep && match (start, k) {
                    (0, 0) | (1, 1) => true,
                    (0, 1) => left(0) == Status::Failure && count < retries,
                    // Back to the first child after a recovery: not followed.
                    _ => false,
                }
            }
            Flow::Gated => ep && self.gated_ticks(p, k),
        }
    }

    /// Whether a RoundRobin ticks child `k` in its turn from `start`: the
    /// children before it in the turn failed, and it has not failed before
    /// (nor, when the turn does not wrap, is it behind the start).
    fn round_robin_ticks(
        &self,
        p: Uid,
        k: usize,
        vals: &[Val],
        (start, failed, wraps): (usize, usize, bool),
    ) -> bool {
        let kids = &self.tree.node(p).children;
        let n = kids.len();
        let pos = (k + n - start) % n;
        pos < n - failed
            && (wraps || k >= start)
            && (0..pos).all(|j| self.r_val(kids[(start + j) % n], vals) == Status::Failure)
    }

    /// Whether a gated node ticks child `k`: as in the run while the node
    /// ran; otherwise its first child, or a Switch's default (its last).
    fn gated_ticks(&self, p: Uid, k: usize) -> bool {
        let kids = &self.tree.node(p).children;
        if self.facts.ticked[p as usize - 1] {
            self.facts.ticked[kids[k] as usize - 1]
        } else {
            k == 0
                || matches!(self.tree.node(p).builtin, Some(Builtin::Switch(_)))
                    && k + 1 == kids.len()
        }
    }

    /// A Parallel's status after its children before `upto` (all if
    /// `upto` = their number): `None` while undecided.
    pub(super) fn parallel(&self, p: Uid, vals: &[Val], upto: usize) -> Option<Status> {
        let kids = &self.tree.node(p).children;
        let fi = p as usize - 1;
        let f = &self.facts.flows[fi];
        let n = kids.len() as i64;
        let (mut s, mut fl, mut sk) = (f.successes as i64, f.failures as i64, f.skipped as i64);
        let mut done: Vec<bool> = f.completed.clone();
        done.resize(kids.len(), false);
        for (i, &c) in kids.iter().enumerate().take(upto) {
            if !done[i] {
                match self.r_val(c, vals) {
                    Status::Success => {
                        s += 1;
                        done[i] = true
                    }
                    Status::Failure => {
                        fl += 1;
                        done[i] = true
                    }
                    Status::Skipped => sk += 1,
                    Status::Idle => return Some(Status::Idle),
                    Status::Running => {}
                }
            }
            if let Flow::Parallel {
                need_s,
                need_f,
                any_s,
            } = self.flows[fi]
            {
                if s >= need_s || (any_s && s + sk >= need_s) {
                    return Some(Status::Success);
                }
                if n - fl < need_s || fl == need_f {
                    return Some(Status::Failure);
                }
            }
        }
        if let Flow::ParallelAll { threshold } = self.flows[fi] {
            if upto < kids.len() {
                return None;
            }
            if sk == n {
                return Some(Status::Skipped);
            }
            let finished = done.iter().filter(|d| **d).count() as i64;
            if sk + finished >= n {
                return Some(if fl >= threshold {
                    Status::Failure
                } else {
                    Status::Success
                });
            }
            return Some(Status::Running);
        }
        if upto < kids.len() {
            None
        } else if sk == n {
            Some(Status::Skipped)
        } else {
            Some(Status::Running)
        }
    }

    /// r of a control node (Algorithm 11, and the executor's other nodes).
    pub(super) fn composite(&self, uid: Uid, vals: &[Val]) -> Status {
        if !vals[self.e(uid)].is_true() {
            return Status::Idle;
        }
        let n = self.tree.node(uid).children.len();
        match self.flows[uid as usize - 1] {
            Flow::Sequential {
                cont,
                start,
                asynch,
            } => self.sequential(uid, vals, cont, start, asynch),
            Flow::Reactive { cont } => self.reactive(uid, vals, cont),
            Flow::Parallel { .. } | Flow::ParallelAll { .. } => {
                self.parallel(uid, vals, n).unwrap_or(Status::Running)
            }
            Flow::Branch { start } => self.branch(uid, vals, start),
            Flow::Map(Mapping::Loop { again, max }) => self.looped(uid, vals, again, max),
            Flow::Map(m) => mapped(m, self.child_r(uid, vals, 0)),
            Flow::Pipeline { last } => self.pipeline(uid, vals, last),
            Flow::RoundRobin {
                start,
                failed,
                wraps,
            } => self.round_robin(uid, vals, start, failed, wraps),
            Flow::Recovery {
                start,
                count,
                retries,
            } => {
                let main = if start == 0 {
                    self.child_r(uid, vals, 0)
                } else {
                    Status::Failure
                };
                match main {
                    Status::Failure if start == 1 || count < retries => {
                        match self.child_r(uid, vals, 1) {
                            // Back to the first child (`Model::opaque`).
                            Status::Success | Status::Running => Status::Running,
                            _ => Status::Failure,
                        }
                    }
                    s => s,
                }
            }
            Flow::Gated => self.gated(uid, vals),
        }
    }

    /// r of child `k` of `uid`.
    fn child_r(&self, uid: Uid, vals: &[Val], k: usize) -> Status {
        self.r_val(self.tree.node(uid).children[k], vals)
    }

    /// A Sequence or Fallback: its children from `start` while they return
    /// `cont`; an asynchronous one yields RUNNING after a child's first
    /// completion.
    fn sequential(
        &self,
        uid: Uid,
        vals: &[Val],
        cont: Status,
        start: usize,
        asynch: bool,
    ) -> Status {
        let kids = &self.tree.node(uid).children;
        let fi = uid as usize - 1;
        let mut skipped = self.facts.flows[fi].skipped;
        if self.facts.start[fi].is_active() {
            skipped = skipped.min(start);
        } else {
            skipped = 0;
        }
        for k in start..kids.len() {
            match self.child_r(uid, vals, k) {
                Status::Skipped => skipped += 1,
                s if s == cont => {
                    let fresh = self.facts.start[kids[k] as usize - 1] != Status::Running;
                    if asynch && fresh && k + 1 < kids.len() {
                        return Status::Running;
                    }
                }
                s => return s,
            }
        }
        if skipped == kids.len() {
            Status::Skipped
        } else {
            cont
        }
    }

    /// A reactive Sequence or Fallback: every child from the first.
    fn reactive(&self, uid: Uid, vals: &[Val], cont: Status) -> Status {
        let mut all_skipped = true;
        for k in 0..self.tree.node(uid).children.len() {
            match self.child_r(uid, vals, k) {
                Status::Skipped => {}
                s if s == cont => all_skipped = false,
                s => return s,
            }
        }
        if all_skipped {
            Status::Skipped
        } else {
            cont
        }
    }

    /// An IfThenElse or WhileDoElse: the condition, then the branch it
    /// chose (or the branch already running, from `start`).
    fn branch(&self, uid: Uid, vals: &[Val], start: usize) -> Status {
        let r = |k: usize| self.child_r(uid, vals, k);
        if start > 0 {
            return r(start);
        }
        match r(0) {
            Status::Success => r(1),
            Status::Failure if self.tree.node(uid).children.len() == 3 => r(2),
            Status::Failure => Status::Failure,
            other => other,
        }
    }

    /// A Retry or Repeat unrolled into its attempts: each attempt's copy
    /// of the child in turn while it returns `again`, up to `max`.
    fn looped(&self, uid: Uid, vals: &[Val], again: Status, max: i64) -> Status {
        let spent = self.attempts_val(uid, vals);
        for (k, &kid) in self.tree.node(uid).children.iter().enumerate() {
            let s = self.r_val(kid, vals);
            if s != again {
                return s;
            }
            let more = spent + k as i64 + 1 < max || max == -1;
            if !more {
                return if again == Status::Failure {
                    Status::Failure
                } else {
                    Status::Success
                };
            }
            if self.wakes(kid) {
                return Status::Running;
            }
        }
        // The node would tick its child again within the tick, in
        // an attempt the model has no copy for (see
        // causal::verify::retry_next).
        again
    }

    /// Nav2's PipelineSequence: a child that succeeded, or one before the
    /// furthest reached (`last`) still running, lets the next go.
    fn pipeline(&self, uid: Uid, vals: &[Val], last: usize) -> Status {
        for k in 0..self.tree.node(uid).children.len() {
            match self.child_r(uid, vals, k) {
                Status::Success => {}
                Status::Running if k < last => {}
                s => return s,
            }
        }
        Status::Success
    }

    /// A RoundRobin: the children from `start` in turn (wrapping round if
    /// it does), those that failed before left out.
    fn round_robin(
        &self,
        uid: Uid,
        vals: &[Val],
        start: usize,
        failed: usize,
        wraps: bool,
    ) -> Status {
        let n = self.tree.node(uid).children.len();
        let turn = if wraps {
            n - failed
        } else {
            (n - start).min(n - failed)
        };
        for j in 0..turn {
            let k = (start + j) % n;
            match self.child_r(uid, vals, k) {
                Status::Failure => {}
                // The last child ends a RoundRobin that does not wrap.
                Status::Success if !wraps && k + 1 == n => return Status::Failure,
                s => return s,
            }
        }
        Status::Failure
    }

    /// A node whose choices the model takes from the run (a RecoveryNode
    /// that looped, a node it has no rule for): as recorded
    /// while its children are; otherwise the child that is ticked decides,
    /// else what the node returned without ticking one (`Model::opaque`
    /// says where that is a guess).
    fn gated(&self, uid: Uid, vals: &[Val]) -> Status {
        let fi = uid as usize - 1;
        if self.facts.ticked[fi] && self.children_as_recorded(uid, vals) {
            return match self.facts.returned[fi] {
                Status::Idle => Status::Failure,
                s => s,
            };
        }
        for (k, &c) in self.tree.node(uid).children.iter().enumerate() {
            let s = self.child_r(uid, vals, k);
            if s != Status::Idle && (self.facts.ticked[c as usize - 1] || !self.facts.ticked[fi]) {
                return s;
            }
        }
        match self.facts.returned[fi] {
            Status::Idle => Status::Failure,
            s => s,
        }
    }

    /// Whether every child of `uid` has, in `vals`, the status it returned
    /// in the run (IDLE: not ticked).
    pub(super) fn children_as_recorded(&self, uid: Uid, vals: &[Val]) -> bool {
        self.tree
            .node(uid)
            .children
            .iter()
            .all(|&c| self.r_val(c, vals) == self.facts.returned[c as usize - 1])
    }

    /// The nodes whose way on, under the values `vals`, the model does not
    /// follow, so that what it says follows from them is a guess: a control
    /// node it does not model (a custom one, Nav2's PersistentSequence, a
    /// RecoveryNode that went back to its first child in the tick, …) whose
    /// children now do otherwise than in the run, or that now runs and did
    /// not; and a RecoveryNode whose recovery now succeeds, after which it
    /// ticks its first child again within the tick. Decorators that pass up
    /// the status of the child they tick (Timeout, Delay, RateController,
    /// …) are followed: which child they tick is the recorded choice.
    ///
    /// And the blackboard, which the model does not hold: a node whose
    /// status a script or a blackboard entry decides (a pre-condition, a
    /// ScriptCondition, a Switch, …) is followed only as recorded, so it is
    /// opaque where it now runs and did not, or where a node that writes the
    /// blackboard (a Script, a post-condition, …) now does otherwise.
    pub fn opaque(&self, vals: &[Val]) -> Vec<Uid> {
        let differs = |u: Uid| {
            let i = u as usize - 1;
            vals[self.e(u)].is_true() != self.facts.ticked[i]
                || (self.facts.ticked[i] && self.r_val(u, vals) != self.facts.returned[i])
        };
        let written_otherwise = (1..=self.tree.len() as Uid)
            .any(|u| writes_blackboard(self.tree.node(u)) && differs(u));
        (1..=self.tree.len() as Uid)
            .filter(|&u| {
                let i = u as usize - 1;
                let n = self.tree.node(u);
                if !vals[self.e(u)].is_true() {
                    return false;
                }
                if reads_blackboard(n) && (!self.facts.ticked[i] || written_otherwise) {
                    return true;
                }
                if n.children.is_empty() {
                    return false;
                }
                match self.flows[i] {
                    Flow::Recovery { .. } => self.r_val(n.children[1], vals) == Status::Success,
                    Flow::Gated if !self.facts.ticked[i] => {
                        !(starts_its_child(n.builtin) && self.facts.start[i] == Status::Idle)
                    }
                    Flow::Gated => {
                        !passes_ticked_child(n.builtin) && !self.children_as_recorded(u, vals)
                    }
                    _ => false,
                }
            })
            .collect()
    }

    /// Whether some change could make `u` one of `opaque`'s nodes.
    pub fn may_be_opaque(&self, u: Uid) -> bool {
        let n = self.tree.node(u);
        reads_blackboard(n)
            || (!n.children.is_empty()
                && matches!(
                    self.flows[u as usize - 1],
                    Flow::Recovery { .. } | Flow::Gated
                ))
    }

    /// Whether, under `vals`, loop `u` ticks its child again within the
    /// tick after its last copy: the attempt the model has no copy for,
    /// as the attempt it would be (from 1).
    pub fn loop_goes_on(&self, u: Uid, vals: &[Val]) -> Option<i64> {
        let Flow::Map(Mapping::Loop { again, max }) = self.flows[u as usize - 1] else {
            return None;
        };
        let kids = &self.tree.node(u).children;
        let &last = kids.last()?;
        let spent = self.attempts_val(u, vals) + kids.len() as i64 - 1;
        let goes_on = vals[self.e(u)].is_true()
            && self.r_val(last, vals) == again
            && (max == -1 || spent + 1 < max)
            && !self.wakes(last);
        goes_on.then_some(spent + 2)
    }

    /// The value, under `vals`, of what a question about variable `t` asks
    /// of the tick: for a node with copies (attempts of a loop above it),
    /// the node's last call in the tick, which may be another attempt's
    /// copy than the one `t` is of (a change can end the tick's attempts
    /// sooner, or later); otherwise `vals[t]`.
    ///
    /// `None` where that is unknown: the node was ticked more often in the
    /// tick than the model has copies of it (under a RecoveryNode that went
    /// back to its first child, or in attempts folded into a count), and
    /// under `vals` none of its modelled calls happens, so its last call is
    /// one the model does not hold.
    pub fn in_tick(&self, t: VarId, vals: &[Val]) -> Option<Val> {
        let u = match self.vars[t].kind {
            VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u) => u,
            _ => return Some(vals[t].clone()),
        };
        let origin = self.origin(u);
        let attempt = |c: Uid| self.attempt_of(c).unwrap_or(0);
        let mine: Vec<Uid> = (1..=self.tree.len() as Uid)
            .filter(|&c| self.origin(c) == origin)
            .collect();
        let modelled = mine
            .iter()
            .filter(|&&c| self.facts.ticked[c as usize - 1])
            .count() as u32;
        let last = mine
            .iter()
            .copied()
            .filter(|&c| vals[self.e(c)].is_true())
            .max_by_key(|&c| attempt(c));
        if last.is_none() && self.facts.calls[origin as usize - 1] > modelled {
            return None;
        }
        Some(match (self.vars[t].kind, last) {
            (VarKind::Executed(_), l) => Val::Bool(l.is_some()),
            (VarKind::Status(_), Some(c)) => vals[self.r(c)].clone(),
            (VarKind::Status(_), None) => Val::Status(Status::Idle),
            (VarKind::Decision(_), Some(c)) => {
                self.d(c).map_or(Val::Action(None), |d| vals[d].clone())
            }
            _ => Val::Action(None),
        })
    }

    /// A loop's attempts variable.
    pub fn attempts_var(&self, u: Uid) -> Option<VarId> {
        self.a_of.get(u as usize - 1).copied().flatten()
    }

    /// The attempts a loop had spent before its first copy, in `vals`.
    pub(super) fn attempts_val(&self, u: Uid, vals: &[Val]) -> i64 {
        match self
            .a_of
            .get(u as usize - 1)
            .copied()
            .flatten()
            .map(|a| &vals[a])
        {
            Some(Val::Data(Value::Number(n))) => n.as_i64().unwrap_or(0),
            _ => 0,
        }
    }

    /// Whether a copy of a loop's child was started in the tick, so that
    /// ending in another attempt takes BehaviorTree.CPP 4's wake-up path.
    pub(super) fn wakes(&self, child: Uid) -> bool {
        self.tree.version == crate::model::Version::V4
            && self.facts.start[child as usize - 1] == Status::Idle
    }

    /// An evaluator for interventions restricted to `within` (topologically
    /// sorted, closed under ancestors).
    pub fn evaluator<'m>(&'m self, within: &'m [VarId]) -> Evaluator<'m> {
        Evaluator {
            m: self,
            within,
            vals: self.fact.clone(),
            changed: vec![false; self.vars.len()],
            fixed: vec![false; self.vars.len()],
            touched: Vec::new(),
            memo: Memo::default(),
        }
    }
}

/// Leaf functions already evaluated on the same inputs: the domain's
/// functions are deterministic, so each input is evaluated once.
#[derive(Default)]
pub struct Memo {
    status: FxHashMap<Vec<u8>, Status>,
    decide: FxHashMap<Vec<u8>, Option<String>>,
    effect: FxHashMap<Vec<u8>, Arc<Vec<(usize, Value)>>>,
    derive: FxHashMap<Vec<u8>, Value>,
    buf: Vec<u8>,
}

/// Evaluates interventions (the Do operator): only descendants of the
/// intervened variables are recomputed, and only while values change.
pub struct Evaluator<'m> {
    m: &'m Model,
    within: &'m [VarId],
    vals: Vec<Val>,
    changed: Vec<bool>,
    fixed: Vec<bool>,
    touched: Vec<VarId>,
    memo: Memo,
}

impl Evaluator<'_> {
    /// Do(v = x for each (v, x)); afterwards `value` reads the result.
    pub fn run(&mut self, dos: &[(VarId, Val)]) -> Result<(), Located> {
        for &t in &self.touched {
            self.vals[t] = self.m.fact[t].clone();
            self.changed[t] = false;
            self.fixed[t] = false;
        }
        self.touched.clear();
        let mut first = usize::MAX;
        for (v, x) in dos {
            self.vals[*v] = x.clone();
            self.fixed[*v] = true;
            self.changed[*v] = *x != self.m.fact[*v];
            self.touched.push(*v);
            first = first.min(self.m.topo_pos[*v]);
        }
        let start = self.within.partition_point(|&v| self.m.topo_pos[v] < first);
        for &v in &self.within[start..] {
            if self.fixed[v] || !self.m.deps[v].iter().any(|&p| self.changed[p]) {
                continue;
            }
            let nv = self.m.eval(v, &self.vals, &mut self.memo)?;
            if nv != self.vals[v] {
                self.vals[v] = nv;
                self.changed[v] = true;
                self.touched.push(v);
            }
        }
        Ok(())
    }

    pub fn value(&self, v: VarId) -> &Val {
        &self.vals[v]
    }
}

/// A decorator that maps its child's status (`s`) to its own.
fn mapped(m: Mapping, s: Status) -> Status {
    match (m, s) {
        (_, Status::Idle) => Status::Idle,
        (Mapping::Invert, Status::Success) => Status::Failure,
        (Mapping::Invert, Status::Failure) => Status::Success,
        (Mapping::ForceSuccess, x) if x.is_completed() => Status::Success,
        (Mapping::ForceFailure, x) if x.is_completed() => Status::Failure,
        (Mapping::KeepRunning, Status::Success | Status::Skipped) => Status::Running,
        _ => s,
    }
}
