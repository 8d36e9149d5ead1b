//! Changes the model holds as recorded (a node deciding by the blackboard,
//! a call the model does not follow), tried by running the tree again.

use super::why::*;
use super::*;
use crate::session::{Moment, Session};

/// The most changes tried by running the tree again through what the
/// model holds as recorded, and the most ticks replayed for them in all.
pub(super) const HELD_RERUNS_MAX: usize = 64;
pub(super) const HELD_RERUN_TICKS_MAX: usize = 200_000;

/// Love's search covers the changes the model follows; a node the model
/// holds as recorded is not followed: one that decides by the blackboard
/// (a pre-condition script, a Switch, a BlackboardCheck, …), whose input a
/// leaf's writes may set, or a control node it does not follow in this
/// tick (a Nav2 RecoveryNode going back to its first child). Where such a
/// node ran and the search found nothing, or nothing about a leaf (only
/// that a parent ran), each leaf's other outcomes are tried by running the
/// tree again: one that gives a foil is an explanation, confirmed by the
/// re-run itself. Where nothing can be run again, "No explanation" says
/// what was not searched.
pub(super) fn through_what_the_model_holds(session: &Session, w: &mut Why, watch: Option<usize>) {
    let m = &w.model;
    if w.answer.stopped.is_some() {
        return;
    }
    let held: Vec<crate::model::Uid> = (1..=m.session_len() as crate::model::Uid)
        .filter(|&u| m.facts.ticked[u as usize - 1] && m.may_be_opaque(u))
        .collect();
    let none = w.answer.explanations.is_empty();
    let about_a_leaf = |e: &Explanation| {
        e.vars.iter().all(|&v| match m.vars[v].kind {
            VarKind::Status(u) => m.tree.node(m.origin(u)).kind.is_leaf(),
            VarKind::Executed(_) | VarKind::Attempts(_) => false,
            _ => true,
        })
    };
    if held.is_empty() || w.answer.explanations.iter().any(about_a_leaf) {
        return;
    }
    let t = w.query.targets[0];
    let changes: Vec<(VarId, Val)> = (1..=m.session_len() as crate::model::Uid)
        .filter(|&u| m.tree.node(u).kind.is_leaf() && m.facts.ticked[u as usize - 1])
        .map(|u| m.r(u))
        .filter(|&v| v != t)
        .flat_map(|v| {
            m.vars[v]
                .range
                .iter()
                .filter(|x| **x != m.fact[v] && **x != Val::Status(crate::run::Status::Idle))
                .map(move |x| (v, x.clone()))
                .collect::<Vec<_>>()
        })
        .collect();
    let affordable = changes.len() <= HELD_RERUNS_MAX
        && changes.len() * m.facts.tick as usize <= HELD_RERUN_TICKS_MAX;
    let rerunner = match verify::Rerunner::new(session, m.facts.tick) {
        Ok(r) if affordable => r,
        _ => {
            if none {
                w.answer.held = held;
            }
            return;
        }
    };
    let found = rerun_changes(&rerunner, m, &w.query, changes, watch);
    if found.is_empty() {
        w.call_changes = rerun_calls(&rerunner, m, &w.query, watch);
    }
    if found.is_empty() && w.call_changes.is_empty() {
        // Every leaf's other outcomes were run: nothing at depth 1 gives a
        // foil through them either; deeper was not tried.
        if none && w.answer.max_depth > 1 {
            w.answer.held = held;
            w.answer.held_tried = true;
        }
        return;
    }
    // They are of size 1: smaller than what the model found, if larger.
    if w.answer.depth.is_some_and(|d| d > 1) {
        w.answer.explanations.clear();
        w.checks.clear();
    }
    for e in found {
        w.checks.push(verify::Check::Confirmed {
            checked: e.values.len(),
            of: e.values.len(),
        });
        w.answer.explanations.push(e);
    }
    w.answer.depth = Some(1);
    relevance::order(&w.model, &w.query, &mut w.answer, &mut w.checks);
}

/// Each plain leaf's other outcome (success for a failure, and the other
/// way round) at each of its calls in the tick that the model's variables
/// do not stand for, run again: those that give a foil.
pub(super) fn rerun_calls(
    rerunner: &verify::Rerunner,
    m: &Model,
    query: &Query,
    watch: Option<usize>,
) -> Vec<CallChange> {
    use crate::run::Status;
    let t = query.targets[0];
    let tick = m.facts.tick;
    let mut out = Vec::new();
    let calls: Vec<_> = m
        .facts
        .call_log
        .iter()
        .filter(|r| {
            r.uid as usize <= m.session_len()
                && m.tree.node(r.uid).kind.is_leaf()
                && m.tree.node(r.uid).builtin.is_none()
                && matches!(r.returned, Status::Success | Status::Failure)
                // The model's variable stands for this call only if the
                // model has the leaf ticked in the tick.
                && !(rerunner.modelled_call(m, r.uid, r.call) && m.facts.ticked[r.uid as usize - 1])
        })
        .take(HELD_RERUNS_MAX)
        .collect();
    if calls.len() * tick as usize > HELD_RERUN_TICKS_MAX {
        return out;
    }
    for r in calls {
        let to = if r.returned == Status::Success {
            Status::Failure
        } else {
            Status::Success
        };
        let forced = crate::run::Forced {
            tick,
            uid: r.uid,
            call: r.call,
            status: to,
        };
        let Ok(got) = rerunner.outcome_forced(m, forced, t, watch) else {
            continue;
        };
        let got = m.snap(t, &got);
        if !query.foils[0].contains(&got) {
            continue;
        }
        // The step at which that call's outcome was recorded: the tick's
        // transitions when the call ended.
        let step = Some(r.transitions_after);
        out.push(CallChange {
            uid: r.uid,
            call: r.call,
            at: Moment { tick, step },
            was: r.returned,
            to,
            outcome: got,
        });
    }
    out
}

/// The changes that give a foil when the tick is run again with them, as
/// explanations (one per variable and outcome).
pub(super) fn rerun_changes(
    rerunner: &verify::Rerunner,
    m: &Model,
    query: &Query,
    changes: Vec<(VarId, Val)>,
    watch: Option<usize>,
) -> Vec<Explanation> {
    let t = query.targets[0];
    let mut found: Vec<Explanation> = Vec::new();
    for (v, x) in changes {
        let Ok(got) = rerunner.outcome(m, &[(v, x.clone())], t, watch) else {
            continue;
        };
        let got = m.snap(t, &got);
        if !query.foils[0].contains(&got) {
            continue;
        }
        match found
            .iter_mut()
            .find(|e| e.vars == [v] && e.outcome == [got.clone()])
        {
            Some(e) => e.values.push(vec![x]),
            None => found.push(Explanation {
                vars: vec![v],
                values: vec![vec![x]],
                outcome: vec![got],
                next: None,
            }),
        }
    }
    found
}
