//! "What happens next?" at a moment of a run, answered by running the tree
//! on, not by reading it: the run's calls as they stood at that moment
//! drive the executor through the rest of the tick (or the next tick, at a
//! tick's end), each leaf not yet called doing what it last did. Where the
//! record holds what really came next, the prediction is compared with it,
//! so the answer never claims what the run contradicts without saying so.

use super::calls::{step_moment, Replay};
use crate::model::{Tree, Uid};
use crate::run::Status;
use crate::session::{Moment, Session};

/// One predicted transition: its moment and what changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    pub tick: u32,
    pub step: u32,
    pub uid: Uid,
    pub prev: Status,
    pub status: Status,
}

/// What the record shows of the predicted span.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Record {
    /// The record ends before it.
    Silent,
    /// The record holds the same transitions.
    Same,
    /// The record parts from the prediction at this transition (the
    /// record's), or is shorter.
    Parted(Option<Step>),
}

/// The rest of the tick after a moment, as the tree would run it.
#[derive(Debug, Clone)]
pub struct Ahead {
    pub from: Moment,
    pub tick: u32,
    pub steps: Vec<Step>,
    /// Leaves the prediction asked more of than was known at the moment.
    pub assumed: Vec<Uid>,
    /// Leaves running at the end of the predicted span, with the moment
    /// each started.
    pub running: Vec<(Uid, Moment)>,
    pub record: Record,
}

/// The span after position `pos` (1-based; 0 is before the run): the rest
/// of its tick, or the next tick when `pos` ends one.
pub fn ahead(session: &Session, pos: u32) -> Result<Ahead, String> {
    let idx = &session.index;
    if pos == 0 || pos as usize > idx.transitions.len() {
        return Err("pick a moment in the run".into());
    }
    let here = idx.transitions[pos as usize - 1];
    let root = session.tree.root().uid;
    if idx.at(pos).root_outcome().is_some() {
        return Err(format!(
            "the run had ended by then ({} ended before {})",
            session.tree.told(root),
            step_moment(idx, pos)
        ));
    }
    let ends_tick = idx.tick_range(here.tick).end as u32 == pos;
    let tick = here.tick + u32::from(ends_tick);
    let replay = Replay::as_of(session, pos)?;
    let mut seen = 0u32;
    let mut steps = Vec::new();
    // Each node's status, and where its latest start was (a record
    // position, or a predicted moment).
    let mut status: Vec<(Status, u32, Moment)> = vec![
        (
            Status::Idle,
            0,
            Moment {
                tick: 0,
                step: None
            }
        );
        session.tree.len()
    ];
    let assumed = replay.run(None, tick, |step, (t, uid, prev, st)| {
        seen += 1;
        if let Some(s) = status.get_mut(uid as usize - 1) {
            s.0 = st;
            if st == Status::Running && prev != Status::Running {
                s.1 = seen;
                s.2 = Moment {
                    tick: t,
                    step: Some(step),
                };
            }
        }
        if seen > pos && t == tick {
            steps.push(Step {
                tick: t,
                step,
                uid,
                prev,
                status: st,
            });
        }
        t <= tick
    })?;
    let running = status
        .iter()
        .enumerate()
        .filter(|(i, s)| s.0 == Status::Running && session.tree.node(*i as Uid + 1).kind.is_leaf())
        .map(|(i, s)| (i as Uid + 1, s.2))
        .collect();
    let record = against_the_record(session, pos, tick, &steps);
    Ok(Ahead {
        from: step_moment(idx, pos),
        tick,
        steps,
        assumed,
        running,
        record,
    })
}

/// The steps predicted, against what the record holds of the same span:
/// the first where they part, if they do.
fn against_the_record(session: &Session, pos: u32, tick: u32, steps: &[Step]) -> Record {
    let idx = &session.index;
    if tick > idx.ticks() {
        return Record::Silent;
    }
    let span = pos as usize..idx.tick_range(tick).end;
    let rec: Vec<Step> = span
        .map(|i| {
            let t = idx.transitions[i];
            let start = idx.tick_range(t.tick).start;
            Step {
                tick: t.tick,
                step: (i - start) as u32 + 1,
                uid: t.uid,
                prev: t.prev,
                status: t.status,
            }
        })
        .collect();
    let same = |a: &Step, b: &Step| (a.uid, a.prev, a.status) == (b.uid, b.prev, b.status);
    match rec.iter().zip(steps).position(|(a, b)| !same(a, b)) {
        Some(i) => Record::Parted(Some(rec[i])),
        None if rec.len() > steps.len() => Record::Parted(Some(rec[steps.len()])),
        None if rec.len() < steps.len() => Record::Parted(None),
        None => Record::Same,
    }
}

fn verb(s: Status) -> &'static str {
    match s {
        Status::Success => "succeeds",
        Status::Failure => "fails",
        Status::Running => "starts",
        _ => "is reset",
    }
}

fn past(s: Status) -> &'static str {
    match s {
        Status::Success => "succeeded",
        Status::Failure => "failed",
        Status::Running => "started",
        _ => "was halted",
    }
}

/// The most leaves one answer lists.
const SAID_MAX: usize = 8;

impl Ahead {
    /// The answer, in sentences a person reads once.
    pub fn text(&self, tree: &Tree) -> String {
        let when = if self.from.step.is_some() && self.from.tick == self.tick {
            format!("In the rest of tick {}", self.tick)
        } else {
            format!("Next, in tick {}", self.tick)
        };
        let leaf = |u: Uid| tree.node(u).kind.is_leaf() && tree.node(u).builtin.is_none();
        let mut said: Vec<String> = self
            .steps
            .iter()
            .filter(|s| leaf(s.uid) && s.status != Status::Idle)
            .map(|s| format!("{} {}", tree.told(s.uid), verb(s.status)))
            .collect();
        let more = said.len().saturating_sub(SAID_MAX);
        said.truncate(SAID_MAX);
        if more > 0 {
            said.push(format!("{more} more"));
        }
        let halted: Vec<String> = self
            .steps
            .iter()
            .filter(|s| leaf(s.uid) && s.prev == Status::Running && s.status == Status::Idle)
            .map(|s| format!("{} is halted", tree.told(s.uid)))
            .collect();
        said.extend(halted);
        let running: Vec<String> = self
            .running
            .iter()
            .filter(|(u, _)| !self.steps.iter().any(|s| s.uid == *u))
            .map(|&(u, at)| format!("{} keeps running (since {at})", tree.told(u)))
            .collect();
        said.extend(running);
        let root = tree.root().uid;
        let ends = self
            .steps
            .iter()
            .find(|s| s.uid == root && matches!(s.status, Status::Success | Status::Failure))
            .map(|s| format!(", and the task {}", past(s.status)))
            .unwrap_or_default();
        let mut out = if said.is_empty() {
            format!("{when}, nothing changes: what runs keeps running{ends}.")
        } else {
            format!("{when}, {}{ends}.", crate::explain::han::and_list(&said))
        };
        out.push_str(&self.assumes(tree));
        match &self.record {
            Record::Silent => {}
            Record::Same => out.push_str(" The run shows the same."),
            Record::Parted(Some(s)) => out.push_str(&format!(
                " The run went otherwise: {} {} at {}:{}.",
                tree.told(s.uid),
                past(s.status),
                s.tick,
                s.step
            )),
            Record::Parted(None) => out.push_str(" The record ends before that."),
        }
        out
    }

    /// What was assumed: checks answer as they last did, and actions not
    /// ended by the moment (or started after it) run on.
    fn assumes(&self, tree: &Tree) -> String {
        let (checks, actions): (Vec<Uid>, Vec<Uid>) = self
            .assumed
            .iter()
            .partition(|&&u| tree.node(u).kind == crate::model::Kind::Condition);
        let mut assumes = Vec::new();
        if !checks.is_empty() {
            let mut names: Vec<String> = checks.iter().map(|&u| tree.told(u)).collect();
            if names.len() > SAID_MAX {
                let more = names.len() - SAID_MAX;
                names.truncate(SAID_MAX);
                names.push(format!("{more} more"));
            }
            assumes.push(format!(
                "{} {} as {} last did",
                crate::explain::han::and_list(&names),
                if names.len() == 1 {
                    "answers"
                } else {
                    "answer"
                },
                if names.len() == 1 { "it" } else { "they" }
            ));
        }
        if !self.running.is_empty() || !actions.is_empty() {
            assumes.push("actions keep running".into());
        }
        if assumes.is_empty() {
            return String::new();
        }
        format!(" This assumes {}.", crate::explain::han::and_list(&assumes))
    }

    pub fn json(&self, tree: &Tree) -> serde_json::Value {
        let step = |s: &Step| {
            serde_json::json!({
                "moment": format!("{}:{}", s.tick, s.step),
                "uid": s.uid,
                "name": tree.description(s.uid),
                "from": s.prev.as_str(),
                "to": s.status.as_str(),
            })
        };
        serde_json::json!({
            "from": self.from.to_string(),
            "tick": self.tick,
            "steps": self.steps.iter().map(step).collect::<Vec<_>>(),
            "assumed": self.assumed,
            "record": match &self.record {
                Record::Silent => serde_json::json!("not recorded"),
                Record::Same => serde_json::json!("same"),
                Record::Parted(s) => serde_json::json!({"parted": s.as_ref().map(step)}),
            },
        })
    }
}
