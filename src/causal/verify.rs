//! Every counterfactual is a claim about the tree, so it is checked against
//! the tree: the session's own plan, domain or world is run again up to the
//! tick asked about, the explanation's change is made within that tick, and
//! the target must come out as the explanation says. The model only proposes.

use super::model::{Model, Val, VarKind};
use super::search::{Explanation, Query};
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
                claimed,
                got,
            } => serde_json::json!({
                "rerun": true, "confirmed": false, "change": change, "claimed": claimed, "got": got,
            }),
            Check::NotRerun(why) => serde_json::json!({"rerun": false, "why": why}),
        }
    }
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

fn new_executor(session: &Session) -> Result<Executor<'_, SourceLeaves>, String> {
    let leaves = leaves_of(session)?;
    Ok(Executor::new(
        &session.tree,
        leaves,
        RunOptions {
            tick_ms: session.header.tick_ms.max(1),
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
            let got = match self.run_with(model, &dos, query.targets[0], watch) {
                Ok(v) => v,
                Err(why) => return Check::NotRerun(why),
            };
            let t = query.targets[0];
            let claimed = model.snap(t, &claimed[t]);
            let got = model.snap(t, &got);
            if claimed != got {
                let change = dos
                    .iter()
                    .map(|(v, x)| {
                        format!("{} = {}", model.var_name(*v), super::english::value_text(x))
                    })
                    .collect::<Vec<_>>()
                    .join(", ");
                return Check::Refuted {
                    change,
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

    /// Runs ticks 1 to the tick again with `dos` made within the tick, and
    /// returns the target's value then.
    fn run_with(
        &self,
        model: &Model,
        dos: &[(usize, Val)],
        target: usize,
        watch: Option<usize>,
    ) -> Result<Val, String> {
        let tick = self.tick;
        let mut ex = new_executor(self.session)?;
        let mut before: Vec<(usize, serde_json::Value)> = Vec::new();
        let mut iv = Intervention::default();
        iv.tick = tick;
        iv.order = vec![0; model.tree.len()];
        for (i, u) in super::model::preorder(&model.tree).into_iter().enumerate() {
            iv.order[u as usize - 1] = i;
        }
        for (v, x) in dos {
            let call = |u: Uid| self.calls[u as usize - 1].max(1);
            match (model.vars[*v].kind, x) {
                (VarKind::Status(_), Val::Status(Status::Idle)) => {
                    return Err("a node's not being ticked is a change of its execution, which btx does not re-run yet".into())
                }
                (VarKind::Status(u), _) if self.calls[u as usize - 1] == 0 => {
                    return Err(format!(
                        "{} was not ticked in tick {tick}, so a re-run cannot give it another status",
                        model.tree.description(u)
                    ))
                }
                (VarKind::Status(u), Val::Status(s)) => ex.forced.push(Forced {
                    tick,
                    uid: u,
                    call: call(u),
                    status: *s,
                }),
                (VarKind::Decision(u), Val::Action(a)) => iv.actions.push((u, call(u), a.clone())),
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
        let mut decisions: Vec<(Uid, String)> = Vec::new();
        for t in 1..=tick {
            if t == tick && !before.is_empty() {
                let SourceLeaves::Domain(l) = &mut ex.leaves else {
                    unreachable!("checked above")
                };
                let mut changed = Vec::new();
                for (var, d) in &before {
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
        Ok(match model.vars[target].kind {
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
}

/// Where copy `k` of a variable holds in a re-run, as a place in the tree's
/// pre-order (before the first call of a leaf at or past it): where its
/// first reader reads it; with no reader, after its last writer; else where
/// the count of copies moved on to it. `None`: before the tick.
pub fn copy_place(model: &Model, var: usize, k: u32) -> Option<usize> {
    let order = super::model::preorder(&model.tree);
    let place = |u: Uid| order.iter().position(|&x| x == u).unwrap_or(0);
    if let Some(first) = model.copy_readers(var, k).into_iter().map(place).min() {
        return Some(first);
    }
    if let Some(last) = model.copy_writers(var, k).into_iter().map(place).max() {
        return Some(last + 1);
    }
    match k {
        0 => None,
        _ => model.copy_writer(var, k).map(|w| place(w) + 1),
    }
}

/// Where a re-run reads copy `k` of a variable, as `Rerunner::check` takes it.
pub fn watch_copy(model: &Model, var: usize, k: u32) -> Option<usize> {
    Some(copy_place(model, var, k).unwrap_or(0))
}
