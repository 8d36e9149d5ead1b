//! A "why?" asked of a session: its target and foil at the moment asked,
//! the model of that tick, and what the run itself says where the model
//! holds no call to change.

use super::rerun::*;
use super::why::*;
use super::*;
use crate::run::domain::Domain;
use crate::session::{Moment, Session};
use crate::source::Located;
use std::sync::Arc;

/// The position from which a node's fact in the model of `tick` holds
/// within the tick (`None`: from its start): Love §5.3 explains a fact at
/// a time only if it holds then. A status holds once the node's last
/// transition into it in the tick was made; a decision or a node's having
/// run, once it was first ticked.
pub(super) fn fact_from(session: &Session, model: &Model, v: VarId, tick: u32) -> Option<u32> {
    let range = session.index.tick_range(tick);
    // A copy stands for a call that had ended by the moment (`call_at`).
    if let VarKind::Status(u) | VarKind::Executed(u) | VarKind::Decision(u) | VarKind::Attempts(u) =
        model.vars[v].kind
    {
        if model.copy_of(u).is_some() {
            return None;
        }
    }
    let in_tick = |u: crate::model::Uid| {
        session
            .index
            .changes_of(u)
            .iter()
            .copied()
            .filter(move |&p| range.contains(&(p as usize - 1)))
    };
    let status_of = |p: u32| session.index.transitions[p as usize - 1].status;
    match (model.vars[v].kind, &model.fact[v]) {
        (VarKind::Status(u), Val::Status(s)) if *s != crate::run::Status::Idle => {
            in_tick(u).rfind(|&p| status_of(p) == *s)
        }
        (VarKind::Executed(u), Val::Bool(true)) | (VarKind::Decision(u), Val::Action(Some(_))) => {
            in_tick(u).next()
        }
        _ => None,
    }
}

/// At a step, the node asked about has just completed, as the log shows,
/// but the model's variable stands for another of its calls in the tick
/// (one it does not follow): the question would be another's.
pub(super) fn another_call(
    session: &Session,
    model: &Model,
    v: VarId,
    moment: Moment,
    pos: u32,
) -> Option<String> {
    let (VarKind::Status(u), Some(_)) = (model.vars[v].kind, moment.step) else {
        return None;
    };
    let origin = model.origin(u);
    let range = session.index.tick_range(moment.tick);
    let logged = session
        .index
        .changes_of(origin)
        .iter()
        .copied()
        .filter(|&p| range.contains(&(p as usize - 1)) && p <= pos)
        .map(|p| session.index.transitions[p as usize - 1].status)
        .rfind(|s| matches!(s, crate::run::Status::Success | crate::run::Status::Failure))?;
    (model.fact[v] != Val::Status(logged)).then(|| {
        format!(
            "at {moment} {} (#{origin}) has just {}, as the run shows, but btx's model of tick {} does not hold that call (in the model, {}): it does not follow the tick's control flow around it (a node called again within the tick, as by a Nav2 RecoveryNode going back to its first child); ask at the end of tick {}, or about the nodes below it",
            model.tree.description(origin),
            if logged == crate::run::Status::Success { "succeeded" } else { "failed" },
            moment.tick,
            english::fact(model, v, &model.fact[v]),
            moment.tick
        )
    })
}

/// The last tick of a run: the tick of its last transition when the root
/// had completed by then, else the last tick the session counts.
pub fn last_tick(session: &Session) -> u32 {
    let idx = &session.index;
    let end = idx.at(idx.transitions.len() as u32);
    match (end.root_outcome(), idx.transitions.last()) {
        (Some(_), Some(t)) if end.status(crate::model::Tree::ROOT) == crate::run::Status::Idle => {
            t.tick
        }
        _ => idx.ticks(),
    }
}

/// The foils of a query that names none: every other value, except that a
/// ticked node is contrasted with the other outcomes of being ticked, and
/// a leaf that chose an action with its other actions ("not ticked" and
/// "no action" answer another question: ask executed(NODE) for that).
pub fn default_foils(model: &Model, v: VarId) -> Vec<Val> {
    let factual = model.snap(v, &model.fact[v]);
    let ticked_alt = |x: &Val| match (model.vars[v].kind, x) {
        (VarKind::Status(_), Val::Status(crate::run::Status::Idle)) => {
            factual == Val::Status(crate::run::Status::Idle)
        }
        (VarKind::Decision(_), Val::Action(None)) => factual == Val::Action(None),
        _ => true,
    };
    model.vars[v]
        .range
        .iter()
        .filter(|x| **x != factual && ticked_alt(x))
        .cloned()
        .collect()
}

/// The why-questions that can be asked about a node at a moment: its
/// status, whether it ran, its decision, and the state variables a leaf
/// reads or writes, as (target, question) pairs.
pub fn why_targets(
    session: &Session,
    domain: Option<Arc<Domain>>,
    uid: crate::model::Uid,
    at: Moment,
) -> Result<Vec<(String, String)>, Located> {
    let pos = session
        .index
        .position(at)
        .map_err(|m| Located::file(&session.path, m))?;
    let m = model_at(session, domain, at.tick)?;
    let mut vars = vec![m.r(uid), m.e(uid)];
    vars.extend(m.d(uid));
    let mut targets: Vec<String> = vec![format!("status(#{uid})"), format!("executed(#{uid})")];
    if m.d(uid).is_some() {
        targets.push(format!("decision(#{uid})"));
    }
    if let Some(d) = &m.domain {
        if let Some(l) = d.leaf_for(&m.tree, uid) {
            let mut names: Vec<usize> = d.leaves[l].inputs.clone();
            for o in &d.leaves[l].outputs {
                if !names.contains(o) {
                    names.push(*o);
                }
            }
            for x in names {
                if let Some(c) = m.copy_at(x, pos) {
                    vars.push(c);
                    targets.push(d.vars[x].name.clone());
                }
            }
        }
    }
    Ok(targets
        .into_iter()
        .zip(vars)
        .filter_map(|(t, v)| {
            let foils = default_foils(&m, v);
            (!foils.is_empty()).then(|| {
                let q = Query {
                    targets: vec![v],
                    foils: vec![foils],
                };
                (t, english::question(&m, &q))
            })
        })
        .collect())
}

/// Asks why `target` had its value at `at` (default: the end of the run)
/// and not one of `foils` (default: every other value).
pub fn why(
    session: &Session,
    domain: Option<Arc<Domain>>,
    target: &str,
    foils: &[String],
    at: Option<Moment>,
    max_depth: usize,
) -> Result<Why, Located> {
    let fail = |m: String| Located::file(&session.path, m);
    let (moment, pos) = moment_in_run(session, at).map_err(fail)?;
    let model = model_at(session, domain, moment.tick)?;
    faithful(&model, moment).map_err(fail)?;
    let t = query::parse_target(&model, target).map_err(fail)?;
    let t = match target_at_step(session, &model, t, moment, pos).map_err(fail)? {
        AtStep::Target(t) => t,
        AtStep::Told(told) => return Ok(told_why(session, model, told, moment, max_depth)),
    };
    let v = query::target_var(&model, &t, pos).map_err(fail)?;
    if let Some(e) = another_call(session, &model, v, moment, pos) {
        // The run itself holds the call: its recorded leaf outcomes, run
        // again, answer.
        let told = match model.vars[v].kind {
            VarKind::Status(u) => calls::Told::of(session, model.origin(u), pos),
            _ => None,
        };
        return match told {
            Some(told) => Ok(told_why(session, model, told, moment, max_depth)),
            None => Err(fail(e)),
        };
    }
    if let Some(when) = fact_from(session, &model, v, moment.tick).filter(|&p| p > pos) {
        let then = session.index.moment(when);
        return Err(fail(format!(
            "at {moment}, \"{}\" is not true yet: it becomes true at {then}; ask at {then} or later",
            english::fact(&model, v, &model.fact[v])
        )));
    }
    state_as_recorded(session, &model, &t, v, moment, pos).map_err(fail)?;
    let foil_vals = foil_values(&model, v, foils, moment).map_err(fail)?;
    if foil_vals.is_empty() {
        // A node whose outcome is fixed by its kind (AlwaysFailure): what
        // the run shows of its call is the answer.
        if let VarKind::Status(u) = model.vars[v].kind {
            if let Some(told) = calls::Told::of(session, model.origin(u), pos) {
                return Ok(told_why(session, model, told, moment, max_depth));
            }
        }
        return Err(fail(format!(
            "{} can take no other value: there is nothing to contrast it with",
            model.var_name(v)
        )));
    }
    let query = Query {
        targets: vec![v],
        foils: vec![foil_vals],
    };
    let answer = search(&model, &query, max_depth)?;
    // A state variable is checked where the model's copy is read, or at the
    // tick's end when that is the moment asked about.
    let watch = match (&model.vars[v].kind, moment.step, &t) {
        (_, None, query::Target::State { copy: None, .. }) => None,
        (VarKind::State { var, copy }, ..) => verify::watch_copy(&model, *var, *copy),
        _ => None,
    };
    let mut w = checked(session, model, query, answer, watch, moment.to_string());
    through_what_the_model_holds(session, &mut w, watch);
    if moment.step.is_some() {
        causes_before(session, &mut w, v, moment, pos);
    }
    from_the_run(session, &mut w, v, pos);
    Ok(w)
}

/// The moment asked about (default: the end of the run) and its position,
/// if the run has it.
pub(super) fn moment_in_run(
    session: &Session,
    at: Option<Moment>,
) -> Result<(Moment, u32), String> {
    if session.index.ticks() == 0 {
        return Err("the session has no ticks".into());
    }
    // Ticks after the root completed are not part of the run, whatever an
    // end record says: nothing is replayed past the root's completion.
    let last = last_tick(session);
    let moment = at.unwrap_or(Moment {
        tick: last,
        step: None,
    });
    if moment.tick > last {
        return Err(format!(
            "tick {} is outside the run: it ended at tick {last}, when its root completed",
            moment.tick
        ));
    }
    let pos = session.index.position(moment)?;
    Ok((moment, pos))
}

/// A model that does not reproduce its tick cannot explain it.
pub(super) fn faithful(model: &Model, moment: Moment) -> Result<(), String> {
    let Some(first) = model.unfaithful().first().cloned() else {
        return Ok(());
    };
    let hint = if model.domain.is_some() {
        "was the domain file changed since the run?"
    } else {
        "btx's model of a node differs from how it ran: a bug of btx's, please report it with the session"
    };
    Err(format!(
        "the model of tick {} does not reproduce the run, so it cannot explain it: {first} ({hint})",
        moment.tick
    ))
}

/// A target asked about at a step: the node's call at or before it.
pub(super) enum AtStep {
    Target(query::Target),
    /// A call the model of the tick does not hold: the run's own calls
    /// answer.
    Told(calls::Told),
}

/// At a step, a node's facts are those of its call at or before it.
pub(super) fn target_at_step(
    session: &Session,
    model: &Model,
    t: query::Target,
    moment: Moment,
    pos: u32,
) -> Result<AtStep, String> {
    let ours = |u: crate::model::Uid| u as usize <= model.session_len();
    Ok(AtStep::Target(match (t, moment.step) {
        (query::Target::Status(u), Some(step)) if ours(u) => match query::call_at(model, u, step) {
            Ok(c) => query::Target::Status(c),
            Err(e) => return calls::Told::of(session, u, pos).map(AtStep::Told).ok_or(e),
        },
        (query::Target::Executed(u), Some(step)) if ours(u) => {
            query::Target::Executed(query::call_at(model, u, step)?)
        }
        (query::Target::Decision(u), Some(step)) if ours(u) => {
            query::Target::Decision(query::call_at(model, u, step)?)
        }
        (t, _) => t,
    }))
}

/// A state variable asked about at the tick's end is the model's last
/// copy of it, which differs from the run's where no leaf read the newer
/// value: said, rather than explained wrong.
pub(super) fn state_as_recorded(
    session: &Session,
    model: &Model,
    t: &query::Target,
    v: VarId,
    moment: Moment,
    pos: u32,
) -> Result<(), String> {
    let (query::Target::State { var, copy: None }, Some(d)) = (t, &model.domain) else {
        return Ok(());
    };
    let e = crate::run::blackboard::EntryId {
        scope: 0,
        key: d.vars[*var].name.clone(),
    };
    let at = session.index.at(pos);
    if let (Some(rec), Val::Data(m)) = (at.entry(&e), &model.fact[v]) {
        if !model::same_value(rec, m) {
            return Err(format!(
                "at {moment} the run has {} = {}, but the model's copy {} is {} (Love's model makes a new copy of a derived variable only where a leaf reads it); ask about {} at the moment a leaf read it",
                d.vars[*var].name,
                english::value_text(&Val::Data(rec.clone())),
                model.var_name(v),
                english::value_text(&model.fact[v]),
                model.var_name(v),
            ));
        }
    }
    Ok(())
}

/// The foils as values of `v` (default: every value it did not have).
pub(super) fn foil_values(
    model: &Model,
    v: VarId,
    foils: &[String],
    moment: Moment,
) -> Result<Vec<Val>, String> {
    if foils.is_empty() {
        return Ok(default_foils(model, v));
    }
    let factual = model.snap(v, &model.fact[v]);
    let mut out = Vec::new();
    for f in foils {
        let x = query::parse_value(model, v, f)?;
        if x == factual {
            return Err(format!(
                "{} is {} at {moment}: a foil must be a value it did not have",
                model.var_name(v),
                english::value_text(&model.fact[v])
            ));
        }
        if !out.contains(&x) {
            out.push(x);
        }
    }
    Ok(out)
}

/// What the run itself says of a node's status: where the search found
/// nothing, a leaf decides its own outcome and what the run shows of its
/// call is the answer (without a domain to say what it depends on), and a
/// control node's, the run's calls searched; and a failure's root cause.
pub(super) fn from_the_run(session: &Session, w: &mut Why, v: VarId, pos: u32) {
    let VarKind::Status(u) = w.model.vars[v].kind else {
        return;
    };
    if w.answer.explanations.is_empty() && w.by_calls.is_none() {
        let leaf = w.model.tree.node(w.model.origin(u)).kind.is_leaf();
        if !leaf || w.model.domain.is_none() {
            w.by_calls = calls::Told::of(session, w.model.origin(u), pos);
        }
    }
    w.root = root_of(session, w.model.origin(u), pos);
}

/// A control node's failure by position `pos` (in its tick), followed
/// down to the leaf it comes from.
pub(super) fn root_of(
    session: &Session,
    u: crate::model::Uid,
    pos: u32,
) -> Option<chain::RootCause> {
    let idx = &session.index;
    if session.tree.node(u).kind.is_leaf() {
        return None;
    }
    let tick = idx.transitions.get((pos as usize).checked_sub(1)?)?.tick;
    let start = idx.tick_range(tick).start as u32;
    // Its state at the moment: the last change that was not a reset. Only
    // a failure it is still in is followed down (one it started again
    // after, in the tick, is not what is asked).
    let p = idx.changes_of(u).iter().copied().rev().find(|&q| {
        q <= pos && idx.transitions[q as usize - 1].status != crate::run::Status::Idle
    })?;
    (p > start && idx.transitions[p as usize - 1].status == crate::run::Status::Failure)
        .then(|| chain::RootCause::of(&session.tree, idx, u, p))
        .flatten()
}

/// A why answered from the run's own calls alone.
pub(super) fn told_why(
    session: &Session,
    model: Model,
    told: calls::Told,
    moment: Moment,
    max_depth: usize,
) -> Why {
    let v = model.r(told.uid);
    let query = Query {
        targets: vec![v],
        foils: vec![default_foils(&model, v)],
    };
    let answer = Answer {
        depth: None,
        max_depth,
        explanations: Vec::new(),
        candidates: 0,
        evaluated: 0,
        stopped: None,
        omitted: 0,
        held: Vec::new(),
        held_tried: false,
        unsearched: 0,
    };
    let mut w = checked(session, model, query, answer, None, moment.to_string());
    w.root = root_of(session, told.uid, told.pos);
    w.by_calls = Some(told);
    w
}

/// A cause comes before its effect: at a step, an explanation resting on
/// a fact the tick made true only after it (the recovery a failure set
/// going) is dropped. Where that leaves nothing about a node's completion,
/// the run's own calls answer.
pub(super) fn causes_before(session: &Session, w: &mut Why, v: VarId, moment: Moment, pos: u32) {
    let m = &w.model;
    let VarKind::Status(target) = m.vars[v].kind else {
        return;
    };
    let target = m.origin(target);
    // A status another node reached after the moment, not on the path
    // above the target (a log may write a parent's change after its
    // child's, as btcm's does).
    let after = |x: VarId| match m.vars[x].kind {
        VarKind::Status(u) => {
            let u = m.origin(u);
            !m.tree.is_ancestor(u, target)
                && u != target
                && fact_from(session, m, x, moment.tick).is_some_and(|q| q > pos)
        }
        _ => false,
    };
    let later: Vec<bool> = w
        .answer
        .explanations
        .iter()
        .map(|e| e.vars.iter().any(|&x| after(x)))
        .collect();
    if !later.contains(&true) {
        return;
    }
    let mut keep = later.iter().map(|l| !l);
    w.answer
        .explanations
        .retain(|_| keep.next().unwrap_or(true));
    if w.checks.len() == later.len() {
        let mut keep = later.iter().map(|l| !l);
        w.checks.retain(|_| keep.next().unwrap_or(true));
    }
    if w.answer.explanations.is_empty() {
        w.by_calls = calls::Told::of(session, target, pos);
    }
}
