//! Every counterfactual is a claim about the tree, so it is checked against
//! the tree: the session's own plan, domain or world is run again up to the
//! tick asked about, the explanation's change is made within that tick, and
//! the target must come out as the explanation says. The model only proposes.

use super::model::{AttemptLoop, Model, Val, VarId, VarKind};
use super::search::{Explanation, Next, Query};
use crate::model::Uid;
use crate::run::blackboard::EntryId;
use crate::run::domain::Intervention;
use crate::run::{Event, Executor, Forced, Leaves, RunOptions, Status};
use crate::session::rerun::{leaves_of, not_rerunnable, SourceLeaves};
use crate::session::Session;

/// At most this many of an explanation's assignments are run again (spread
/// over all of them, first and last included).
pub const ASSIGNMENTS_MAX: usize = 64;

/// What re-running said of one explanation.
#[derive(Debug, Clone, PartialEq)]
pub enum Check {
    /// Every assignment checked gave the target the value the explanation
    /// claims.
    Confirmed { checked: usize, of: usize },
    /// An assignment gave another value: the explanation is false.
    Refuted {
        change: String,
        /// What the claim is about (a variable, a node).
        subject: String,
        claimed: String,
        got: String,
    },
    /// The explanation could not be re-run; why.
    NotRerun(String),
}

impl Check {
    pub fn json(&self) -> serde_json::Value {
        match self {
            Check::Confirmed { checked, of } => serde_json::json!({
                "rerun": true, "confirmed": true, "assignments_checked": checked, "assignments": of,
            }),
            Check::Refuted {
                change,
                subject,
                claimed,
                got,
            } => serde_json::json!({
                "rerun": true, "confirmed": false, "change": change, "subject": subject, "claimed": claimed, "got": got,
            }),
            Check::NotRerun(why) => serde_json::json!({"rerun": false, "why": why}),
        }
    }
}

/// A change as the answer names it: `status(L0) = SUCCESS, X_a^0 = true`.
fn change_text(model: &Model, dos: &[(usize, Val)]) -> String {
    dos.iter()
        .map(|(v, x)| format!("{} = {}", model.var_name(*v), super::english::value_text(x)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A session that can be re-run, with its reference run checked.
pub struct Rerunner<'s> {
    session: &'s Session,
    tick: u32,
    /// How often each node was ticked in the tick, in the reference run.
    calls: Vec<u32>,
}

/// The transitions of ticks up to `tick`, as (tick, uid, prev, status).
fn transitions_upto(session: &Session, tick: u32) -> Vec<(u32, Uid, Status, Status)> {
    let end = session.index.tick_range(tick).end;
    session.index.transitions[..end]
        .iter()
        .map(|t| (t.tick, t.uid, t.prev, t.status))
        .collect()
}

/// Runs the session again up to `tick`, the calls of its last tick
/// recorded and the state of `before` set as it starts: the decisions
/// taken in that tick, in order.
fn replay(
    ex: &mut Executor<'_, SourceLeaves>,
    tick: u32,
    before: &[(usize, serde_json::Value)],
) -> Result<Vec<(Uid, String)>, String> {
    let mut decisions: Vec<(Uid, String)> = Vec::new();
    for t in 1..=tick {
        ex.record_calls = t == tick;
        if t == tick && !before.is_empty() {
            set_state(ex, before)?;
        }
        let r = ex.tick_once();
        for e in ex.take_events() {
            match e {
                Event::Transition {
                    tick: et,
                    uid,
                    decision: Some(d),
                    ..
                }
                | Event::Decision {
                    tick: et,
                    uid,
                    decision: d,
                } if et == tick => decisions.push((uid, d)),
                _ => {}
            }
        }
        if let Some(e) = ex.leaves.take_error() {
            return Err(format!("the re-run stopped: {e}"));
        }
        r.map_err(|e| format!("the re-run stopped: {e}"))?;
    }
    Ok(decisions)
}

/// Sets the domain's state variables of `before`, and the blackboard
/// entries that mirror every variable they change.
fn set_state(
    ex: &mut Executor<'_, SourceLeaves>,
    before: &[(usize, serde_json::Value)],
) -> Result<(), String> {
    let SourceLeaves::Domain(l) = &mut ex.leaves else {
        unreachable!("checked before the re-run")
    };
    let mut changed = Vec::new();
    for (var, d) in before {
        changed.extend(l.apply(*var, d.clone()).map_err(|e| e.to_string())?);
    }
    let d = std::sync::Arc::clone(&l.domain);
    for k in changed {
        let e = EntryId {
            scope: 0,
            key: d.vars[k].name.clone(),
        };
        let v = l.state[k].clone();
        ex.bb.set(&e, v);
    }
    Ok(())
}

fn new_executor(session: &Session) -> Result<Executor<'_, SourceLeaves>, String> {
    let leaves = leaves_of(session)?;
    Ok(Executor::new(
        &session.tree,
        leaves,
        RunOptions {
            tick_ms: session.header.tick_ms.max(1),
            nav2: session.header.nav2.unwrap_or_default(),
        },
    ))
}

impl<'s> Rerunner<'s> {
    /// Runs the session again without any change up to `tick`; it must give
    /// the recorded transitions, or nothing re-run from it can be trusted.
    pub fn new(session: &'s Session, tick: u32) -> Result<Rerunner<'s>, String> {
        if let Some(why) = not_rerunnable(session) {
            return Err(why);
        }
        let mut ex = new_executor(session)?;
        let mut got = Vec::new();
        for t in 1..=tick {
            let r = ex.tick_once();
            for e in ex.take_events() {
                if let Event::Transition {
                    tick,
                    uid,
                    prev,
                    status,
                    ..
                } = e
                {
                    got.push((tick, uid, prev, status));
                }
            }
            if let Some(e) = ex.leaves.take_error() {
                return Err(format!("running tick {t} again failed: {e}"));
            }
            r.map_err(|e| format!("running tick {t} again failed: {e}"))?;
        }
        let want = transitions_upto(session, tick);
        if got != want {
            let i = got.iter().zip(&want).take_while(|(a, b)| a == b).count();
            return Err(format!(
                "running the session's {} again does not give the recorded run (transition {} differs)",
                session.header.source.kind,
                i + 1
            ));
        }
        let calls = (1..=session.tree.len() as Uid)
            .map(|u| ex.calls(u))
            .collect();
        Ok(Rerunner {
            session,
            tick,
            calls,
        })
    }

    /// Checks one explanation of `query` in `model` by re-running. A state
    /// target is read where `watch` says: before the first leaf at or past
    /// that place in the tree's pre-order is called (`None`: at the end of
    /// the tick).
    pub fn check(
        &self,
        model: &Model,
        query: &Query,
        e: &Explanation,
        watch: Option<usize>,
    ) -> Check {
        let n = e.values.len();
        let picks: Vec<usize> = if n <= ASSIGNMENTS_MAX {
            (0..n).collect()
        } else {
            (0..ASSIGNMENTS_MAX)
                .map(|i| i * (n - 1) / (ASSIGNMENTS_MAX - 1))
                .collect()
        };
        for &i in &picks {
            let dos: Vec<(usize, Val)> = e.vars.iter().copied().zip(e.values[i].clone()).collect();
            let claimed = match model.evaluate_with(&dos) {
                Ok(v) => v,
                Err(err) => return Check::NotRerun(format!("the model cannot evaluate it: {err}")),
            };
            let got = match self.run_with(model, &dos, &[], query.targets[0], watch) {
                Ok((v, _)) => v,
                Err(why) => return Check::NotRerun(why),
            };
            let t = query.targets[0];
            let claimed = model.snap(t, &claimed[t]);
            let got = model.snap(t, &got);
            if claimed != got {
                return Check::Refuted {
                    change: change_text(model, &dos),
                    subject: model.var_name(t),
                    claimed: super::english::value_text(&claimed),
                    got: super::english::value_text(&got),
                };
            }
        }
        Check::Confirmed {
            checked: picks.len(),
            of: n,
        }
    }

    /// The target's value when the tick is run again with `dos`.
    pub fn outcome(
        &self,
        model: &Model,
        dos: &[(usize, Val)],
        target: usize,
        watch: Option<usize>,
    ) -> Result<Val, String> {
        self.run_with(model, dos, &[], target, watch)
            .map(|(v, _)| v)
    }

    /// The target's value when the tick is run again with a node's status
    /// forced at one of its calls, any call, not only the one the model's
    /// variable stands for.
    pub fn outcome_forced(
        &self,
        model: &Model,
        forced: Forced,
        target: usize,
        watch: Option<usize>,
    ) -> Result<Val, String> {
        self.run_with(model, &[], &[forced], target, watch)
            .map(|(v, _)| v)
    }

    /// Whether the model's variables stand for a node's call `call`.
    pub fn modelled_call(&self, model: &Model, u: Uid, call: u32) -> bool {
        self.call_of(model, u) == call
    }

    /// Runs ticks 1 to the tick again with `dos` made within the tick, and
    /// returns the target's value then.
    fn run_with(
        &self,
        model: &Model,
        dos: &[(usize, Val)],
        forced: &[Forced],
        target: usize,
        watch: Option<usize>,
    ) -> Result<(Val, Vec<u32>), String> {
        let mut ex = new_executor(self.session)?;
        ex.forced.extend_from_slice(forced);
        let (mut iv, before) = self.intervention(model, dos, &mut ex)?;
        if let VarKind::State { var, .. } = model.vars[target].kind {
            iv.watch = Some((var, watch));
        }
        match &mut ex.leaves {
            SourceLeaves::Domain(l) => l.intervene = iv,
            _ if !(iv.actions.is_empty() && iv.sets.is_empty() && before.is_empty()) => {
                return Err("state and decisions can only be changed in a domain's run".into())
            }
            _ => {}
        }
        let decisions = replay(&mut ex, self.tick, &before)?;
        let calls = (1..=model.session_len() as Uid)
            .map(|u| ex.calls(u))
            .collect();
        let val = self.value_after(model, &ex, target, &decisions)?;
        Ok((val, calls))
    }

    /// The changes `dos` as the re-run makes them: statuses forced and
    /// attempt counts set on the executor, decisions and state within the
    /// tick in the domain's intervention, and state set before the tick's
    /// first node (returned apart: it is applied as the tick starts).
    #[allow(clippy::type_complexity)]
    fn intervention(
        &self,
        model: &Model,
        dos: &[(usize, Val)],
        ex: &mut Executor<'_, SourceLeaves>,
    ) -> Result<(Intervention, Vec<(usize, serde_json::Value)>), String> {
        let tick = self.tick;
        let mut before: Vec<(usize, serde_json::Value)> = Vec::new();
        let mut iv = Intervention::default();
        iv.tick = tick;
        iv.order = vec![0; model.tree.len()];
        for (i, u) in model.tree.preorder().into_iter().enumerate() {
            iv.order[u as usize - 1] = i;
        }
        let call = |u: Uid| self.call_of(model, u);
        for (v, x) in dos {
            match (model.vars[*v].kind, x) {
                (VarKind::Status(_), Val::Status(Status::Idle)) => {
                    return Err("a node's not being ticked is a change of its execution, which btx does not re-run yet".into())
                }
                (VarKind::Status(u), _) if !model.facts.ticked[u as usize - 1] => {
                    return Err(format!(
                        "{} was not ticked in tick {tick}, so a re-run cannot give it another status",
                        model.tree.description(u)
                    ))
                }
                (VarKind::Status(u), Val::Status(s)) => ex.forced.push(Forced {
                    tick,
                    uid: model.origin(u),
                    call: call(u),
                    status: *s,
                }),
                (VarKind::Decision(u), Val::Action(a)) => {
                    iv.actions.push((model.origin(u), call(u), a.clone()))
                }
                (VarKind::Attempts(u), Val::Data(n)) => {
                    if model.folded(u) != 0 {
                        return Err(format!("{} ticked its child more often in tick {tick} than the model has attempts for", model.tree.description(u)));
                    }
                    // Set as the tick starts: the count its first call
                    // resumes with (only such a call's count is a cause).
                    ex.set_count.push((tick, model.origin(u), n.as_i64().unwrap_or(0)));
                }
                (VarKind::State { var, copy }, Val::Data(d)) => match copy_place(model, var, copy) {
                    None => before.push((var, d.clone())),
                    Some(p) => iv.sets.push((p, var, d.clone())),
                },
                (VarKind::Executed(_), _) => {
                    return Err("a change of whether a node executed is not re-run yet".into())
                }
                _ => return Err(format!("{} cannot be set in a re-run", model.var_name(*v))),
            }
        }
        Ok((iv, before))
    }

    /// The target's value in the re-run: a node of an attempt read at its
    /// own call, any other at its last in the tick.
    fn value_after(
        &self,
        model: &Model,
        ex: &Executor<'_, SourceLeaves>,
        target: usize,
        decisions: &[(Uid, String)],
    ) -> Result<Val, String> {
        let tick = self.tick;
        let call = |u: Uid| self.call_of(model, u);
        let record = |u: Uid| {
            let c = call(u);
            ex.call_log()
                .iter()
                .find(|r| r.uid == model.origin(u) && r.call == c)
        };
        Ok(match model.vars[target].kind {
            VarKind::Status(u) if self.in_attempts(model, u) => Val::Status(
                record(u)
                    .map(|r| r.returned)
                    .filter(|s| *s != Status::Skipped)
                    .unwrap_or(Status::Idle),
            ),
            VarKind::Executed(u) if self.in_attempts(model, u) => Val::Bool(record(u).is_some()),
            VarKind::Decision(u) if self.in_attempts(model, u) => Val::Action(
                record(u)
                    .and_then(|r| r.decision.clone())
                    .filter(|d| d != "null"),
            ),
            VarKind::Attempts(u) => Val::Data(serde_json::Value::from(
                ex.call_log()
                    .iter()
                    .find(|r| r.uid == model.origin(u))
                    .map_or(0, |r| r.entry.count),
            )),
            VarKind::Status(u) => {
                let (t, s) = ex.last_ticked(u);
                Val::Status(if t == tick && s != Status::Skipped {
                    s
                } else {
                    Status::Idle
                })
            }
            VarKind::Executed(u) => Val::Bool(ex.last_ticked(u).0 == tick),
            VarKind::Decision(u) => Val::Action(
                decisions
                    .iter()
                    .rev()
                    .find(|(x, _)| *x == u)
                    .map(|(_, d)| d.clone())
                    .filter(|d| d != "null"),
            ),
            VarKind::State { var, .. } => {
                let SourceLeaves::Domain(l) = &ex.leaves else {
                    return Err("a state variable needs a domain's run".into());
                };
                Val::Data(
                    l.intervene
                        .seen
                        .clone()
                        .unwrap_or_else(|| l.state[var].clone()),
                )
            }
        })
    }

    /// Which call within the tick a node of the model stands for: a copy's
    /// own (the attempt that did not happen: the one after the last), else
    /// the node's last in the reference run.
    fn call_of(&self, model: &Model, u: Uid) -> u32 {
        let last = |o: Uid| self.calls.get(o as usize - 1).copied().unwrap_or(0);
        match model.copy_of(u) {
            Some(c) if c.call > 0 => c.call,
            Some(c) => last(c.origin) + 1,
            None => last(u).max(1),
        }
    }

    /// Whether a node is in a loop the model has copies of attempts for
    /// (it is then read at its own call, not at its last).
    fn in_attempts(&self, model: &Model, u: Uid) -> bool {
        let t = &model.tree;
        model.copy_of(u).is_some()
            || t.ancestors(u)
                .any(|a| model.attempt_loop(a).is_some() && t.node(a).children.len() > 1)
    }

    /// Checks an explanation whose consequent is a retry: re-run, the
    /// node's child must be ticked again within the tick.
    pub fn check_retry(&self, model: &Model, query: &Query, e: &Explanation, node: Uid) -> Check {
        let Some(&child) = model.tree.node(node).children.first() else {
            return Check::NotRerun("the node has no child".into());
        };
        let child = model.origin(child);
        let before = self.calls[child as usize - 1];
        for values in e.values.iter().take(ASSIGNMENTS_MAX) {
            let dos: Vec<(usize, Val)> = e.vars.iter().copied().zip(values.clone()).collect();
            match self.run_with(model, &dos, &[], query.targets[0], None) {
                Ok((_, calls)) if calls[child as usize - 1] > before => {}
                Ok(_) => {
                    return Check::Refuted {
                        change: change_text(model, &dos),
                        subject: model.node_name(child),
                        claimed: "ticked again within the tick".into(),
                        got: "ticked only as in the run".into(),
                    }
                }
                Err(why) => return Check::NotRerun(why),
            }
        }
        Check::Confirmed {
            checked: e.values.len().min(ASSIGNMENTS_MAX),
            of: e.values.len(),
        }
    }
}

/// Where copy `k` of a variable begins to hold in a re-run, as a place in
/// the tree's pre-order (it holds before the first call of a leaf at or
/// past that place): after the last leaf that writes it, or after the leaf
/// whose read moved the count on to it; a derived copy not before the
/// copies it is computed from. `None`: from the tick's start.
pub fn copy_place(model: &Model, var: usize, k: u32) -> Option<usize> {
    let order = model.tree.preorder();
    let place = |u: Uid| order.iter().position(|&x| x == u).unwrap_or(0);
    let mut seen = Vec::new();
    let p = copy_start(model, &place, var, k, &mut seen);
    (p > 0).then_some(p)
}

fn copy_start(
    model: &Model,
    place: &dyn Fn(Uid) -> usize,
    var: usize,
    k: u32,
    seen: &mut Vec<(usize, u32)>,
) -> usize {
    if seen.contains(&(var, k)) {
        return 0;
    }
    seen.push((var, k));
    let mut start = match model.copy_writers(var, k).into_iter().map(place).max() {
        Some(last) => last + 1,
        None if k > 0 => model.copy_writer(var, k).map_or(0, |w| place(w) + 1),
        None => 0,
    };
    for (p, pk) in model.copy_sources(var, k) {
        start = start.max(copy_start(model, place, p, pk, seen));
    }
    start
}

/// Where a re-run reads copy `k` of a variable, as `Rerunner::check` takes it.
pub fn watch_copy(model: &Model, var: usize, k: u32) -> Option<usize> {
    Some(copy_place(model, var, k).unwrap_or(0))
}

/// At most this many evaluations are spent per explanation on the leaves
/// nothing recorded; past it, the outcome counts as unknown.
const UNKNOWN_EVALUATIONS_MAX: usize = 512;

/// For a model with no domain (a log): whether the explanation's outcome
/// depends on what leaves not ticked in the tick would have returned. Each
/// such leaf its change makes the tree tick is given every outcome in turn
/// (leaves in tree order, each given its own); if the target does not
/// always come out as claimed, the first leaf is returned.
pub fn unknown_next(model: &Model, query: &Query, reach: &Reach, e: &Explanation) -> Option<Next> {
    if model.domain.is_some() {
        return None;
    }
    let t = query.targets[0];
    let unknown = |u: Uid| model.tree.node(u).kind.is_leaf() && !model.facts.ticked[u as usize - 1];
    let matters = what_matters(model, t);
    let unknown = |u: Uid| unknown(u) && matters.contains(&model.r(u));
    let order = model.tree.preorder();
    let mut budget = UNKNOWN_EVALUATIONS_MAX;
    for values in e.values.iter().take(ASSIGNMENTS_MAX) {
        let dos: Vec<(usize, Val)> = e.vars.iter().copied().zip(values.clone()).collect();
        let Ok(base) = model.evaluate_with(&dos) else {
            return None;
        };
        let claimed = model.snap(t, &base[t]);
        // Depth-first over the outcomes of the unknown leaves ticked.
        let mut stack = vec![dos];
        let mut first: Option<Uid> = None;
        while let Some(dos) = stack.pop() {
            if budget == 0 {
                return first
                    .or_else(|| order.iter().copied().find(|&u| unknown(u)))
                    .map(|u| unknown_or_retry(model, u));
            }
            budget -= 1;
            let Ok(vals) = model.evaluate_with(&dos) else {
                continue;
            };
            let open = order.iter().copied().find(|&u| {
                unknown(u)
                    && vals[model.e(u)] == Val::Bool(true)
                    && !dos.iter().any(|(v, _)| *v == model.r(u))
            });
            match open {
                // Each outcome is one the run could have had: where the
                // target then differs, or rests on a node the model does
                // not follow, the answer hangs on the first leaf.
                None => {
                    let in_tick = model.in_tick(t, &vals).map(|x| model.snap(t, &x));
                    if model.snap(t, &vals[t]) != claimed
                        || in_tick.as_ref() != Some(&claimed)
                        || opaque_in(model, reach, &vals).is_some()
                    {
                        return first.map(|u| unknown_or_retry(model, u));
                    }
                }
                Some(u) => {
                    first.get_or_insert(u);
                    for s in &model.vars[model.r(u)].range {
                        if *s != Val::Status(Status::Idle) {
                            let mut next = dos.clone();
                            next.push((model.r(u), s.clone()));
                            stack.push(next);
                        }
                    }
                }
            }
        }
    }
    None
}

/// The variables whose values can change the target `t`: only leaves
/// whose status can reach the target matter, or reach a node the target
/// rests on whose way on the model may not follow (a RecoveryNode going
/// back to its first child reaches the target through no edge of the
/// model). The question is about the node's last call in the tick: every
/// attempt's copy of it counts (`Model::in_tick`).
fn what_matters(model: &Model, t: VarId) -> Vec<VarId> {
    let mut ends = vec![t];
    if let VarKind::Executed(n) | VarKind::Status(n) | VarKind::Decision(n) = model.vars[t].kind {
        let origin = model.origin(n);
        for c in 1..=model.tree.len() as Uid {
            if c != n && model.origin(c) == origin {
                ends.extend([model.e(c), model.r(c)]);
            }
        }
    }
    let near = model.ancestors(&ends);
    for u in 1..=model.tree.len() as Uid {
        let kids = &model.tree.node(u).children;
        if model.may_be_opaque(u)
            && (near.contains(&model.r(u)) || kids.iter().any(|&c| near.contains(&model.e(c))))
        {
            ends.push(model.r(u));
        }
    }
    model.ancestors(&ends)
}

/// What reaches the targets of a question in the model: the variables
/// they depend on, and each variable's distance to them. The same for
/// every explanation of an answer, so taken once.
pub struct Reach {
    matters: Vec<VarId>,
    dist: Vec<usize>,
}

impl Reach {
    pub fn of(model: &Model, query: &Query) -> Reach {
        Reach {
            matters: model.ancestors(&query.targets),
            dist: model.distances_to(&query.targets),
        }
    }
}

/// Under the values `vals` (of a change): the control node, nearest the
/// target, whose way on the model does not follow (`Model::opaque`) and on
/// which the target rests (its status, or whether one of its children
/// runs, reaches the target). What the model says follows from there is a
/// guess.
pub fn opaque_next(model: &Model, reach: &Reach, vals: &[Val]) -> Option<Next> {
    opaque_in(model, reach, vals).map(Next::Opaque)
}

fn opaque_in(model: &Model, reach: &Reach, vals: &[Val]) -> Option<Uid> {
    model
        .opaque(vals)
        .into_iter()
        .filter_map(|u| {
            let kids = &model.tree.node(u).children;
            std::iter::once(model.r(u))
                .chain(kids.iter().map(|&c| model.e(c)))
                .filter(|v| reach.matters.contains(v))
                .map(|v| reach.dist[v])
                .min()
                .map(|d| (d, u))
        })
        .min()
        .map(|(_, u)| u)
}

/// Under the values `vals` (of a change), a loop above the node asked
/// about goes on to a later attempt than the run's, in which a copy of that
/// node runs: the node's last call in the tick, which the question is
/// about, is then in an attempt the run does not give. Said as the retry.
pub fn later_attempt_next(model: &Model, query: &Query, vals: &[Val]) -> Option<Next> {
    let t = *query.targets.first()?;
    let (VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u)) = model.vars[t].kind
    else {
        return None;
    };
    let origin = model.origin(u);
    let asked = model.attempt_of(u)?;
    let later = (1..=model.tree.len() as Uid)
        .filter(|&c| {
            model.copy_of(c).is_some_and(|k| {
                k.origin == origin
                    && k.attempt > asked
                    && vals[model.e(c)] == Val::Bool(true)
                    && model.fact[model.e(c)] == Val::Bool(false)
            })
        })
        .min_by_key(|&c| model.copy_of(c).map(|k| k.attempt))?;
    let attempt = model.copy_of(later)?.attempt;
    let (node, l) = model
        .tree
        .ancestors(later)
        .find_map(|a| model.attempt_loop(a).map(|l| (a, l)))?;
    Some(Next::Retry {
        node,
        attempt,
        of: l.max,
        repeat: l.again == Status::Success,
    })
}

/// A leaf nothing recorded, as what the tree would do next: a leaf of an
/// attempt that did not happen is that attempt ("I would have retried").
fn unknown_or_retry(model: &Model, leaf: Uid) -> Next {
    let Some(c) = model.copy_of(leaf).filter(|c| c.call == 0) else {
        return Next::Unknown(leaf);
    };
    let found = model
        .tree
        .ancestors(leaf)
        .find_map(|a| model.attempt_loop(a).map(|l| (a, l)));
    match found {
        Some((node, l)) => Next::Retry {
            node,
            attempt: c.attempt,
            of: l.max,
            repeat: l.again == Status::Success,
        },
        None => Next::Unknown(leaf),
    }
}

/// Where the model passes a RetryUntilSuccessful's (Repeat's) child status
/// straight up although the node would tick the child again within the
/// tick: under the change `dos`, a child that did not fail (succeed) in the
/// run now does, with attempts (cycles) left. The model cannot say what the
/// next attempt gives; the run would have retried. Nearest the target first.
pub fn retry_next(model: &Model, query: &Query, reach: &Reach, vals: &[Val]) -> Option<Next> {
    let loops: Vec<(Uid, AttemptLoop)> = (1..=model.tree.len() as Uid)
        .filter_map(|u| model.attempt_loop(u).map(|l| (u, l)))
        .collect();
    if loops.is_empty() {
        return None;
    }
    // A node asked about inside the loop's child is ticked again too: its
    // last call in the tick would be in that attempt.
    let asked: Vec<Uid> = query
        .targets
        .iter()
        .filter_map(|&t| match model.vars[t].kind {
            VarKind::Executed(n) | VarKind::Status(n) | VarKind::Decision(n) => Some(n),
            _ => None,
        })
        .collect();
    let mut found: Option<(usize, Next)> = None;
    for (u, l) in loops {
        let inside = asked.iter().any(|&n| model.tree.is_ancestor(u, n));
        if !inside && !reach.matters.contains(&model.r(u)) {
            continue;
        }
        // The attempt a copy stands for that the run did not make: the
        // model starts it afresh, but a node below may keep its place
        // across the failure (a SequenceWithMemory does): what it gives is
        // not known either.
        let unmade = model
            .tree
            .node(u)
            .children
            .iter()
            .copied()
            .find(|&c| {
                model.copy_of(c).is_some_and(|k| k.call == 0)
                    && vals[model.e(c)] == Val::Bool(true)
                    && model.fact[model.e(c)] == Val::Bool(false)
            })
            .and_then(|c| model.copy_of(c))
            .map(|k| k.attempt);
        let attempt = match unmade {
            Some(a) => a,
            // Past the last copy: a child that this tick started takes the
            // wake-up path, which the model follows (the node returns
            // RUNNING); only a child already running is ticked again within
            // the tick. The change may get there through the child's status
            // or through the attempts left.
            None => {
                let Some(a) = model.loop_goes_on(u, vals) else {
                    continue;
                };
                if model.loop_goes_on(u, &model.fact).is_some() {
                    continue;
                }
                a
            }
        };
        let next = Next::Retry {
            node: u,
            attempt,
            of: l.max,
            repeat: l.again == Status::Success,
        };
        let d = if inside { 0 } else { reach.dist[model.r(u)] };
        if found.as_ref().is_none_or(|(best, _)| d < *best) {
            found = Some((d, next));
        }
    }
    found.map(|(_, n)| n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::causal::search::Explanation;
    use crate::causal::TickFacts;

    #[test]
    fn an_attempt_the_run_does_not_give_is_said_as_a_retry() {
        use crate::causal::attempts::testing::{planned, RETRY};
        let (tree, s) = planned(RETRY, "a = S\nb = 2RS", 5);
        // Tick 2: b resumed and still running; had it failed, attempt 2
        // (copies 5–7) would have started in the tick, with leaves whose
        // outcomes nothing gives.
        let m = Model::build(&tree, None, TickFacts::of(&s, 2).unwrap()).unwrap();
        assert_eq!(m.copy_of(6).map(|c| (c.origin, c.call)), Some((3, 0)));
        let q = Query {
            targets: vec![m.r(1)],
            foils: vec![vec![Val::Status(Status::Success)]],
        };
        let e = Explanation {
            vars: vec![m.r(4)],
            values: vec![vec![Val::Status(Status::Failure)]],
            outcome: vec![Val::Status(Status::Running)],
            next: None,
        };
        assert_eq!(
            unknown_next(&m, &q, &Reach::of(&m, &q), &e),
            Some(Next::Retry {
                node: 1,
                attempt: 2,
                of: 3,
                repeat: false
            })
        );
    }
}
