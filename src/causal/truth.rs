//! How often the model's counterfactuals survive a re-run: every question
//! `why` can be asked about generated runs (Love's random domains), each
//! explanation checked by running the tree again. The figure behind "every
//! answer true": what the model proposes and the re-run disproves is what
//! btx would have said wrongly without the check.

use super::verify::Check;
use crate::model::Uid;
use crate::run::domain::{Domain, DomainLeaves};
use crate::run::world::random::{generate, Params};
use crate::run::RunOptions;
use crate::session::record::simulate;
use crate::session::{Moment, Source};
use crate::xml::{load_str, LoadOptions};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// The counts of one sweep.
#[derive(Debug, Default, Clone, Serialize, PartialEq)]
pub struct Tally {
    /// Questions asked (a target at the end of a tick).
    pub questions: usize,
    /// Questions `why` refused (a fact the model does not hold, no foil).
    pub refused: usize,
    /// Explanations the model proposed.
    pub proposed: usize,
    /// Confirmed by a re-run.
    pub confirmed: usize,
    /// Shown without a re-run, by reason.
    pub not_rerun: BTreeMap<String, usize>,
    /// Disproved by a re-run, and dropped.
    pub refuted: usize,
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.questions += o.questions;
        self.refused += o.refused;
        self.proposed += o.proposed;
        self.confirmed += o.confirmed;
        self.refuted += o.refuted;
        for (k, v) in &o.not_rerun {
            *self.not_rerun.entry(k.clone()).or_default() += v;
        }
    }

    pub fn text(&self) -> String {
        let mut out = format!(
            "{} questions ({} refused), {} explanations proposed:\n  confirmed by a re-run  {}\n  disproved and dropped  {}\n",
            self.questions, self.refused, self.proposed, self.confirmed, self.refuted
        );
        for (why, n) in &self.not_rerun {
            out.push_str(&format!("  not re-run            {n}  ({why})\n"));
        }
        out
    }
}

/// Asks every status, decision and state-variable question at the end of
/// every tick of generated runs (btcm's parameters, `seeds` per
/// configuration), and counts what re-running says of each explanation.
pub fn truth_random(seeds: u64, extended: bool) -> Result<Tally, String> {
    let mut configs = Vec::new();
    for vars in [4, 8, 12] {
        for leaves in [2, 4, 8] {
            for connectivity in [0.0, 0.5, 1.0] {
                for seed in 0..seeds {
                    configs.push(Params {
                        seed,
                        vars,
                        connectivity,
                        leaves,
                        extended,
                    });
                }
            }
        }
    }
    let tallies: Vec<Result<Tally, String>> = configs.par_iter().map(one).collect();
    let mut total = Tally::default();
    for t in tallies {
        total.add(&t?);
    }
    Ok(total)
}

fn one(p: &Params) -> Result<Tally, String> {
    let g = generate(p, None);
    let name = format!("{p:?}");
    let tree = load_str(Path::new(&name), &g.xml, &LoadOptions::default())
        .map_err(|e| e.to_string())?
        .tree;
    let domain = Arc::new(Domain::parse(Path::new(&name), &g.domain).map_err(|e| e.to_string())?);
    let leaves = DomainLeaves::new(Arc::clone(&domain), &tree).map_err(|e| e.to_string())?;
    let source = Source {
        kind: "domain".into(),
        path: None,
        text: Some(g.domain.clone()),
        name: None,
    };
    let ticks = if p.extended { 6 } else { 1 };
    let s = simulate(&tree, source, None, ticks, RunOptions::default(), leaves)?;
    let first = super::model_at(&s, Some(Arc::clone(&domain)), 1).map_err(|e| e.to_string())?;
    let mut targets: Vec<String> = Vec::new();
    for u in 1..=tree.len() as Uid {
        targets.push(format!("status(#{u})"));
        if first.d(u).is_some() {
            targets.push(format!("decision(#{u})"));
        }
    }
    targets.extend(domain.vars.iter().map(|v| v.name.clone()));
    let mut t = Tally::default();
    for tick in 1..=s.index.ticks() {
        let at = Moment { tick, step: None };
        for target in &targets {
            t.questions += 1;
            match super::why(&s, Some(Arc::clone(&domain)), target, &[], Some(at), 2) {
                Err(_) => t.refused += 1,
                Ok(w) => {
                    t.proposed += w.checks.len() + w.dropped.len();
                    t.refuted += w.dropped.len();
                    for c in &w.checks {
                        match c {
                            Check::Confirmed { .. } => t.confirmed += 1,
                            Check::NotRerun(why) => {
                                // One line per kind of reason, not per node.
                                let kind =
                                    if why.contains("so a re-run cannot give it another status") {
                                        "a status given to a node the tick did not tick".to_string()
                                    } else {
                                        why.clone()
                                    };
                                *t.not_rerun.entry(kind).or_default() += 1
                            }
                            Check::Refuted { .. } => {}
                        }
                    }
                }
            }
        }
    }
    Ok(t)
}
