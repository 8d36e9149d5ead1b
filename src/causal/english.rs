//! Answers in plain English, and in JSON with Love et al.'s formal reason
//! set R and counterfactual set C. Explanations that differ only in which
//! temporal copy of a variable they change read the same, so they are
//! merged; value sets of discretised variables read as ≤, ≥ or intervals.

use super::model::{Model, Val, VarId, VarKind};
use super::search::{Answer, Explanation, Next, Query};
use crate::run::Status;
use serde_json::{json, Value};

pub fn value_text(v: &Val) -> String {
    match v {
        Val::Bool(b) => b.to_string(),
        Val::Status(s) => s.as_str().to_string(),
        Val::Action(Some(a)) => a.clone(),
        Val::Action(None) => "no action".into(),
        Val::Data(Value::String(s)) => s.clone(),
        Val::Data(Value::Number(n)) if n.is_f64() => short_number(n.as_f64().unwrap_or(0.0)),
        Val::Data(d) => d.to_string(),
    }
}

/// A float at the fewest significant digits that still name it (within a
/// few units in the last place): `0.16`, not `0.16000000000000003`, which
/// is 0.1 + 0.06 in binary.
pub fn short_number(x: f64) -> String {
    if !x.is_finite() {
        return crate::run::script::number(x)
            .as_str()
            .unwrap_or("nan")
            .to_string();
    }
    for digits in 1..=17 {
        let s = format!("{:.*e}", digits - 1, x);
        let back: f64 = s.parse().unwrap_or(f64::NAN);
        if (back - x).abs() <= 4.0 * f64::EPSILON * x.abs() {
            // In decimals while short (0.00000025), else with an exponent:
            // Display writes 1e-300 as 300 digits, Debug as 1e-300.
            let plain = back.to_string();
            return if plain.len() > 12 {
                format!("{back:?}")
            } else if plain.contains('.') {
                plain
            } else {
                format!("{plain}.0")
            };
        }
    }
    format!("{x:?}")
}

pub fn value_json(v: &Val) -> Value {
    match v {
        Val::Bool(b) => Value::Bool(*b),
        Val::Status(s) => Value::from(s.as_str()),
        Val::Action(a) => a.clone().map_or(Value::Null, Value::from),
        Val::Data(d) => d.clone(),
    }
}

/// What a variable is about: a node's description or a variable's name.
fn subject(m: &Model, v: VarId) -> String {
    subject_as(m, v, false)
}

/// With `copy`, a state variable is named with its copy (`X_b^1`), to tell
/// an earlier value of the queried variable from the queried one.
fn subject_as(m: &Model, v: VarId, copy: bool) -> String {
    if copy {
        if let VarKind::State { .. } = m.vars[v].kind {
            return m.var_name(v);
        }
    }
    match m.vars[v].kind {
        VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u) | VarKind::Attempts(u) => {
            m.node_name(u)
        }
        VarKind::State { var, .. } => m.domain.as_ref().expect("a domain").vars[var].name.clone(),
    }
}

/// "of its 3 attempts before this tick" (cycles of a Repeat).
fn attempts_of(m: &Model, u: crate::model::Uid) -> String {
    let word = match m.tree.node(u).builtin {
        Some(crate::model::Builtin::Repeat) => "cycles",
        _ => "attempts",
    };
    let of = match m.attempt_loop(u) {
        Some(l) if l.max > 0 => format!("of its {} {word}", l.max),
        _ => word.to_string(),
    };
    // Attempts of the tick no copy stands for are counted in too.
    if m.folded(u) == 0 {
        format!("{of} before this tick")
    } else {
        format!("{of} before its first modelled attempt")
    }
}

fn status_past(s: Status) -> &'static str {
    match s {
        Status::Success => "succeeded",
        Status::Failure => "failed",
        Status::Running => "was still running",
        Status::Idle => "was not ticked",
        Status::Skipped => "was skipped",
    }
}

fn status_inf(s: Status) -> &'static str {
    match s {
        Status::Success => "succeed",
        Status::Failure => "fail",
        Status::Running => "keep running",
        Status::Idle => "not be ticked",
        Status::Skipped => "be skipped",
    }
}

/// "L0 failed", "L1 did not execute", "L2 chose Action2", "X_a was false".
pub fn fact(m: &Model, v: VarId, x: &Val) -> String {
    fact_as(m, v, x, false)
}

fn fact_as(m: &Model, v: VarId, x: &Val, copy: bool) -> String {
    let s = subject_as(m, v, copy);
    match (m.vars[v].kind, x) {
        (VarKind::Executed(_), Val::Bool(true)) => format!("{s} executed"),
        (VarKind::Executed(_), _) => format!("{s} did not execute"),
        (VarKind::Status(_), Val::Status(st)) => format!("{s} {}", status_past(*st)),
        (VarKind::Decision(_), Val::Action(None)) => format!("{s} chose no action"),
        (VarKind::Decision(_), a) => format!("{s} chose {}", value_text(a)),
        (VarKind::Attempts(u), x) => {
            format!("{s} had used {} {}", value_text(x), attempts_of(m, u))
        }
        (_, x) => format!("{s} was {}", value_text(x)),
    }
}

fn or_list(items: &[String]) -> String {
    match items.len() {
        0 => String::new(),
        1 => items[0].clone(),
        n => format!("{} or {}", items[..n - 1].join(", "), items[n - 1]),
    }
}

pub(crate) fn and_list(items: &[String]) -> String {
    match items.len() {
        0 => String::new(),
        1 => items[0].clone(),
        n => format!("{} and {}", items[..n - 1].join(", "), items[n - 1]),
    }
}

/// A set of values of one variable: "true", "≤ 0.7", "between 2 and 4",
/// "Action3 or Action4".
fn value_set(m: &Model, v: VarId, xs: &[Val]) -> String {
    if xs.len() == 1 {
        return value_text(&xs[0]);
    }
    let range = &m.vars[v].range;
    let numeric = xs.iter().all(|x| matches!(x, Val::Data(Value::Number(_))));
    let mut pos: Vec<usize> = xs
        .iter()
        .filter_map(|x| range.iter().position(|r| r == x))
        .collect();
    pos.sort_unstable();
    if numeric && pos.len() == xs.len() && pos.windows(2).all(|w| w[1] == w[0] + 1) {
        let (lo, hi) = (pos[0], *pos.last().expect("two or more"));
        if lo == 0 {
            return format!("≤ {}", value_text(&range[hi]));
        }
        if hi == range.len() - 1 {
            return format!("≥ {}", value_text(&range[lo]));
        }
        return format!(
            "between {} and {}",
            value_text(&range[lo]),
            value_text(&range[hi])
        );
    }
    let mut sorted: Vec<&Val> = pos.iter().map(|&p| &range[p]).collect();
    if sorted.len() != xs.len() {
        sorted = xs.iter().collect();
    }
    let items: Vec<String> = sorted.into_iter().map(value_text).collect();
    if items.len() > 2 {
        format!("one of {}", items.join(", "))
    } else {
        or_list(&items)
    }
}

/// "X_a had been true", "L0 had succeeded", "UserFrustration had been ≤ 0.7".
fn supposed(m: &Model, v: VarId, xs: &[Val], copy: bool) -> String {
    let s = subject_as(m, v, copy);
    match m.vars[v].kind {
        VarKind::Executed(_) => {
            if xs[0] == Val::Bool(true) {
                format!("{s} had executed")
            } else {
                format!("{s} had not executed")
            }
        }
        VarKind::Status(_) => {
            let forms: Vec<String> = xs
                .iter()
                .map(|x| match x {
                    Val::Status(Status::Success) => "succeeded".into(),
                    Val::Status(Status::Failure) => "failed".into(),
                    Val::Status(Status::Running) => "been running".into(),
                    Val::Status(Status::Idle) => "not been ticked".into(),
                    _ => "been skipped".into(),
                })
                .collect();
            format!("{s} had {}", or_list(&forms))
        }
        VarKind::Decision(_) => format!("{s} had chosen {}", value_set(m, v, xs)),
        VarKind::Attempts(u) => {
            format!("{s} had used {} {}", value_set(m, v, xs), attempts_of(m, u))
        }
        VarKind::State { .. } => format!("{s} had been {}", value_set(m, v, xs)),
    }
}

/// "L0 would have succeeded", "X_c would have been true".
pub fn would(m: &Model, v: VarId, x: &Val) -> String {
    let s = subject(m, v);
    match (m.vars[v].kind, x) {
        (VarKind::Executed(_), Val::Bool(true)) => format!("{s} would have executed"),
        (VarKind::Executed(_), _) => format!("{s} would not have executed"),
        (VarKind::Status(_), Val::Status(st)) => format!(
            "{s} would {}",
            match st {
                Status::Success => "have succeeded",
                Status::Failure => "have failed",
                Status::Running => "have been running",
                Status::Idle => "not have been ticked",
                Status::Skipped => "have been skipped",
            }
        ),
        (VarKind::Decision(_), Val::Action(None)) => format!("{s} would have chosen no action"),
        (VarKind::Decision(_), a) => format!("{s} would have chosen {}", value_text(a)),
        (VarKind::Attempts(u), x) => format!(
            "{s} would have used {} {}",
            value_text(x),
            attempts_of(m, u)
        ),
        (_, x) => format!("{s} would have been {}", value_text(&m.snap(v, x))),
    }
}

/// "Why did L0 fail rather than succeed?"
pub fn question(m: &Model, q: &Query) -> String {
    let v = q.targets[0];
    let x = &m.fact[v];
    let foils = &q.foils[0];
    let s = subject(m, v);
    let binary = m.vars[v].range.len() == 2 && foils.len() == 1;
    match (m.vars[v].kind, x) {
        (VarKind::Executed(_), Val::Bool(e)) => {
            if *e {
                format!("Why did {s} execute?")
            } else {
                format!("Why did {s} not execute?")
            }
        }
        (VarKind::Status(_), Val::Status(Status::Idle)) => format!("Why was {s} not ticked?"),
        (VarKind::Status(_), Val::Status(Status::Skipped)) => format!("Why was {s} skipped?"),
        (VarKind::Status(_), Val::Status(st)) => {
            let alts: Vec<String> = foils
                .iter()
                .map(|f| status_inf(f_status(f)).to_string())
                .collect();
            format!(
                "Why did {s} {} rather than {}?",
                status_inf(*st),
                or_list(&alts)
            )
        }
        (VarKind::Decision(_), a) => format!(
            "Why did {s} choose {} rather than {}?",
            value_text(a),
            value_set(m, v, foils)
        ),
        (_, x) if binary => format!("Why was {s} {}?", value_text(x)),
        (_, x) => format!(
            "Why was {s} {} rather than {}?",
            value_text(x),
            value_set(m, v, foils)
        ),
    }
}

fn f_status(v: &Val) -> Status {
    match v {
        Val::Status(s) => *s,
        _ => Status::Idle,
    }
}

/// Explanations that read alike: the same variables up to their copy, the
/// same values, the same outcome.
pub fn merge(m: &Model, a: &Answer) -> Vec<Vec<usize>> {
    let base = |v: VarId| match m.vars[v].kind {
        VarKind::State { var, .. } => (3u8, var as u64),
        VarKind::Executed(u) => (0, u64::from(u)),
        VarKind::Status(u) => (1, u64::from(u)),
        VarKind::Decision(u) => (2, u64::from(u)),
        VarKind::Attempts(u) => (4, u64::from(u)),
    };
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, e) in a.explanations.iter().enumerate() {
        // Copies merge only when they read alike in full: the same
        // factual values, the same changes, the same outcome.
        let key = |e: &Explanation| {
            (
                e.vars.iter().map(|&v| base(v)).collect::<Vec<_>>(),
                e.vars
                    .iter()
                    .map(|&v| m.fact[v].clone())
                    .collect::<Vec<_>>(),
                e.values.clone(),
                e.outcome.clone(),
                e.next,
            )
        };
        match groups
            .iter_mut()
            .find(|g| key(&a.explanations[g[0]]) == key(e))
        {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

/// The merged explanations, with the siblings that only did again what they
/// do every tick (Nav2's selectors, each alone a reason, with the same
/// outcome) folded into one: "…; likewise PlannerSelector".
pub fn folded(m: &Model, a: &Answer) -> Vec<Vec<usize>> {
    let routine = |i: usize| -> Option<(crate::model::Uid, &Explanation)> {
        let e = &a.explanations[i];
        let [v] = e.vars[..] else { return None };
        let VarKind::Status(u) = m.vars[v].kind else {
            return None;
        };
        let o = m.origin(u);
        let quiet = !m.facts.done_at.contains_key(&u) && !m.facts.done_at.contains_key(&o);
        (m.tree.node(o).kind.is_leaf() && quiet).then_some((o, e))
    };
    let mut out: Vec<Vec<usize>> = Vec::new();
    for g in merge(m, a) {
        let fold_into = routine(g[0]).and_then(|(o, e)| {
            out.iter().position(|h| {
                routine(h[0]).is_some_and(|(p, f)| {
                    m.tree.parent(p) == m.tree.parent(o)
                        && m.fact[f.vars[0]] == m.fact[e.vars[0]]
                        && f.values == e.values
                        && f.outcome == e.outcome
                        && f.next == e.next
                })
            })
        });
        match fold_into {
            Some(h) => out[h].extend(g),
            None => out.push(g),
        }
    }
    out
}

/// A folded explanation as sentences: its first member's, and the
/// siblings folded into it.
pub fn group_sentence(m: &Model, q: &Query, a: &Answer, g: &[usize]) -> String {
    let first = &a.explanations[g[0]];
    let mut text = sentence(m, q, first);
    let mut others: Vec<String> = Vec::new();
    for &i in &g[1..] {
        for &v in &a.explanations[i].vars {
            if !first.vars.contains(&v) {
                let VarKind::Status(u) = m.vars[v].kind else {
                    continue;
                };
                let name = m.node_name(u);
                if !others.contains(&name) {
                    others.push(name);
                }
            }
        }
    }
    if !others.is_empty() {
        text.push_str(&format!(
            " Likewise for {}, which also did as in every tick.",
            and_list(&others)
        ));
    }
    text
}

/// The values each variable takes over an explanation's assignments, if
/// they form a full product (so they can be read one variable at a time).
fn per_variable(e: &Explanation) -> Option<Vec<Vec<Val>>> {
    let mut sets: Vec<Vec<Val>> = vec![Vec::new(); e.vars.len()];
    for tuple in &e.values {
        for (i, x) in tuple.iter().enumerate() {
            if !sets[i].contains(x) {
                sets[i].push(x.clone());
            }
        }
    }
    let product: usize = sets.iter().map(Vec::len).product();
    (product == e.values.len()).then_some(sets)
}

/// One merged explanation as sentences.
pub fn sentence(m: &Model, q: &Query, e: &Explanation) -> String {
    let target_fact: Vec<String> = q.targets.iter().map(|&t| fact(m, t, &m.fact[t])).collect();
    let base = |v: VarId| match m.vars[v].kind {
        VarKind::State { var, .. } => Some(var),
        _ => None,
    };
    let same = |v: VarId| base(v).is_some() && q.targets.iter().any(|&t| base(t) == base(v));
    let reasons: Vec<String> = e
        .vars
        .iter()
        .map(|&v| fact_as(m, v, &m.fact[v], same(v)))
        .collect();
    let cond = match per_variable(e) {
        Some(sets) => and_list(
            &e.vars
                .iter()
                .zip(&sets)
                .map(|(&v, xs)| supposed(m, v, xs, same(v)))
                .collect::<Vec<_>>(),
        ),
        None => or_list(
            &e.values
                .iter()
                .map(|t| {
                    and_list(
                        &e.vars
                            .iter()
                            .zip(t)
                            .map(|(&v, x)| supposed(m, v, std::slice::from_ref(x), same(v)))
                            .collect::<Vec<_>>(),
                    )
                })
                .collect::<Vec<_>>(),
        ),
    };
    let outcome: Vec<String> = match e.next {
        Some(next) => vec![what_next(m, q, next)],
        None => q
            .targets
            .iter()
            .zip(&e.outcome)
            .map(|(&t, x)| would(m, t, x))
            .collect(),
    };
    format!(
        "{} because {}. If {}, {}.",
        capitalise(&and_list(&target_fact)),
        and_list(&reasons),
        cond,
        and_list(&outcome)
    )
}

/// Where the change leads past what the model holds, said as that:
/// never a final status the run cannot give, nor a consequence the model
/// only guesses.
fn what_next(m: &Model, q: &Query, next: Next) -> String {
    match next {
        // What the tree would have done next, and that its outcome is
        // unknown.
        Next::Unknown(l) => format!(
            "{} would have gone on to {}, whose outcome the run does not give",
            match m.vars[q.targets[0]].kind {
                VarKind::Status(u) | VarKind::Executed(u) | VarKind::Decision(u)
                    if m.tree.is_ancestor(u, l) =>
                {
                    m.node_name(u)
                }
                _ => "the tree".to_string(),
            },
            m.node_name(l)
        ),
        Next::Retry {
            node,
            attempt,
            of,
            repeat,
        } => retried(m, node, attempt, of, repeat),
        // Which node it rests on, and why btx cannot follow it.
        Next::Opaque(node) => {
            let id = &m.tree.node(node).id;
            let how = if m.tree.node(node).builtin.is_none() {
                format!("btx does not know how a {id} decides")
            } else if m.tree.node(node).builtin == Some(crate::model::Builtin::RecoveryNode) {
                format!("a {id} goes back to its first child within the tick, which btx's model does not follow")
            } else {
                format!("btx's model does not follow how a {id} decides")
            };
            format!(
                "what followed would have rested on how {} went on, which the run does not give ({how})",
                m.node_name(node)
            )
        }
    }
}

/// A loop that would have ticked its child again: attempt (or cycle)
/// `attempt` of `of`.
fn retried(m: &Model, node: crate::model::Uid, attempt: i64, of: i64, repeat: bool) -> String {
    let of = if of > 0 {
        format!(" of {of}")
    } else {
        String::new()
    };
    let origin = m.origin(node);
    // A loop someone named ("patrol twice") is said as itself, with
    // what it runs again: never the task it is part of.
    let child = m.tree.node(origin).children.first().copied();
    if let (true, Some(c)) = (m.tree.has_name(origin), child) {
        let (lp, what) = (m.tree.description(origin), m.tree.description(c));
        return if repeat {
            format!("{lp} would have repeated {what}: cycle {attempt}{of}")
        } else {
            format!("{lp} would have tried {what} again: attempt {attempt}{of}")
        };
    }
    let what = m
        .tree
        .ancestors(node)
        .find(|&a| m.tree.has_name(a))
        .map_or_else(|| m.node_name(node), |a| m.node_name(a));
    if repeat {
        format!("I would have repeated {what}: cycle {attempt}{of}")
    } else {
        format!("I would have retried to {what}: attempt {attempt}{of}")
    }
}

pub fn capitalised(s: &str) -> String {
    capitalise(s)
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}

/// What an explanation says instead of a consequence (JSON `next`; null
/// when it states one, in each C's K).
fn next_json(m: &Model, next: Option<Next>) -> Value {
    let node = |u: crate::model::Uid| json!({"uid": m.origin(u), "name": m.node_name(u)});
    match next {
        None => Value::Null,
        Some(Next::Unknown(l)) => json!({"kind": "unknown_outcome", "node": node(l)}),
        Some(Next::Retry {
            node: u,
            attempt,
            of,
            repeat,
        }) => json!({
            "kind": if repeat { "repeat" } else { "retry" },
            "node": node(u),
            "attempt": attempt,
            "of": of,
        }),
        Some(Next::Opaque(u)) => {
            json!({"kind": "not_followed", "node": node(u), "id": m.tree.node(u).id})
        }
    }
}

/// The formal statement of one explanation: R and C.
fn formal(m: &Model, q: &Query, e: &Explanation) -> (Vec<Value>, Vec<Value>) {
    let r = e
        .vars
        .iter()
        .map(|&v| json!({"variable": m.var_name(v), "value": value_json(&m.fact[v])}))
        .collect();
    // A consequence the answer does not claim (`next`) has no K.
    let k: Vec<Value> = q
        .targets
        .iter()
        .zip(&e.outcome)
        .filter(|_| e.next.is_none())
        .map(|(&t, x)| json!({"variable": m.var_name(t), "value": value_json(x)}))
        .collect();
    let c = e
        .values
        .iter()
        .map(|tuple| {
            json!({
                "J": e.vars.iter().zip(tuple).map(|(&v, x)| json!({"variable": m.var_name(v), "value": value_json(x)})).collect::<Vec<_>>(),
                "K": k.clone(),
            })
        })
        .collect();
    (r, c)
}

/// The formal reasons of a merged explanation, one line.
pub fn formal_line(m: &Model, a: &Answer, group: &[usize]) -> String {
    let alts: Vec<String> = group
        .iter()
        .map(|&i| {
            a.explanations[i]
                .vars
                .iter()
                .map(|&v| format!("{} = {}", m.var_name(v), value_text(&m.fact[v])))
                .collect::<Vec<_>>()
                .join(" ∧ ")
        })
        .collect();
    alts.join("  |  ")
}

pub fn to_json(m: &Model, q: &Query, a: &Answer, moment: &str) -> Value {
    let groups = folded(m, a);
    let explanations: Vec<Value> = groups
        .iter()
        .map(|g| {
            let mut rs = Vec::new();
            let mut cs = Vec::new();
            for &i in g {
                let (r, c) = formal(m, q, &a.explanations[i]);
                rs.push(Value::Array(r));
                cs.extend(c);
            }
            json!({
                "text": group_sentence(m, q, a, g),
                "R": rs,
                "C": cs,
                "next": next_json(m, a.explanations[g[0]].next),
            })
        })
        .collect();
    json!({
        "question": question(m, q),
        "moment": moment,
        "tick": m.facts.tick,
        "targets": q.targets.iter().map(|&t| json!({"variable": m.var_name(t), "value": value_json(&m.fact[t])})).collect::<Vec<_>>(),
        "foils": q.foils.iter().map(|f| f.iter().map(value_json).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "depth": a.depth,
        "max_depth": a.max_depth,
        "candidates": a.candidates,
        "evaluated": a.evaluated,
        "omitted": a.omitted,
        "unsearched": a.unsearched,
        "held": a.held,
        "stopped": a.stopped.map(|(depth, n)| json!({"depth": depth, "interventions": n.to_string()})),
        "model": {"nodes": m.vars.len(), "edges": m.edge_count()},
        "explanations": explanations,
        "unfaithful": m.unfaithful(),
    })
}

/// What the search could not follow: nodes that decide by the blackboard,
/// held as recorded, through which a change might reach the target.
fn held_note(m: &Model, a: &Answer) -> String {
    if a.held.is_empty() {
        return String::new();
    }
    let names: Vec<String> = a
        .held
        .iter()
        .take(3)
        .map(|&u| format!("{} (#{u})", m.tree.description(u)))
        .collect();
    let more = if a.held.len() > 3 {
        format!(" and {} more", a.held.len() - 3)
    } else {
        String::new()
    };
    let (verb, it) = if a.held.len() == 1 {
        ("decides", "it")
    } else {
        ("decide", "them")
    };
    let tried = if a.held_tried {
        format!("each single change of a leaf's outcome was run again through {it} and none gives the foil, but larger changes were not tried")
    } else {
        "changes through them were not tried (the run cannot be run again: it holds no plan, domain or world)".replace("them", it)
    };
    format!(
        "Not searched by the model: {}{more} {verb} by the blackboard or a script, which btx's model holds as recorded; {tried}. Whether an explanation reaches the target that way is unknown.\n",
        and_list(&names),
    )
}

/// Why nothing can explain a leaf's own outcome in a structure-only model:
/// the run gave it (a plan, a log), and only a domain says what it depends on.
fn exogenous_note(m: &Model, q: &Query) -> String {
    match m.vars[q.targets[0]].kind {
        VarKind::Status(u) | VarKind::Decision(u)
            if m.domain.is_none() && m.tree.node(u).kind.is_leaf() =>
        {
            format!(
                "Without a domain file, what {} returns is given by the run (its plan or log), not explained; give --domain FILE to ask what it depends on.\n",
                m.tree.description(u)
            )
        }
        _ => String::new(),
    }
}

/// What a search cut by its bound found: nothing, up to a depth, which is
/// not "no explanation".
pub fn stopped_text(a: &Answer) -> String {
    let Some((depth, n)) = a.stopped else {
        return String::new();
    };
    let searched = if depth > 1 {
        format!("No explanation up to depth {}; ", depth - 1)
    } else {
        String::new()
    };
    let narrower = if depth > 1 {
        format!(", or give --max-depth {}", depth - 1)
    } else {
        String::new()
    };
    format!(
        "{searched}not searched at depth {depth}: it would try {n} changes of the {} variables it depends on, past btx's bound ({} variable evaluations). Unknown whether an explanation exists there: ask about something that depends on fewer variables{narrower}.\n",
        a.candidates,
        short_count(super::search::SEARCH_WORK_MAX),
    )
}

fn short_count(n: u128) -> String {
    match n.checked_ilog10() {
        Some(e) if n.is_multiple_of(10u128.pow(e)) && e >= 4 => {
            format!("{}·10^{e}", n / 10u128.pow(e))
        }
        _ => n.to_string(),
    }
}

/// The answer as text; `full` adds each explanation's formal line.
pub fn to_text(
    m: &Model,
    q: &Query,
    a: &Answer,
    moment: &str,
    shown: Option<usize>,
    full: bool,
) -> String {
    let mut out = format!(
        "{}  (tick {}, moment {moment})\n",
        question(m, q),
        m.facts.tick
    );
    let groups = folded(m, a);
    match a.depth {
        None if a.stopped.is_some() => out.push_str(&stopped_text(a)),
        None => {
            out.push_str(&format!(
                "No explanation up to depth {}: no change of up to {} of the {} variables it depends on gives {}.\n",
                a.max_depth,
                a.max_depth,
                a.candidates,
                or_list(&q.foils[0].iter().map(value_text).collect::<Vec<_>>())
            ));
            out.push_str(&exogenous_note(m, q));
            out.push_str(&held_note(m, a));
        }
        Some(_) => {
            let limit = shown.unwrap_or(usize::MAX);
            for (n, g) in groups.iter().enumerate().take(limit) {
                out.push_str(&format!("{}. {}\n", n + 1, group_sentence(m, q, a, g)));
                if full {
                    out.push_str(&format!("   formally: {}\n", formal_line(m, a, g)));
                }
            }
            if groups.len() > limit {
                let more = groups.len() - limit;
                out.push_str(&format!(
                    "… and {more} more explanation{} (--all shows every one).\n",
                    if more == 1 { "" } else { "s" }
                ));
            }
            if a.omitted > 0 {
                out.push_str(&format!(
                    "… and {} more explanations of this size, farther from {}: not shown or checked (btx keeps the nearest {}).\n",
                    a.omitted,
                    m.var_name(q.targets[0]),
                    super::search::EXPLANATIONS_MAX
                ));
            }
            if a.unsearched > 0 {
                out.push_str(&format!(
                    "The search at this size was past btx's bound ({} variable evaluations): the {} variables nearest {} were searched, the {} farther ones not; more explanations may lie there.\n",
                    short_count(super::search::SEARCH_WORK_MAX),
                    a.candidates - a.unsearched,
                    m.var_name(q.targets[0]),
                    a.unsearched
                ));
            }
        }
    }
    for w in m.unfaithful() {
        out.push_str(&format!(
            "warning: the model does not reproduce the run: {w}\n"
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_said_at_the_precision_they_name() {
        assert_eq!(short_number(0.1 + 0.06), "0.16");
        assert_eq!(short_number(2.0), "2.0");
        assert_eq!(short_number(1e-300), "1e-300");
        assert_eq!(short_number(-2.5e300), "-2.5e300");
        assert_eq!(short_number(-2.5e-7), "-0.00000025");
        assert_eq!(short_number(123456789.5), "123456789.5");
        assert_eq!(short_number(f64::NAN), "nan");
        assert_eq!(short_number(f64::NEG_INFINITY), "-inf");
        assert_eq!(value_text(&Val::Data(Value::from("nan"))), "nan");
    }
}
