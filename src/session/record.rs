//! Recording a run into a session file as it goes.

use super::format::{fnv64, Header, Source, TreeRef, FORMAT_VERSION};
use super::{Index, SessionWriter, Transition};
use crate::model::edit::Insertion;
use crate::model::{Tree, Uid};
use crate::run::{Event, Executor, Leaves, RunError, RunOptions, Status};
use crate::source::Located;
use std::path::{Path, PathBuf};

/// What to run and where to record it.
pub struct RunRequest<'a> {
    pub tree: &'a Tree,
    /// The tree file's path and text, named in the header.
    pub tree_file: Option<(&'a Path, &'a str)>,
    pub source: Source,
    pub seed: Option<u64>,
    pub max_ticks: u32,
    pub options: RunOptions,
    /// A "Can you X?" question asked at the end of a tick.
    pub ask: Option<Asked>,
    pub out: &'a Path,
}

/// "Can you X?" asked at the end of a tick of a run being recorded
/// (`explain::insert::asked_during_run` makes one).
#[derive(Clone)]
pub struct Asked {
    pub tick: u32,
    /// X: the behaviour the question names.
    pub behaviour: String,
    /// Whether and where the robot executing a node can do X.
    pub decide: fn(&Tree, Uid, &str) -> Result<Insertion, String>,
}

#[derive(Debug, Clone)]
pub struct RunSummary {
    pub path: PathBuf,
    pub ticks: u32,
    pub root: Status,
    pub transitions: u64,
    pub reason: String,
    /// The answer to the question asked during the run.
    pub answer: Option<String>,
}

/// A run that stopped on an error; the session up to it is kept.
#[derive(Debug)]
pub enum RecordError {
    /// The session could not be written.
    Io(Located),
    /// The tree could not go on; the session was finished up to here.
    Run(RunError, RunSummary),
    /// A leaf's script failed; the session was finished up to here.
    Script(Located, RunSummary),
}

/// The session's header; without `xml`, the tree is not written into it.
pub fn header(req: &RunRequest, xml: bool) -> Header {
    Header {
        btx_session: FORMAT_VERSION,
        btx_version: env!("CARGO_PKG_VERSION").to_string(),
        tree: TreeRef {
            path: req.tree_file.map(|(p, _)| p.display().to_string()),
            hash: req.tree_file.map(|(_, t)| fnv64(t)),
            xml: if xml {
                crate::xml::to_v4_xml(req.tree)
            } else {
                String::new()
            },
            btcpp_format: req.tree.version.number(),
            main_tree: req.tree.main_tree.clone(),
        },
        source: req.source.clone(),
        seed: req.seed,
        tick_ms: req.options.tick_ms,
        // Written where it is not main's, so that a re-run follows it.
        nav2: (req.options.nav2 != Default::default()).then_some(req.options.nav2),
        blackboard: Vec::new(),
        before: Vec::new(),
    }
}

/// Adds an event of a run to an index.
fn index_event(index: &mut Index, tree: &Tree, e: Event) {
    match e {
        Event::Transition {
            tick,
            uid,
            prev,
            status,
            decision,
        } => index.push_transition(
            tree,
            Transition {
                tick,
                uid,
                prev,
                status,
            },
            decision,
        ),
        Event::Decision {
            tick,
            uid,
            decision,
        } => index.push_decision_call(tick, uid, decision),
        Event::Write {
            tick,
            uid,
            entry,
            value,
        } => index.push_write_by(tick, uid, entry, value),
    }
}

/// Runs a tree in memory, without a session file: the session a recorded
/// run would give (for evaluations that run thousands of times).
pub fn simulate<L: Leaves>(
    tree: &Tree,
    source: Source,
    seed: Option<u64>,
    max_ticks: u32,
    options: RunOptions,
    leaves: L,
) -> Result<super::Session, String> {
    let req = RunRequest {
        tree,
        tree_file: None,
        source,
        seed,
        max_ticks,
        options,
        ask: None,
        out: Path::new("(simulated)"),
    };
    // Never written to a file: the tree's XML would only cost time.
    let mut h = header(&req, false);
    let mut ex = Executor::new(tree, leaves, options);
    h.blackboard = ex.bb.entries().map(|(e, v)| (e, v.clone())).collect();
    let mut index = Index::new(tree.len());
    for (e, v) in &h.blackboard {
        index.push_write(e.clone(), v.clone());
    }
    let mut root = Status::Idle;
    let mut reason = "max ticks".to_string();
    while ex.ticks() < max_ticks {
        let r = ex.tick_once();
        for e in ex.take_events() {
            index_event(&mut index, tree, e);
        }
        index.end_tick(ex.ticks());
        if let Some(e) = ex.leaves.take_error() {
            return Err(e.to_string());
        }
        root = r.map_err(|e| e.to_string())?;
        if ex.leaves.run_over(root) {
            reason = "root completed".into();
            break;
        }
    }
    Ok(super::Session {
        path: PathBuf::from("(simulated)"),
        header: h,
        tree: tree.clone(),
        index,
        end: Some((ex.ticks(), root, reason)),
        inserts: Vec::new(),
        span_us: None,
        times_us: Vec::new(),
        warnings: Vec::new(),
        run: None,
    })
}

/// The recording so far.
struct Rec {
    w: SessionWriter,
    index: Index,
    transitions: u64,
    root: Status,
    ended: Option<String>,
    failure: Option<RunError>,
    script: Option<Located>,
}

/// Ticks until the root completes, an error, or tick `until`. True when the run is over.
fn phase<L: Leaves>(
    ex: &mut Executor<L>,
    tree: &Tree,
    rec: &mut Rec,
    until: u32,
) -> Result<bool, RecordError> {
    while ex.ticks() < until {
        let r = ex.tick_once();
        for e in ex.take_events() {
            rec.w.event(&e).map_err(RecordError::Io)?;
            if matches!(e, Event::Transition { .. }) {
                rec.transitions += 1;
            }
            index_event(&mut rec.index, tree, e);
        }
        rec.index.end_tick(ex.ticks());
        rec.w.flush().map_err(RecordError::Io)?;
        if let Some(e) = ex.leaves.take_error() {
            rec.ended = Some(format!("error: {e}"));
            rec.script = Some(e);
            return Ok(true);
        }
        match r {
            Err(e) => {
                rec.ended = Some(format!("error: {e}"));
                rec.failure = Some(e);
                return Ok(true);
            }
            Ok(s) => rec.root = s,
        }
        if ex.leaves.run_over(rec.root) {
            rec.ended = Some("root completed".into());
            return Ok(true);
        }
    }
    Ok(false)
}

fn finish(rec: Rec, ticks: u32, answer: Option<String>) -> Result<RunSummary, RecordError> {
    let reason = rec.ended.unwrap_or_else(|| "max ticks".into());
    let path = rec
        .w
        .finish(ticks, rec.root, &reason)
        .map_err(RecordError::Io)?;
    let summary = RunSummary {
        path,
        ticks,
        root: rec.root,
        transitions: rec.transitions,
        reason,
        answer,
    };
    if let Some(e) = rec.script {
        return Err(RecordError::Script(e, summary));
    }
    match rec.failure {
        Some(e) => Err(RecordError::Run(e, summary)),
        None => Ok(summary),
    }
}

/// Runs the tree until the root completes or `max_ticks`, writing every
/// event to the session as it happens. A "Can you X?" answered yes inserts
/// the subgoal and the run goes on with it.
pub fn record<L: Leaves>(req: RunRequest, leaves: L) -> Result<RunSummary, RecordError> {
    let mut h = header(&req, true);
    let mut ex = Executor::new(req.tree, leaves, req.options);
    h.blackboard = ex.bb.entries().map(|(e, v)| (e, v.clone())).collect();
    let w = SessionWriter::create(req.out, &h).map_err(RecordError::Io)?;
    let mut index = Index::new(req.tree.len());
    for (e, v) in &h.blackboard {
        index.push_write(e.clone(), v.clone());
    }
    let mut rec = Rec {
        w,
        index,
        transitions: 0,
        root: Status::Idle,
        ended: None,
        failure: None,
        script: None,
    };
    let ask_tick = req
        .ask
        .as_ref()
        .map(|a| a.tick)
        .filter(|t| *t < req.max_ticks);
    if phase(
        &mut ex,
        req.tree,
        &mut rec,
        ask_tick.unwrap_or(req.max_ticks),
    )? {
        let ticks = ex.ticks();
        return finish(rec, ticks, None);
    }
    let Some(asked) = req.ask.as_ref().filter(|_| ask_tick.is_some()) else {
        let ticks = ex.ticks();
        return finish(rec, ticks, None);
    };
    let (t, x) = (&asked.tick, &asked.behaviour);
    let at = rec.index.at(rec
        .index
        .position(super::Moment {
            tick: *t,
            step: None,
        })
        .expect("the tick ran"));
    let decided = match at.current() {
        None => Err(format!(
            "Sorry. I cannot redo \"{x}\": I am not doing anything yet."
        )),
        Some(cur) => (asked.decide)(req.tree, cur, x),
    };
    match decided {
        Ok(ins) => {
            let (modified, first) = req
                .tree
                .with_copy_after(ins.copy_of, ins.after)
                .expect("checked by can_you");
            rec.w
                .insert(*t, ins.copy_of, ins.after, first, &format!("Can you {x}?"))
                .map_err(RecordError::Io)?;
            rec.index.resize(modified.len());
            let mut ex = ex.retarget(&modified);
            phase(&mut ex, &modified, &mut rec, req.max_ticks)?;
            let ticks = ex.ticks();
            finish(rec, ticks, Some(ins.answer))
        }
        Err(refusal) => {
            phase(&mut ex, req.tree, &mut rec, req.max_ticks)?;
            let ticks = ex.ticks();
            finish(rec, ticks, Some(refusal))
        }
    }
}
