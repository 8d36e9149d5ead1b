//! What the run itself tells of a call where the model holds none to
//! change: how the leaf ended, what it was designed to do, what handled
//! it, whether it was tried again.

use super::*;

/// A why about a node's completion, answered from the run's calls.
#[derive(Debug, Clone)]
pub struct Told {
    pub uid: Uid,
    /// The record's position of the completion, its status and moment.
    pub pos: u32,
    pub status: Status,
    pub moment: Moment,
    /// The causes found, or why the run could not be replayed.
    pub found: Result<CallCauses, String>,
    /// The record's last tick (a re-run that did not end the call by then).
    pub last_tick: u32,
    /// For a leaf: what the run shows of its call.
    pub leaf_facts: Option<String>,
    /// For a control node: what the run shows of how it ended (the child
    /// it ended after, and what its kind does with that).
    pub design: Option<String>,
}

pub fn past(s: Status) -> &'static str {
    match s {
        Status::Success => "succeeded",
        Status::Failure => "failed",
        Status::Running => "kept running",
        _ => "was not ticked",
    }
}

impl Told {
    /// Node `u`'s last completion at or before position `pos`, in its tick,
    /// explained by the run's calls; `None` when it completed in no call
    /// by then in that tick.
    pub fn of(session: &Session, u: Uid, pos: u32) -> Option<Told> {
        let idx = &session.index;
        let tick = idx.transitions.get(pos.checked_sub(1)? as usize)?.tick;
        let start = idx.tick_range(tick).start as u32;
        let p = idx.changes_of(u).iter().copied().rev().find(|&q| {
            q <= pos
                && q > start
                && matches!(
                    idx.transitions[q as usize - 1].status,
                    Status::Success | Status::Failure
                )
        })?;
        let t = idx.transitions[p as usize - 1];
        let leaf = session.tree.node(u).kind.is_leaf();
        // A leaf decides its own outcome: what the run shows of its call
        // is the answer, and nothing is searched.
        let found = if leaf {
            Ok(CallCauses::default())
        } else {
            Replay::new(session, p).map(|r| {
                let below = r.causes(u, p, Within::Below);
                if below.causes.is_empty() {
                    r.causes(u, p, Within::Anywhere)
                } else {
                    below
                }
            })
        };
        Some(Told {
            uid: u,
            pos: p,
            status: t.status,
            moment: step_moment(idx, p),
            found,
            leaf_facts: leaf.then(|| leaf_facts(session, u, p, idx.transitions.len() as u32)),
            design: (!leaf).then(|| design(session, u, p)),
            last_tick: idx.ticks(),
        })
    }

    /// Each cause as a sentence.
    pub fn sentences(&self, tree: &Tree) -> Vec<String> {
        let Ok(found) = &self.found else {
            return Vec::new();
        };
        // One leaf's several calls are one cause: it failed again.
        let mut groups: Vec<Vec<&CallCause>> = Vec::new();
        for c in &found.causes {
            match groups
                .iter_mut()
                .find(|g| g[0].leaf == c.leaf && g[0].was == c.was)
            {
                Some(g) => g.push(c),
                None => groups.push(vec![c]),
            }
        }
        groups.iter().map(|g| self.sentence(tree, g)).collect()
    }

    /// The sentence of one leaf's calls that caused this call's end: the
    /// latest first, then what each earlier one would have changed.
    fn sentence(&self, tree: &Tree, g: &[&CallCause]) -> String {
        let me = tree.told(self.uid);
        let c = g[0];
        let other = if c.was == Status::Success {
            Status::Failure
        } else {
            Status::Success
        };
        let would = |c: &CallCause| match c.instead {
            Some((s, m)) => format!("{me} would have {} at {m}", past(s)),
            None => format!(
                "{me} would not have ended that call by tick {}, where the run ends",
                self.last_tick
            ),
        };
        let assumed = assumed_said(tree, g);
        // "Look at chuck failed at 10:1 because detect chuck failed".
        let because = format!(
            "{} {} at {} because {} {}",
            capitalised(&me),
            past(self.status),
            self.moment,
            tree.told(c.leaf),
            past(c.was),
        );
        if g.len() == 1 {
            return format!(
                "{because} at {}. Had it {} then, {}{assumed}.",
                c.at,
                past(other),
                would(c),
            );
        }
        let earlier: Vec<String> = g[1..].iter().map(|c| c.at.to_string()).collect();
        let alternatives: Vec<String> = g[1..]
            .iter()
            .map(|c| format!("had it {} at {}, {}", past(other), c.at, would(c)))
            .collect();
        format!(
            "{because} again at {}, after it {} at {}{}. Had it {} at {}, {}; {}{assumed}.",
            c.at,
            past(c.was),
            earlier.join(", "),
            self.retries_used(tree, c.leaf),
            past(other),
            c.at,
            would(c),
            alternatives.join("; "),
        )
    }

    /// ", and the retries of the node that repeats `leaf` were used on it
    /// (number_of_retries=1)", where a RecoveryNode or a retry between the
    /// node asked about and the leaf gives it.
    fn retries_used(&self, tree: &Tree, leaf: Uid) -> String {
        use crate::model::{Builtin, PortValue};
        let Some(a) = std::iter::once(leaf)
            .chain(tree.ancestors(leaf))
            .find(|&a| {
                matches!(
                    tree.node(a).builtin,
                    Some(Builtin::RecoveryNode | Builtin::RetryUntilSuccessful)
                ) && (a == self.uid || tree.is_ancestor(self.uid, a))
            })
        else {
            return String::new();
        };
        let port = tree.node(a).ports.iter().find_map(|p| match &p.value {
            PortValue::Literal(v)
                if matches!(p.name.as_str(), "number_of_retries" | "num_attempts") =>
            {
                Some((p.name.clone(), v.clone()))
            }
            _ => None,
        });
        let whose = if a == self.uid {
            "its".to_string()
        } else {
            format!("{}'s", tree.told(a))
        };
        match port {
            Some((p, v)) if p == "number_of_retries" => format!(
                " and {whose} {} ({p}={v}) {} used",
                if v == "1" {
                    "one retry".to_string()
                } else {
                    format!("{v} retries")
                },
                if v == "1" { "was" } else { "were" }
            ),
            Some((p, v)) => format!(" and {whose} attempts ({p}={v}) were all made"),
            None => String::new(),
        }
    }

    /// The answer: the causes found, latest first (at most `shown`), or
    /// for a leaf what the run shows of its call; `full` adds how they
    /// were found.
    pub fn text(&self, tree: &Tree, shown: Option<usize>, full: bool) -> String {
        let mut out = format!("{}\n", self.question(tree));
        let sentences = self.sentences(tree);
        let n = shown.unwrap_or(usize::MAX).min(sentences.len());
        for (i, s) in sentences[..n].iter().enumerate() {
            out.push_str(&format!("{}. {s}\n", i + 1));
        }
        if n < sentences.len() {
            out.push_str(&format!(
                "{} more (--all shows them).\n",
                sentences.len() - n
            ));
        }
        if sentences.is_empty() {
            if let Some(f) = self.leaf_facts.as_ref().or(self.design.as_ref()) {
                out.push_str(f);
                out.push('\n');
            } else {
                out.push_str(&format!(
                    "No other outcome of one leaf's call before {} changes it.\n",
                    self.moment
                ));
            }
        }
        match &self.found {
            Err(e) if full || sentences.is_empty() => out.push_str(&format!(
                "The run could not be replayed to look further: {e}.\n"
            )),
            Ok(f) if full && f.candidates > 0 => out.push_str(&format!(
                "Found by running the tree again on the run's own leaf outcomes, each of {} of the {} leaf calls before {} changed in turn.\n",
                f.tried, f.candidates, self.moment
            )),
            _ => {}
        }
        out
    }

    pub fn question(&self, tree: &Tree) -> String {
        format!(
            "Why did {} {} at {}?",
            tree.told(self.uid),
            match self.status {
                Status::Success => "succeed",
                _ => "fail",
            },
            self.moment
        )
    }

    pub fn json(&self, tree: &Tree) -> serde_json::Value {
        let found = self.found.as_ref().ok();
        serde_json::json!({
            "question": self.question(tree),
            "uid": self.uid,
            "status": self.status.as_str(),
            "at": self.moment.to_string(),
            "sentences": self.sentences(tree),
            "causes": found.map(|f| f.causes.iter().map(|c| serde_json::json!({
                "leaf": c.leaf,
                "at": c.at.to_string(),
                "was": c.was.as_str(),
                "instead": c.instead.map(|(s, m)| serde_json::json!({"status": s.as_str(), "at": m.to_string()})),
                "assumed": c.assumed,
                "rerun": true,
            })).collect::<Vec<_>>()),
            "tried": found.map(|f| f.tried),
            "candidates": found.map(|f| f.candidates),
            "not_replayed": self.found.as_ref().err(),
            "leaf_facts": self.leaf_facts,
            "design": self.design,
        })
    }
}

/// A record's position as TICK:STEP.
pub fn step_moment(idx: &crate::session::Index, pos: u32) -> Moment {
    let t = idx.transitions[pos as usize - 1].tick;
    Moment {
        tick: t,
        step: Some(pos - idx.tick_range(t).start as u32),
    }
}

/// How a control node's call ended, as the run shows it: the child it
/// ended after, and what a node of its kind does with that ("a ForceFailure
/// fails whatever its child returns").
pub(super) fn design(session: &Session, u: Uid, p: u32) -> String {
    use crate::model::Builtin;
    let idx = &session.index;
    let tree = &session.tree;
    let t = idx.transitions[p as usize - 1];
    let me = capitalised(&tree.told(u));
    let start = idx.call_start(u, p).unwrap_or(0);
    let child = (start + 1..p).rev().find_map(|q| {
        let x = idx.transitions[q as usize - 1];
        (tree.parent(x.uid) == Some(u) && x.status.is_completed()).then_some((q, x))
    });
    let kind = match tree.node(u).builtin {
        Some(Builtin::ForceFailure) => " A ForceFailure fails whatever its child returns.",
        Some(Builtin::ForceSuccess) => " A ForceSuccess succeeds whatever its child returns.",
        Some(Builtin::Inverter) => " An Inverter turns its child's outcome around.",
        Some(Builtin::Precondition) => {
            " A Precondition whose `if` is false returns its `else` without ticking its child."
        }
        _ => "",
    };
    let then = past(t.status);
    match child {
        Some((q, x)) => format!(
            "{me} {then} at {} after {} {} at {}.{kind}",
            step_moment(idx, p),
            tree.told(x.uid),
            past(x.status),
            step_moment(idx, q)
        ),
        None => format!(
            "{me} {then} at {} without a child of it ending in that call.{kind}",
            step_moment(idx, p)
        ),
    }
}

/// What a leaf's call read and wrote, where the run holds the blackboard:
/// its inputs as they were when it started, its outputs when it ended
/// (Nav2's `error_code_id`). Empty where the run holds none of them.
pub(super) fn ports_said(session: &Session, u: Uid, start: u32, end: u32) -> String {
    use crate::model::Direction;
    let tree = &session.tree;
    let n = tree.node(u);
    let bb = crate::run::blackboard::Blackboard::new(tree);
    let (before, after) = (
        session.index.at(start.saturating_sub(1)),
        session.index.at(end),
    );
    let mut read = Vec::new();
    let mut wrote = Vec::new();
    for port in &n.ports {
        let Some(e) = bb.port_entry(tree, n.scope, &port.value) else {
            continue;
        };
        match port.assumed_direction() {
            Direction::Out => {
                if let Some(v) = after.entry(&e) {
                    wrote.push(format!("{} = {v}", e.key));
                }
            }
            _ => {
                if let Some(v) = before.entry(&e) {
                    read.push(format!("{} = {v}", e.key));
                }
            }
        }
    }
    let mut said = Vec::new();
    if !read.is_empty() {
        said.push(format!("read {}", read.join(", ")));
    }
    if !wrote.is_empty() {
        said.push(format!("wrote {}", wrote.join(", ")));
    }
    if said.is_empty() {
        String::new()
    } else {
        format!("It {}.", said.join(" and "))
    }
}

/// "once", "twice", "N times".
pub fn times(n: usize) -> String {
    match n {
        1 => "once".into(),
        2 => "twice".into(),
        n => format!("{n} times"),
    }
}

/// What the run shows of a leaf's completion at position `p`: that it
/// returned the status itself, when it started and how long it ran, how
/// often it had ended so before, what handled a failure and whether that
/// worked (by the record's end), and where its outcome came from.
pub fn leaf_facts(session: &Session, u: Uid, p: u32, upto: u32) -> String {
    let t = session.index.transitions[p as usize - 1];
    let start = session.index.call_start(u, p);
    let mut out = vec![
        returned_itself(session, u, p, start),
        ended_so_before(session, u, p),
    ];
    if t.status == Status::Failure {
        out.push(handled(session, u, p, upto));
    }
    out.push(ports_said(session, u, start.unwrap_or(p), p));
    out.push(not_in_the_run(
        session,
        past(t.status),
        "the outcome, not its reason",
    ));
    out.retain(|l| !l.is_empty());
    out.join(" ")
}

/// What the run shows of a leaf still running at position `upto`, in the
/// spell that began at `since`: it runs on by its own work, which the tree
/// does not decide ("why is walk still running?" of an action).
pub fn leaf_running(session: &Session, u: Uid, since: u32, upto: u32) -> String {
    let idx = &session.index;
    let name = capitalised(&session.tree.told(u));
    let began = idx.transitions[since as usize - 1].tick;
    let now = idx.moment(upto);
    let ticks = now.tick - began + 1;
    let mut out = vec![format!(
        "{name} has been running since {} ({ticks} tick{}) and had not finished by {now}: it is {}, so it runs on by its own work, not by anything the tree decides.",
        step_moment(idx, since),
        if ticks == 1 { "" } else { "s" },
        a_kind(session, u)
    )];
    out.push(not_in_the_run(
        session,
        "runs on",
        "that it ran, not what it was waiting for",
    ));
    out.retain(|l| !l.is_empty());
    out.join(" ")
}

/// A leaf's finished spell of RUNNING, from its start at position `since`
/// to the transition at `end` that ended it, told as `leaf_running` tells
/// one still going: its own work, not the tree's.
pub fn leaf_ran(session: &Session, u: Uid, since: u32, end: u32) -> String {
    let idx = &session.index;
    let name = capitalised(&session.tree.told(u));
    let t = idx.transitions[end as usize - 1];
    let ticks = t.tick - idx.transitions[since as usize - 1].tick + 1;
    let how = match t.status {
        Status::Idle => "was halted",
        s => past(s),
    };
    let mut out = vec![format!(
        "{name} ran from {} until it {how} at {} ({ticks} tick{}): it is {}, so it ran on by its own work, not by anything the tree decided.",
        step_moment(idx, since),
        step_moment(idx, end),
        if ticks == 1 { "" } else { "s" },
        a_kind(session, u)
    )];
    out.push(not_in_the_run(
        session,
        "ran on",
        "that it ran, not what it was waiting for",
    ));
    out.retain(|l| !l.is_empty());
    out.join(" ")
}

/// "an action", "a condition": what kind of node `u` is.
fn a_kind(session: &Session, u: Uid) -> String {
    let what = session.tree.node(u).kind.as_str().to_lowercase();
    let a = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    format!("{a} {what}")
}

/// Where a leaf's outcome came from, when the run does not say why ("Why
/// it failed is not in the run: the plan scripted it; …"): `did` is what it
/// did, `log_says` what a robot's log records of it. Nothing where a domain
/// says what the leaf depends on.
fn not_in_the_run(session: &Session, did: &str, log_says: &str) -> String {
    match session.header.source.kind.as_str() {
        "domain" => String::new(),
        "plan" => format!(
            "Why it {did} is not in the run: the plan scripted it; give a domain file (--domain FILE) to say what it depends on."
        ),
        "world" => format!("Why it {did} is not in the run: the world's scenario decided it."),
        _ => format!(
            "Why it {did} is not in the run: the robot's log records {log_says} (the node's own logs or its outputs may say)."
        ),
    }
}

/// "X returned FAILURE itself at 10:1, after running from 9:3 (2 ticks):
/// it is an action, so nothing in the tree decided it."
pub(super) fn returned_itself(session: &Session, u: Uid, p: u32, start: Option<u32>) -> String {
    let idx = &session.index;
    let t = idx.transitions[p as usize - 1];
    let name = capitalised(&session.tree.told(u));
    let m = step_moment(idx, p);
    let ran = match start {
        Some(q) if idx.transitions[q as usize - 1].status == Status::Running => {
            let ticks = t.tick - idx.transitions[q as usize - 1].tick + 1;
            format!(
                ", after running from {} ({ticks} tick{})",
                step_moment(idx, q),
                if ticks == 1 { "" } else { "s" }
            )
        }
        _ => " in the call that started it".to_string(),
    };
    format!(
        "{name} returned {} itself at {m}{ran}: it is {}, so nothing in the tree decided it.",
        t.status.as_str(),
        a_kind(session, u)
    )
}

/// How often, and when, the leaf had ended so before position `p`.
pub(super) fn ended_so_before(session: &Session, u: Uid, p: u32) -> String {
    let idx = &session.index;
    let t = idx.transitions[p as usize - 1];
    let before: Vec<String> = idx
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q < p && idx.transitions[q as usize - 1].status == t.status)
        .map(|q| step_moment(idx, q).to_string())
        .collect();
    match before.len() {
        0 => format!("It had not {} before.", past(t.status)),
        n if n > 12 => format!(
            "It had {} {} before, at {}, … and {}.",
            past(t.status),
            times(n),
            before[..10].join(", "),
            before[n - 1]
        ),
        n => format!(
            "It had {} {} before, at {}.",
            past(t.status),
            times(n),
            before.join(", ")
        ),
    }
}

/// How the handlers above a failed leaf came out, by the moment asked:
/// the last one reached, and how it ended (`None`: it had not ended).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Handling {
    pub by: Option<Uid>,
    pub ended: Option<Status>,
}

/// What handled the leaf's failure at `p`, by position `upto`: each
/// handler above it in turn, from where the one below ended.
pub fn handled(session: &Session, u: Uid, p: u32, upto: u32) -> String {
    handling(session, u, p, upto).1
}

/// [`handled`], with how the handling came out: a handler's success ends
/// it, a failure passes it to the next one up.
pub fn handling(session: &Session, u: Uid, p: u32, upto: u32) -> (Handling, String) {
    let idx = &session.index;
    let tree = &session.tree;
    let mut said = Vec::new();
    let mut from = p;
    let mut out = Handling {
        by: None,
        ended: None,
    };
    let by = by_then(idx, upto);
    for h in tree
        .ancestors(u)
        .filter(|&a| crate::explain::failure::handles_failure(tree, a))
    {
        let done = idx
            .changes_of(h)
            .iter()
            .copied()
            .filter(|&q| q > from && q <= upto)
            .map(|q| (q, idx.transitions[q as usize - 1].status))
            .find(|(_, s)| matches!(s, Status::Success | Status::Failure));
        let hn = tree.told(h);
        out = Handling {
            by: Some(h),
            ended: done.map(|d| d.1),
        };
        let a = again_at(session, u, from, upto, done.map(|d| d.0));
        let ran = ran_between(session, h, u, from, a.or(done.map(|d| d.0)).unwrap_or(upto));
        let who = if ran.is_empty() {
            hn.clone()
        } else {
            format!("{hn} ran {ran} and")
        };
        let again = a.map(|a| tried_again(session, u, p, a, upto, done.map(|d| d.0), &who));
        if let Some(line) = &again {
            said.push(line.clone());
        }
        match done {
            Some((q, Status::Success)) => {
                said.push(match (&again, ran.is_empty()) {
                    (Some(_), _) => format!("{hn} then succeeded at {}", step_moment(idx, q)),
                    (None, true) => {
                        format!("{hn} handled it and succeeded at {}", step_moment(idx, q))
                    }
                    (None, false) => format!(
                        "{hn} handled it by running {ran}, and succeeded at {}",
                        step_moment(idx, q)
                    ),
                });
                break;
            }
            Some((q, _)) => {
                said.push(if again.is_none() && !ran.is_empty() {
                    format!("{hn} ran {ran}, and failed at {}", step_moment(idx, q))
                } else {
                    format!("{hn} then failed, at {}", step_moment(idx, q))
                });
                from = q;
            }
            None => {
                said.push(if again.is_some() {
                    // What it ran and the try again are told just before.
                    format!("{hn} had not finished {by}")
                } else if ran.is_empty() {
                    format!("{hn} handles it, and had not finished {by}")
                } else {
                    format!("{hn} handles it with {ran}, and had not finished {by}")
                });
                break;
            }
        }
    }
    let told = if said.is_empty() {
        "No fallback, retry or recovery is above it: its failure went up the tree.".into()
    } else {
        format!("{}.", capitalised(&said.join("; ")))
    };
    (out, told)
}

/// "when the run ends", or "by moment 4:5".
fn by_then(idx: &crate::session::Index, upto: u32) -> String {
    if upto as usize >= idx.transitions.len() {
        "when the run ends".to_string()
    } else {
        super::by_moment(idx, upto)
    }
}

/// Where the leaf started again after `from`, before its handler ended
/// (at `done`) and by `upto`.
fn again_at(session: &Session, u: Uid, from: u32, upto: u32, done: Option<u32>) -> Option<u32> {
    let idx = &session.index;
    idx.changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q > from && q <= upto && done.is_none_or(|d| q < d))
        .find(|&q| idx.transitions[q as usize - 1].prev == Status::Idle)
}

/// What the handler `h` ran of its own between the failure it handles
/// (at `from`) and `until`: the children it tried other than the one the
/// leaf is under ("FollowPathRecoveryFallback (#11, succeeded at 4:6)"),
/// said as a list, or "" where it ran none.
fn ran_between(session: &Session, h: Uid, u: Uid, from: u32, until: u32) -> String {
    let idx = &session.index;
    let tree = &session.tree;
    let ran: Vec<String> = tree
        .node(h)
        .children
        .iter()
        .copied()
        .filter(|&c| c != u && !tree.is_ancestor(c, u))
        .filter_map(|c| {
            let changes: Vec<(u32, Status)> = idx
                .changes_of(c)
                .iter()
                .copied()
                .filter(|&q| q > from && q <= until)
                .map(|q| (q, idx.transitions[q as usize - 1].status))
                .collect();
            let ended = changes
                .iter()
                .find(|(_, s)| matches!(s, Status::Success | Status::Failure));
            // Asked while the recovery runs: that it runs.
            let how = match (ended, changes.last()) {
                (Some(&(q, s)), _) => format!("{} at {}", past(s), step_moment(idx, q)),
                (None, Some(&(_, Status::Running))) => "still running".to_string(),
                _ => return None,
            };
            let told = tree.told(c);
            Some(match told.strip_suffix(')') {
                Some(named) => format!("{named}, {how})"),
                None => format!("{told} ({how})"),
            })
        })
        .collect();
    crate::explain::han::and_list(&ran)
}

/// How the leaf went, started again by its handler at `a` (`who`: the
/// handler, and what it ran first) before the handler ended (at `done`).
fn tried_again(
    session: &Session,
    u: Uid,
    p: u32,
    a: u32,
    upto: u32,
    done: Option<u32>,
    who: &str,
) -> String {
    let idx = &session.index;
    let status = idx.transitions[p as usize - 1].status;
    let before_done = |q: u32| q <= upto && done.is_none_or(|d| q < d);
    let ended = idx
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q >= a && before_done(q))
        .map(|q| (q, idx.transitions[q as usize - 1].status))
        .find(|(_, s)| matches!(s, Status::Success | Status::Failure));
    match ended {
        Some((q, s)) => format!(
            "{who} tried it again at {}, and it {} at {}",
            step_moment(idx, a),
            if s == status {
                format!("{} again", past(s))
            } else {
                past(s).to_string()
            },
            step_moment(idx, q)
        ),
        None => format!("{who} tried it again at {}", step_moment(idx, a)),
    }
}

/// " (assuming X went on as the run last showed)": the nodes the calls'
/// causes take as the run last showed them, each once.
fn assumed_said(tree: &Tree, g: &[&CallCause]) -> String {
    let mut assumed: Vec<Uid> = Vec::new();
    for c in g {
        for &a in &c.assumed {
            if !assumed.contains(&a) {
                assumed.push(a);
            }
        }
    }
    if assumed.is_empty() {
        return String::new();
    }
    let names: Vec<String> = assumed.iter().map(|&a| tree.told(a)).collect();
    format!(
        " (assuming {} went on as the run last showed)",
        names.join(", ")
    )
}
