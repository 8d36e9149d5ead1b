//! Running a recorded session again: the leaves its header names (the plan,
//! domain or world that made the run), rebuilt from the text the session
//! embeds, so that a claim about the run can be checked against the tree
//! itself rather than against the model that made the claim.

use super::Session;
use crate::run::blackboard::EntryId;
use crate::run::domain::{Domain, DomainLeaves};
use crate::run::plan::{Plan, PlanLeaves};
use crate::run::world::taxi::{Grid, TaxiLeaves};
use crate::run::{LeafCall, LeafOutcome, Leaves, Status};
use crate::source::Located;
use crate::Uid;
use serde_json::Value;
use std::path::PathBuf;
use std::sync::Arc;

/// The leaves of a recorded run, whichever made it. One lives per re-run,
/// so the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
pub enum SourceLeaves {
    Plan(PlanLeaves),
    Domain(DomainLeaves),
    Taxi(TaxiLeaves),
}

impl Leaves for SourceLeaves {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        match self {
            SourceLeaves::Plan(l) => l.tick(call),
            SourceLeaves::Domain(l) => l.tick(call),
            SourceLeaves::Taxi(l) => l.tick(call),
        }
    }

    fn halt(&mut self, uid: Uid) {
        match self {
            SourceLeaves::Plan(l) => l.halt(uid),
            SourceLeaves::Domain(l) => l.halt(uid),
            SourceLeaves::Taxi(l) => l.halt(uid),
        }
    }

    fn observe(&mut self, uid: Uid, prev: Status, status: Status) {
        match self {
            SourceLeaves::Plan(l) => l.observe(uid, prev, status),
            SourceLeaves::Domain(l) => l.observe(uid, prev, status),
            SourceLeaves::Taxi(l) => l.observe(uid, prev, status),
        }
    }

    fn enums(&self) -> &[(String, i64)] {
        match self {
            SourceLeaves::Plan(l) => l.enums(),
            SourceLeaves::Domain(l) => l.enums(),
            SourceLeaves::Taxi(l) => l.enums(),
        }
    }

    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        match self {
            SourceLeaves::Plan(l) => l.initial_entries(),
            SourceLeaves::Domain(l) => l.initial_entries(),
            SourceLeaves::Taxi(l) => l.initial_entries(),
        }
    }

    fn run_over(&mut self, root: Status) -> bool {
        match self {
            SourceLeaves::Plan(l) => l.run_over(root),
            SourceLeaves::Domain(l) => l.run_over(root),
            SourceLeaves::Taxi(l) => l.run_over(root),
        }
    }

    fn take_error(&mut self) -> Option<Located> {
        match self {
            SourceLeaves::Plan(l) => l.take_error(),
            SourceLeaves::Domain(l) => l.take_error(),
            SourceLeaves::Taxi(l) => l.take_error(),
        }
    }
}

/// Why a session cannot be run again.
pub fn not_rerunnable(session: &Session) -> Option<String> {
    let src = &session.header.source;
    if !session.inserts.is_empty() {
        return Some("a subgoal was inserted during the run".into());
    }
    match (src.kind.as_str(), &src.text, src.name.as_deref()) {
        ("plan" | "domain", Some(_), _) => None,
        ("world", _, Some("taxi")) => None,
        ("world", Some(_), Some(n)) if n.starts_with("kitting") => None,
        ("import", ..) => {
            Some("the session is a log: it holds no plan, domain or world to run it again".into())
        }
        _ => Some(format!(
            "the session's source ({}) cannot be run again",
            src.kind
        )),
    }
}

/// The leaves that made the session's run, as they were at its start
/// (a domain run's `--set` values come from the recorded blackboard).
pub fn leaves_of(session: &Session) -> Result<SourceLeaves, String> {
    if let Some(why) = not_rerunnable(session) {
        return Err(why);
    }
    let src = &session.header.source;
    let name = PathBuf::from(format!(
        "{} (embedded in {})",
        src.path.as_deref().unwrap_or(&src.kind),
        session.path.display()
    ));
    let text = src.text.as_deref().unwrap_or_default();
    match src.kind.as_str() {
        "domain" => {
            let d = Arc::new(Domain::parse(&name, text).map_err(|e| e.to_string())?);
            let mut leaves =
                DomainLeaves::new(Arc::clone(&d), &session.tree).map_err(|e| e.to_string())?;
            for (e, v) in &session.header.blackboard {
                let Some(k) = d.var(&e.key).filter(|_| e.scope == 0) else {
                    continue;
                };
                if d.vars[k].function.is_none() && leaves.state[k] != *v {
                    leaves.apply(k, v.clone()).map_err(|e| e.to_string())?;
                }
            }
            Ok(SourceLeaves::Domain(leaves))
        }
        "world" if src.name.as_deref() == Some("taxi") => {
            Ok(SourceLeaves::Taxi(TaxiLeaves::new(Grid::han())))
        }
        _ => {
            let plan = Plan::parse(&name, text).map_err(|e| e.to_string())?;
            let mut leaves = PlanLeaves::new(plan, &session.tree);
            // What the run started with (`btx run --set`).
            leaves.seeds = session.header.blackboard.clone();
            Ok(SourceLeaves::Plan(leaves))
        }
    }
}
