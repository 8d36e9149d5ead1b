//! "Why did X fail?" in the user's words, as `btx why` asks it: the tense
//! picks the moment (X's latest failure at or before the one asked at),
//! and the counterfactual search answers at that moment.

use super::context::{events, run_of, Context};
use super::parse::Event;
use super::say::{past, step_moment, times, upper, verb};
use super::Reply;
use crate::model::Uid;
use crate::run::Status;
use crate::session::Moment;

fn status_word(e: Event) -> Option<&'static str> {
    match e {
        Event::Fail => Some("FAILURE"),
        Event::Succeed => Some("SUCCESS"),
        Event::KeepRunning => Some("RUNNING"),
        _ => None,
    }
}

pub fn answer(
    cx: &Context,
    u: Uid,
    e: Event,
    foil: Option<Event>,
    r: &mut Reply,
) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let name = cx_name(cx, u);
    r.nodes = vec![u];
    r.short_event = Some(e);
    if e == Event::KeepRunning && at.status(u) != Status::Running && leaf_ran_on(cx, at, u, r) {
        return Ok(());
    }
    let (target, moment) = match e {
        Event::Skipped => {
            let tick = at.moment().tick;
            r.understood = format!("Why was {name} skipped in tick {tick}?");
            (format!("status(#{u})"), Moment { tick, step: None })
        }
        Event::NotRun => match not_run(cx, u, r) {
            Some(asked) => asked,
            None => return Ok(()),
        },
        Event::KeepRunning if at.status(u) == Status::Running => {
            let m = at.moment();
            r.understood = format!("Why was {name} still running at {m}?");
            if leaf_runs_on(cx, at, u, r) {
                return Ok(());
            }
            (format!("status(#{u})"), m)
        }
        _ => match event_asked(cx, at, u, e, r) {
            Some(asked) => asked,
            None => return Ok(()),
        },
    };
    let asked_foil = foil.is_some();
    // "Why did X fail?" contrasts with succeeding, and the other way round,
    // unless the question names its own contrast (`search` widens it
    // when nothing would have made it so).
    let foil = foil.or(match e {
        Event::Fail => Some(Event::Succeed),
        Event::Succeed => Some(Event::Fail),
        _ => None,
    });
    r.foil_implied = foil.is_some() && !asked_foil;
    let not: Vec<String> = foil
        .and_then(status_word)
        .map(String::from)
        .into_iter()
        .collect();
    search(cx, &target, &not, moment, r)
}

/// The target and moment of "why did X fail / succeed / run / …?" at the
/// node's last such event; none where the run itself answers (the event
/// never happened, a halt, a call again within the tick, a leaf's own
/// outcome without a domain).
fn event_asked(
    cx: &Context,
    at: &crate::session::At,
    u: Uid,
    e: Event,
    r: &mut Reply,
) -> Option<(String, Moment)> {
    let name = cx_name(cx, u);
    if e == Event::KeepRunning {
        r.answer = not_running_now(cx, at, u).unwrap_or_default();
    }
    let ev = events(at, u, e);
    let Some(&p) = ev.last() else {
        r.understood = format!("Why did {name} {}?", verb(e));
        r.answer = never(cx, u, e);
        return None;
    };
    let m = step_moment(at.index, p);
    r.understood = format!("Why did {name} {} at {m}?", verb(e));
    if e == Event::Halted {
        r.answer = halted_by(cx, u, p);
        return None;
    }
    // Called again within the tick (Nav2's RecoveryNode): the tick's
    // causal model holds its first call only; the run says why.
    if e == Event::Run {
        if let Some(again) = called_again(cx, at, u, p) {
            r.answer = again;
            return None;
        }
        // Started again in a later tick: what the run shows of why, the
        // root cause, before the tick's causal model.
        if let Some(again) = restarted(cx, at, u, p) {
            r.answer = again;
        }
    }
    // A control node's failure: the leaf it comes from, first.
    if e == Event::Fail && !cx.tree.node(u).kind.is_leaf() {
        if let Some(chain) = root_cause(cx, at, u, p) {
            r.answer = chain;
        }
    }
    // A leaf decides its own outcome: what the run shows of it comes
    // first; the search only where a domain says what it depends on.
    if cx.tree.node(u).kind.is_leaf() && matches!(e, Event::Fail | Event::Succeed) {
        r.answer = leaf_outcome(cx, at, u, p);
        let domain = cx.session.is_some_and(|s| s.header.source.kind == "domain");
        if !domain {
            return None;
        }
    }
    if ev.len() > 1 {
        r.history = Some(format!(
            "{} {} {} by then: at {}.",
            upper(&name),
            past(e),
            times(ev.len()),
            super::say::moments(at.index, &ev)
        ));
    }
    let t = if e == Event::Run {
        "executed"
    } else {
        "status"
    };
    Some((format!("{t}(#{u})"), m))
}

/// A leaf still running runs on by its own work: what the run shows of
/// its spell comes first, and is the whole answer where no domain says
/// what the leaf depends on (the search could only say it found nothing).
fn leaf_runs_on(cx: &Context, at: &crate::session::At, u: Uid, r: &mut Reply) -> bool {
    let (Some(s), true) = (cx.session, cx.tree.node(u).kind.is_leaf()) else {
        return false;
    };
    let Some(since) = at.index.call_start(u, at.pos + 1) else {
        return false;
    };
    r.answer = crate::causal::calls::leaf_running(s, u, since, at.pos);
    s.header.source.kind != "domain"
}

/// "Why did X keep running?" of a leaf that has stopped: its last spell,
/// told from the run as `leaf_runs_on` tells one still going, where no
/// domain says what the leaf depends on.
fn leaf_ran_on(cx: &Context, at: &crate::session::At, u: Uid, r: &mut Reply) -> bool {
    let (Some(s), true) = (cx.session, cx.tree.node(u).kind.is_leaf()) else {
        return false;
    };
    if s.header.source.kind == "domain" {
        return false;
    }
    let Some(&since) = events(at, u, Event::KeepRunning).last() else {
        return false;
    };
    let Some(&end) = at
        .index
        .changes_of(u)
        .iter()
        .find(|&&p| p > since && p <= at.pos)
    else {
        return false;
    };
    r.understood = format!(
        "Why did {} keep running until {}?",
        cx_name(cx, u),
        step_moment(at.index, end)
    );
    r.answer = crate::causal::calls::leaf_ran(s, u, since, end);
    true
}

/// "Why is X still running?" asked when it is not: how it last ended, by
/// the moment asked, before why it ran on in its last spell.
fn not_running_now(cx: &Context, at: &crate::session::At, u: Uid) -> Option<String> {
    let last = at
        .index
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&p| p <= at.pos)
        .map(|p| (p, at.index.transitions[p as usize - 1].status))
        .rfind(|(_, s)| matches!(s, Status::Success | Status::Failure))?;
    Some(format!(
        "{} is not running at {}: it last ended with {} at {}.",
        upper(&cx_name(cx, u)),
        at.moment(),
        last.1,
        step_moment(at.index, last.0)
    ))
}

/// The failure of control node `u` at position `p` followed down to the
/// leaf it comes from (`causal::chain`).
fn root_cause(cx: &Context, at: &crate::session::At, u: Uid, p: u32) -> Option<String> {
    crate::causal::chain::RootCause::of(cx.tree, at.index, u, p).map(|c| c.text(cx.tree))
}

/// What the run shows of a leaf's completion at position `p`, by the
/// moment of the conversation (`causal::calls::leaf_facts`).
fn leaf_outcome(cx: &Context, at: &crate::session::At, u: Uid, p: u32) -> String {
    match cx.session {
        Some(s) => crate::causal::calls::leaf_facts(s, u, p, at.pos),
        None => format!(
            "{} returned {} itself at {}.",
            upper(&cx.tree.told(u)),
            at.index.transitions[p as usize - 1].status.as_str(),
            step_moment(at.index, p)
        ),
    }
}

/// A start at `p` of a node that already ended earlier in the same tick:
/// its parent ticked it again, and a RecoveryNode does so once its
/// recovery succeeded. Told from the run's transitions; `None` for a
/// first call.
pub(super) fn called_again(
    cx: &Context,
    at: &crate::session::At,
    u: Uid,
    p: u32,
) -> Option<String> {
    let index = at.index;
    let tick = index.transitions[p as usize - 1].tick;
    let start = index.tick_range(tick).start as u32;
    let ended = |q: u32| {
        let t = index.transitions[q as usize - 1];
        (t.tick == tick && q > start && matches!(t.status, Status::Success | Status::Failure))
            .then_some((q, t.status))
    };
    let (q, how) = index
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q < p)
        .filter_map(ended)
        .next_back()?;
    let name = upper(&cx_name(cx, u));
    let outcome = crate::causal::calls::past(how);
    let mut text = format!(
        "{name} started again at {}, after it {outcome} at {} in the same tick.",
        step_moment(index, p),
        step_moment(index, q)
    );
    let Some(parent) = cx.tree.parent(u) else {
        return Some(text);
    };
    let node = cx.tree.node(parent);
    let recovery = (node.id == "RecoveryNode" && node.children.first() == Some(&u))
        .then(|| node.children.get(1).copied())
        .flatten();
    let recovered = recovery.and_then(|c| {
        index
            .changes_of(c)
            .iter()
            .copied()
            .find(|&x| {
                x > q && x < p && index.transitions[x as usize - 1].status == Status::Success
            })
            .map(|x| (c, x))
    });
    text.push(' ');
    text.push_str(&match recovered {
        Some((c, x)) => format!(
            "{} ran its recovery, {}, which succeeded at {}, and so tried {} again, as a RecoveryNode does.",
            upper(&cx_name(cx, parent)),
            cx_name(cx, c),
            step_moment(index, x),
            cx_name(cx, u)
        ),
        None => format!("{} ticked it again.", upper(&cx_name(cx, parent))),
    });
    Some(text)
}

/// A start at `p` of a node that had ended in an earlier tick ("why is
/// look at chuck roughly being run again?"): the node above it that ended
/// and was entered again, why that one ended (its root cause, for a
/// failure), and what entered it again: the loop above it, or the tree
/// ticked anew from its root. Told from the run's transitions; `None` for
/// a first start.
pub(super) fn restarted(cx: &Context, at: &crate::session::At, u: Uid, p: u32) -> Option<String> {
    let index = at.index;
    let tick = index.transitions[p as usize - 1].tick;
    let (q, how) =
        last_end(index, u, p).filter(|&(q, _)| index.transitions[q as usize - 1].tick < tick)?;
    let mut text = format!(
        "{} started again at {}, after it {} at {}.",
        upper(&cx_name(cx, u)),
        step_moment(index, p),
        crate::causal::calls::past(how),
        step_moment(index, q)
    );
    // The highest of the nodes above it that ended in between, each the
    // parent of the last: the one above that stayed is what looped.
    let ended = cx
        .tree
        .ancestors(u)
        .map_while(|a| {
            last_end(index, a, p)
                .filter(|&(x, _)| x > q)
                .map(|(x, _)| (a, x))
        })
        .last();
    let Some((a, x)) = ended else {
        let parent = cx.tree.parent(u)?;
        text.push_str(&format!(
            " {} ticked it again.",
            upper(&cx_name(cx, parent))
        ));
        return Some(text);
    };
    text.push(' ');
    text.push_str(why_it_ended(cx, index, a, x).trim_end_matches('.'));
    text.push('.');
    text.push_str(&entered_again(cx, index, a, x, p));
    Some(text)
}

/// The last end (SUCCESS or FAILURE) of `v` before position `p`: its
/// changes are in order, so those before `p` are found by halving (the
/// root's list holds every run of a long log).
fn last_end(index: &crate::session::Index, v: Uid, p: u32) -> Option<(u32, Status)> {
    let changes = index.changes_of(v);
    changes[..changes.partition_point(|&x| x < p)]
        .iter()
        .map(|&x| (x, index.transitions[x as usize - 1].status))
        .rfind(|(_, st)| matches!(st, Status::Success | Status::Failure))
}

/// Why `a` ended at `x`: for a failure, followed down to the leaf it
/// comes from.
fn why_it_ended(cx: &Context, index: &crate::session::Index, a: Uid, x: u32) -> String {
    let st = index.transitions[x as usize - 1].status;
    (st == Status::Failure)
        .then(|| crate::causal::chain::RootCause::of(cx.tree, index, a, x))
        .flatten()
        .map(|c| c.text(cx.tree))
        .unwrap_or_else(|| {
            format!(
                "{} {} at {}.",
                upper(&cx_name(cx, a)),
                crate::causal::calls::past(st),
                step_moment(index, x)
            )
        })
}

/// " Its parent then started it again at y.", or the root ticked anew.
fn entered_again(cx: &Context, index: &crate::session::Index, a: Uid, x: u32, p: u32) -> String {
    let changes = index.changes_of(a);
    let entered = changes[changes.partition_point(|&y| y <= x)..]
        .iter()
        .copied()
        .take_while(|&y| y <= p)
        .find(|&y| index.transitions[y as usize - 1].status == Status::Running);
    match (cx.tree.parent(a), entered) {
        (Some(l), Some(y)) => format!(
            " {} then started {} again at {}.",
            upper(&cx_name(cx, l)),
            cx_name(cx, a),
            step_moment(index, y)
        ),
        (None, Some(y)) => format!(
            " The tree was ticked again from its root at {}.",
            step_moment(index, y)
        ),
        _ => String::new(),
    }
}

/// "Why did X not run?" in the tick of the moment: the target and moment
/// to search, or `None` when X did run then (and the answer says so).
fn not_run(cx: &Context, u: Uid, r: &mut Reply) -> Option<(String, Moment)> {
    let at = cx.at.as_ref()?;
    let name = cx_name(cx, u);
    let tick = at.moment().tick;
    r.understood = format!("Why did {name} not run in tick {tick}?");
    let range = at.index.tick_range(tick);
    if let Some(&p) = at
        .index
        .changes_of(u)
        .iter()
        .find(|&&p| (p as usize) > range.start && (p as usize) <= range.end)
    {
        r.answer = format!(
            "{} did run in tick {tick}: it changed status at {}.",
            upper(&name),
            step_moment(at.index, p)
        );
        return None;
    }
    // A node that never ran at all: why, across the run, first; the
    // search then says what held it back in the tick.
    if let Some(never) = cx
        .session
        .and_then(|s| crate::causal::calls::never_ran(s, u, at.pos))
    {
        r.answer = never;
    }
    Some((format!("executed(#{u})"), Moment { tick, step: None }))
}

/// "Why did you do X instead of Y?": why Y did not run, in the tick where
/// X last ran.
pub fn instead(cx: &Context, done: Uid, other: Uid, r: &mut Reply) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let (d, o) = (cx_name(cx, done), cx_name(cx, other));
    let Some(&p) = events(at, done, Event::Run).last() else {
        r.understood = format!("Why did I do {d} and not {o}?");
        r.answer = format!("{} had not run {}.", upper(&d), by(cx));
        return Ok(());
    };
    let tick = step_moment(at.index, p).tick;
    r.understood = format!("Why did I do {d} and not {o} in tick {tick}?");
    r.short_event = Some(Event::NotRun);
    r.about = Some(other);
    r.nodes = vec![done, other];
    // Nav2 calls nodes again within a tick: Y may have been tried first in
    // this tick, and its end is why X ran. Searching the tick's last pass
    // would answer why Y was not tried again, which is not what was asked.
    let start = at.index.tick_range(tick).start as u32;
    let ended_before = at.index.changes_of(other).iter().copied().rfind(|&q| {
        q > start
            && q < p
            && matches!(
                at.index.transitions[q as usize - 1].status,
                Status::Failure | Status::Success
            )
    });
    if let Some(q) = ended_before {
        let ended = at.index.transitions[q as usize - 1].status;
        let mut why = super::Reply::new(&r.question, r.short);
        answer(cx, done, Event::Run, None, &mut why)?;
        r.answer = format!(
            "{} was tried first in tick {tick}: it {} at {}, and {d} started after it, at {}.\n{}",
            upper(&o),
            past(if ended == Status::Failure {
                Event::Fail
            } else {
                Event::Succeed
            }),
            step_moment(at.index, q),
            step_moment(at.index, p),
            why.answer
        );
        r.answered = why.answered;
        return Ok(());
    }
    search(
        cx,
        &format!("executed(#{other})"),
        &[],
        Moment { tick, step: None },
        r,
    )
}

fn by(cx: &Context) -> String {
    match &cx.at {
        Some(a) => crate::causal::calls::by_moment(a.index, a.pos),
        None => String::new(),
    }
}

fn cx_name(cx: &Context, u: Uid) -> String {
    cx.tree.told(u)
}

/// X never did what was asked by then: say so, and how it last ended.
fn never(cx: &Context, u: Uid, e: Event) -> String {
    let at = cx.at.as_ref().expect("a run");
    let name = upper(&cx_name(cx, u));
    let by = by(cx);
    match at.last_completion(u) {
        _ if events(at, u, Event::Run).is_empty() => format!("{name} had not run {by}."),
        Some((p, s)) => format!(
            "{name} did not {} {by}: it last ended with {} at {}.",
            verb(e),
            s.as_str(),
            step_moment(at.index, p)
        ),
        None => format!("{name} did not {} {by}: it has not finished.", verb(e)),
    }
}

/// A halt comes from above: the last change of an ancestor before it in
/// the same tick.
fn halted_by(cx: &Context, u: Uid, p: u32) -> String {
    let at = cx.at.as_ref().expect("a run");
    let idx = at.index;
    let tick = idx.transitions[p as usize - 1].tick;
    let start = idx.tick_range(tick).start as u32;
    let cause = (start + 1..p).rev().find(|&q| {
        let t = idx.transitions[q as usize - 1];
        cx.tree.is_ancestor(t.uid, u) && t.status != Status::Running
    });
    let name = upper(&cx_name(cx, u));
    match cause {
        Some(q) => {
            let t = idx.transitions[q as usize - 1];
            format!(
                "{name} was halted at {} after {} became {} at {}: a node stops the children it no longer ticks.",
                step_moment(idx, p),
                cx_name(cx, t.uid),
                t.status.as_str(),
                step_moment(idx, q)
            )
        }
        None => match sibling_outcome(cx, u, start + 1..p) {
            // A reactive node's earlier child changed, so it stopped the
            // child it no longer ticks (a guard that failed).
            Some((q, a)) => {
                let t = idx.transitions[q as usize - 1];
                format!(
                    "{name} was halted at {} because {} became {} at {}, so the {} {} stopped ticking it.",
                    step_moment(idx, p),
                    cx_name(cx, t.uid),
                    t.status.as_str(),
                    step_moment(idx, q),
                    cx.tree.node(a).id,
                    cx_name(cx, a),
                )
            }
            None => format!(
                "{name} was halted at {}: a node above it stopped ticking it, and the record of that tick does not show which.",
                step_moment(idx, p)
            ),
        },
    }
}

/// The latest outcome before a halt, within `span` of the halt's tick, of
/// a node beside the halted one (under one of its ancestors, not above or
/// below it), and the ancestor both are under.
fn sibling_outcome(cx: &Context, u: Uid, span: std::ops::Range<u32>) -> Option<(u32, Uid)> {
    let idx = cx.at.as_ref()?.index;
    let tree = cx.tree;
    span.rev().find_map(|q| {
        let t = idx.transitions[q as usize - 1];
        if t.status == Status::Idle
            || t.uid == u
            || tree.is_ancestor(t.uid, u)
            || tree.is_ancestor(u, t.uid)
        {
            return None;
        }
        let common = tree.ancestors(u).find(|&a| tree.is_ancestor(a, t.uid))?;
        Some((q, common))
    })
}

/// Nothing would have made it the contrast the words imply: what would
/// have changed it at all becomes the answer (`w`), and the line that says
/// so is returned; nothing where nothing would have.
fn widened(
    s: &crate::session::Session,
    d: Option<std::sync::Arc<crate::run::domain::Domain>>,
    target: &str,
    at: Moment,
    w: &mut crate::causal::Why,
    r: &mut Reply,
) -> Result<String, String> {
    let any = crate::causal::why(s, d, target, &[], Some(at), 2)
        .map(|w| crate::causal::Why { root: None, ..w })
        .map_err(|e| e.to_string())?;
    if any.answer.explanations.is_empty() {
        return Ok(String::new());
    }
    let said = format!(
        "No change of up to 2 things would have made it {}; what would have changed it:\n",
        r.not.join(" or ")
    );
    r.not.clear();
    *w = any;
    Ok(said)
}

/// Asks the counterfactual search, and keeps its explanations (its own
/// restatement, the first line, is replaced by ours).
fn search(
    cx: &Context,
    target: &str,
    not: &[String],
    at: Moment,
    r: &mut Reply,
) -> Result<(), String> {
    // What the run shows, set before (a leaf's outcome), stays first.
    let mut facts = std::mem::take(&mut r.answer);
    let s = cx.session.ok_or_else(|| {
        "a why needs a recorded run; a live robot's statuses cannot be re-run".to_string()
    })?;
    let d = crate::causal::session_domain(s, None).map_err(|e| e.to_string())?;
    r.target = Some(target.to_string());
    r.not = not.to_vec();
    r.moment = Some(at.to_string());
    let mut w = match crate::causal::why(s, d.clone(), target, not, Some(at), 2) {
        // The conversation says the root cause itself, first.
        Ok(w) => crate::causal::Why { root: None, ..w },
        // The causal model of the tick lacks this call (a node called
        // again within the tick): what the run shows is the answer.
        Err(_) if !facts.is_empty() => {
            r.answer = facts;
            return Ok(());
        }
        Err(e) => return Err(e.to_string()),
    };
    let mut widened = if w.answer.explanations.is_empty() && !not.is_empty() && r.foil_implied {
        widened(s, d, target, at, &mut w, r)?
    } else {
        String::new()
    };
    // Answered from the run's own calls, the chain is told there, checked
    // by running the tree again: the record's chain would say it twice.
    if w.by_calls.is_some() {
        facts.clear();
    }
    let text = super::detail::why_text(&mut w, s, cx.detail);
    let (asked, body) = text.split_once('\n').unwrap_or((text.as_str(), ""));
    // The search explains the node's last call in the tick; where that is
    // not the call asked about (a node ticked again in the same tick), its
    // answer is to another question, and is not passed off as this one's.
    if !says(asked, r.short_event) {
        if !facts.is_empty() {
            r.answer = facts;
            return Ok(());
        }
        r.answer = format!(
            "btx cannot answer this as asked: its causal model of tick {} holds the node otherwise (it would answer another question: \"{}\"), as where a node is called again within a tick under a Nav2 RecoveryNode. The transitions are in btx log.",
            at.tick,
            asked.split("  (").next().unwrap_or(asked).trim()
        );
        r.answered = false;
        return Ok(());
    }
    if cx.detail == super::Detail::Brief {
        widened.clear();
        // Brief: the cause, which the run's facts give first where it has them.
        if !facts.is_empty() {
            r.answer = facts;
            return Ok(());
        }
    }
    r.answer = format!("{widened}{}{}", past_the_moment(cx, at), body.trim_end());
    if r.answer.trim().is_empty() && facts.is_empty() {
        // Never an empty line where an answer goes.
        r.answer = format!(
            "The causal model of tick {} gives no explanation of it: no change of up to 2 things it holds would have changed it.",
            at.tick
        );
    }
    if !facts.is_empty() {
        r.answer = format!("{facts}\n{}", r.answer);
    }
    Ok(())
}

/// Where the conversation's moment is a step before the end of the tick
/// the search covers whole, the line that says so: what the tick's causal
/// model holds after that step ("GoalUpdated succeeded" at 6:10, asked at
/// 6:5) had not happened by the moment asked.
fn past_the_moment(cx: &Context, at: Moment) -> String {
    let Some(now) = cx.at.as_ref() else {
        return String::new();
    };
    let asked = now.moment();
    let range = now.index.tick_range(at.tick);
    if at.step.is_some() || asked.tick != at.tick || now.pos as usize >= range.end {
        return String::new();
    }
    format!(
        "Over the whole of tick {t}, to {t}:{last}, past the moment asked ({asked}):\n",
        t = at.tick,
        last = range.end - range.start
    )
}

/// Whether the search's own question asks about `e`.
fn says(asked: &str, e: Option<Event>) -> bool {
    let words: &[&str] = match e {
        Some(Event::Fail) => &["fail"],
        Some(Event::Succeed) => &["succeed"],
        Some(Event::KeepRunning) => &["running"],
        Some(Event::NotRun) => &["not execute", "not ticked"],
        Some(Event::Skipped) => &["skipped"],
        Some(Event::Run) => &["execute"],
        _ => return true,
    };
    let q = asked.to_lowercase();
    let negated = q.contains("not execute") || q.contains("not ticked");
    words.iter().any(|w| q.contains(w)) && (e == Some(Event::NotRun) || !negated)
}
