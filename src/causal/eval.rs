//! Target recovery (Love et al. §7): perturb one input of a run, explain
//! the first difference between the default and the altered run, and count
//! the perturbed variable as recovered if it is among the reasons.

use super::compare::{difference_query, first_difference};
use super::facts::TickFacts;
use super::model::{Model, VarKind};
use super::search::{search, Query};
use crate::run::domain::{Domain, DomainLeaves};
use crate::run::world::random::{generate, Params};
use crate::run::RunOptions;
use crate::session::record::simulate;
use crate::session::{Session, Source};
use crate::xml::{load_str, LoadOptions};
use crate::Tree;
use rayon::prelude::*;
use serde_json::Value;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// One comparison of a default run with an altered one.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    pub config: String,
    pub vars: usize,
    pub leaves: usize,
    pub seed: u64,
    /// The perturbed variable.
    pub target: String,
    /// `None`: the runs do not differ.
    pub found: Option<bool>,
    /// Explanations as btcm counts them (one per set of intervened
    /// variables and outcome), and once copies are merged.
    pub explanations: usize,
    pub merged: usize,
    pub model_nodes: usize,
    pub model_edges: usize,
    pub evaluated: usize,
    pub seconds: f64,
}

/// A run of `domain` from its initial state with some variables set first
/// (their derived variables recomputed).
impl Row {
    /// A comparison of `config` ((variables, leaves, seed)) that perturbed
    /// `target`, begun at `start`.
    fn of(
        config: &str,
        (vars, leaves, seed): (usize, usize, u64),
        target: &str,
        c: &Comparison,
        start: Instant,
    ) -> Row {
        Row {
            config: config.to_string(),
            vars,
            leaves,
            seed,
            target: target.to_string(),
            found: c.found,
            explanations: c.explanations,
            merged: c.merged,
            model_nodes: c.model_nodes,
            model_edges: c.model_edges,
            evaluated: c.evaluated,
            seconds: start.elapsed().as_secs_f64(),
        }
    }
}

fn run(
    tree: &Tree,
    domain: &Arc<Domain>,
    text: &str,
    set: &[(usize, Value)],
    max_ticks: u32,
) -> Result<Session, String> {
    let mut leaves = DomainLeaves::new(Arc::clone(domain), tree).map_err(|e| e.to_string())?;
    for (k, v) in set {
        leaves.state[*k] = v.clone();
    }
    let changed: Vec<usize> = set.iter().map(|(k, _)| *k).collect();
    domain
        .propagate(&mut leaves.state, &changed, &[])
        .map_err(|e| e.to_string())?;
    simulate(
        tree,
        Source {
            kind: "domain".into(),
            path: None,
            text: Some(text.to_string()),
            name: None,
        },
        None,
        max_ticks,
        RunOptions::default(),
        leaves,
    )
}

/// What explaining one difference gave.
#[derive(Debug, Clone, Default)]
pub struct Comparison {
    /// `None`: the runs do not differ.
    pub found: Option<bool>,
    pub explanations: usize,
    pub merged: usize,
    pub model_nodes: usize,
    pub model_edges: usize,
    pub evaluated: usize,
}

/// Compares `default` with `altered` (the run with `target` perturbed)
/// and explains their first difference.
pub fn compare(
    tree: &Tree,
    domain: &Arc<Domain>,
    default: &Session,
    altered: &Session,
    target: usize,
    max_depth: usize,
) -> Result<Comparison, String> {
    let Some(d) = first_difference(default, altered) else {
        return Ok(Comparison::default());
    };
    let facts = TickFacts::of(altered, d.moment.tick)?;
    let m = Model::build(tree, Some(Arc::clone(domain)), facts).map_err(|e| e.to_string())?;
    let Some((t, foils)) = difference_query(&m, &d) else {
        return Ok(Comparison {
            model_nodes: m.vars.len(),
            model_edges: m.edge_count(),
            ..Comparison::default()
        });
    };
    let q = Query {
        targets: vec![t],
        foils: vec![foils],
    };
    let a = search(&m, &q, max_depth).map_err(|e| e.to_string())?;
    let found = a.explanations.iter().any(|e| {
        e.vars
            .iter()
            .any(|&v| matches!(m.vars[v].kind, VarKind::State { var, .. } if var == target))
    });
    let merged = super::english::merge(&m, &a).len();
    Ok(Comparison {
        found: Some(found),
        explanations: a.explanations.len(),
        merged,
        model_nodes: m.vars.len(),
        model_edges: m.edge_count(),
        evaluated: a.evaluated,
    })
}

/// The paper's grid: 4/8/12 variables × 2/4/8 leaves × 5 connectivities ×
/// `seeds` seeds, every top-level variable flipped in turn.
pub fn recovery_random(seeds: u64, extended: bool) -> Result<Vec<Row>, String> {
    let mut configs = Vec::new();
    for vars in [4, 8, 12] {
        for leaves in [2, 4, 8] {
            for connectivity in [0.0, 0.25, 0.5, 0.75, 1.0] {
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
    let rows: Vec<Result<Vec<Row>, String>> = configs
        .par_iter()
        .map(|p| {
            let g = generate(p, None);
            let name = format!(
                "random seed {} vars {} connectivity {} leaves {}",
                p.seed, p.vars, p.connectivity, p.leaves
            );
            let tree = load_str(Path::new(&name), &g.xml, &LoadOptions::default())
                .map_err(|e| e.to_string())?
                .tree;
            let domain =
                Arc::new(Domain::parse(Path::new(&name), &g.domain).map_err(|e| e.to_string())?);
            let ticks = if extended { 8 } else { 1 };
            let default = run(&tree, &domain, &g.domain, &[], ticks)?;
            let mut out = Vec::new();
            for t in &g.top {
                let k = domain.var(t).expect("generated variables exist");
                let start = Instant::now();
                let flipped = !default.header.blackboard[k].1.as_bool().unwrap_or(false);
                let altered = run(
                    &tree,
                    &domain,
                    &g.domain,
                    &[(k, Value::Bool(flipped))],
                    ticks,
                )?;
                let c = compare(&tree, &domain, &default, &altered, k, p.vars)?;
                out.push(Row::of(&name, (p.vars, p.leaves, p.seed), t, &c, start));
            }
            Ok(out)
        })
        .collect();
    let mut out = Vec::new();
    for r in rows {
        out.extend(r?);
    }
    Ok(out)
}

/// The rows whose target was found, how many runs did not differ, and the
/// recovery rate (found over runs that differ).
fn recovered<'a>(sel: &[&'a Row]) -> (Vec<&'a Row>, usize, String) {
    let found: Vec<&Row> = sel
        .iter()
        .copied()
        .filter(|r| r.found == Some(true))
        .collect();
    let differ = sel.iter().filter(|r| r.found.is_some()).count();
    let rate = if differ == 0 {
        "-".to_string()
    } else {
        format!("{:.3}", found.len() as f64 / differ as f64)
    };
    (found, sel.len() - differ, rate)
}

fn stats(xs: &[f64]) -> String {
    if xs.is_empty() {
        return "-".into();
    }
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let sd = if xs.len() > 1 {
        (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    let min = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let max = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    format!("{min:.0} {max:.0} {mean:.2} ({sd:.2})")
}

/// Love et al.'s Table 2: found, no difference, nodes (min max mean), explanations (mean).
/// A row of the paper's table: (variables, leaves) and (found, no
/// difference, node counts, mean explanations).
type PaperRow = ((usize, usize), (usize, usize, &'static str, &'static str));

const PAPER_TABLE2: [PaperRow; 10] = [
    ((4, 2), (49, 51, "10 14 11.71", "1.86")),
    ((4, 4), (48, 52, "19 29 22.52", "2.00")),
    ((4, 8), (47, 53, "33 51 40.64", "1.89")),
    ((8, 2), (76, 124, "14 24 16.83", "2.86")),
    ((8, 4), (79, 121, "22 45 29.04", "2.92")),
    ((8, 8), (93, 107, "43 77 57.73", "3.15")),
    ((12, 2), (81, 219, "18 33 23.68", "3.49")),
    ((12, 4), (109, 191, "28 60 40.39", "3.10")),
    ((12, 8), (124, 176, "50 105 77.81", "4.12")),
    ((0, 0), (706, 1094, "10 105 40.33", "3.04")),
];

/// The rows as Love et al.'s Table 2, the paper's figures beside ours.
pub fn table2(rows: &[Row]) -> String {
    let mut out = String::from(
        "vars leaves | found no-diff recovery | model nodes min max mean (sd) | explanations min max mean (sd) | merged mean || paper: found no-diff nodes(min max mean) expl. mean\n",
    );
    let mut groups: Vec<(usize, usize)> = Vec::new();
    for r in rows {
        if !groups.contains(&(r.vars, r.leaves)) {
            groups.push((r.vars, r.leaves));
        }
    }
    groups.push((0, 0));
    for g in groups {
        let sel: Vec<&Row> = rows
            .iter()
            .filter(|r| g == (0, 0) || (r.vars, r.leaves) == g)
            .collect();
        let (found, nodiff, rate) = recovered(&sel);
        let nodes: Vec<f64> = found.iter().map(|r| r.model_nodes as f64).collect();
        let expl: Vec<f64> = found.iter().map(|r| r.explanations as f64).collect();
        let merged: Vec<f64> = found.iter().map(|r| r.merged as f64).collect();
        let paper = PAPER_TABLE2
            .iter()
            .find(|(k, _)| *k == g)
            .map(|(_, (f, n, nodes, e))| format!("{f} {n} {nodes} {e}"))
            .unwrap_or_default();
        let label = if g == (0, 0) {
            "All       ".to_string()
        } else {
            format!("{:>4} {:>6}", g.0, g.1)
        };
        out.push_str(&format!(
            "{label} | {:>5} {:>7} {:>8} | {:>29} | {:>30} | {:>11} || {paper}\n",
            found.len(),
            nodiff,
            rate,
            stats(&nodes),
            stats(&expl),
            if merged.is_empty() {
                "-".to_string()
            } else {
                format!("{:.2}", merged.iter().sum::<f64>() / merged.len() as f64)
            }
        ));
    }
    out
}

/// The serial-recall task, shipped in `trees/` and built in.
pub const SERIAL_RECALL_TREE: &str = include_str!("../../trees/serial-recall.xml");
pub const SERIAL_RECALL_DOMAIN: &str = include_str!("../../trees/serial-recall.domain.toml");

/// Love et al.'s altered profiles: name, the variable perturbed, its value.
pub const PROFILES: [(&str, &str, f64); 4] = [
    ("frustrated", "UserFrustration", 0.8),
    ("no_attention", "UserAttention", 0.0),
    ("no_reactivity", "UserReactivity", 0.0),
    ("no_memory", "UserMemory", 0.0),
];

/// The serial-recall tree and domain (with the profile's frustration).
pub fn serial_recall(frustration: f64) -> Result<(Tree, Arc<Domain>, String), String> {
    let tree = load_str(
        Path::new("trees/serial-recall.xml"),
        SERIAL_RECALL_TREE,
        &LoadOptions::default(),
    )
    .map_err(|e| e.to_string())?
    .tree;
    let text = SERIAL_RECALL_DOMAIN.replace(
        "fn base_frustration() { 0.2 }",
        &format!("fn base_frustration() {{ {frustration:?} }}"),
    );
    let domain = Domain::parse(Path::new("trees/serial-recall.domain.toml"), &text)
        .map_err(|e| e.to_string())?;
    Ok((tree, Arc::new(domain), text))
}

/// Each profile against the default one, over `seeds` seeds (the user's
/// accuracy and response-time seeds are the seed and the seed + 1000).
pub fn recovery_serial_recall(seeds: u64) -> Result<Vec<Row>, String> {
    let (tree, domain, text) = serial_recall(0.2)?;
    let (_, frustrated, ftext) = serial_recall(0.8)?;
    let var = |n: &str| domain.var(n).ok_or(format!("no variable {n}"));
    let (aseed, tseed) = (var("AccuracySeed")?, var("ResponseTimeSeed")?);
    let per_seed: Vec<Result<Vec<Row>, String>> = (0..seeds)
        .into_par_iter()
        .map(|seed| {
            let seeds = [
                (aseed, Value::from(seed as i64)),
                (tseed, Value::from(seed as i64 + 1000)),
            ];
            let default = run(&tree, &domain, &text, &seeds, 200)?;
            let mut rows = Vec::new();
            for (name, target, value) in PROFILES {
                let k = var(target)?;
                let start = Instant::now();
                let (d, altered) = if name == "frustrated" {
                    (&frustrated, run(&tree, &frustrated, &ftext, &seeds, 200)?)
                } else {
                    let mut set = seeds.to_vec();
                    set.push((k, Value::from(value)));
                    (&domain, run(&tree, &domain, &text, &set, 200)?)
                };
                let c = compare(&tree, d, &default, &altered, k, 2)?;
                rows.push(Row::of(
                    name,
                    (domain.vars.len(), 18, seed),
                    target,
                    &c,
                    start,
                ));
            }
            Ok(rows)
        })
        .collect();
    let mut rows = Vec::new();
    for r in per_seed {
        rows.extend(r?);
    }
    Ok(rows)
}

/// Love et al.'s Table 3: found, no difference, explanations min max mean (sd).
const PAPER_TABLE3: [(&str, &str); 5] = [
    ("frustrated", "47 3 1 5 1.09 (0.58)"),
    ("no_attention", "50 0 5 17 6.62 (1.93)"),
    ("no_reactivity", "49 1 3 38 7.37 (10.08)"),
    ("no_memory", "50 0 3 38 18.48 (14.64)"),
    ("All", "196 4 1 38 8.51 (10.95)"),
];

/// The rows as Love et al.'s Table 3, the paper's figures beside ours.
pub fn table3(rows: &[Row]) -> String {
    let mut out = String::from(
        "profile       | found no-diff recovery | explanations min max mean (sd) | merged mean | model nodes/edges || paper: found no-diff expl. min max mean (sd)\n",
    );
    let mut names: Vec<&str> = PROFILES.iter().map(|p| p.0).collect();
    names.push("All");
    for name in names {
        let sel: Vec<&Row> = rows
            .iter()
            .filter(|r| name == "All" || r.config == name)
            .collect();
        let (found, nodiff, rate) = recovered(&sel);
        let expl: Vec<f64> = found.iter().map(|r| r.explanations as f64).collect();
        let merged = if found.is_empty() {
            "-".to_string()
        } else {
            format!(
                "{:.2}",
                found.iter().map(|r| r.merged as f64).sum::<f64>() / found.len() as f64
            )
        };
        let size = found.first().map_or("-".to_string(), |r| {
            format!("{}/{}", r.model_nodes, r.model_edges)
        });
        let paper = PAPER_TABLE3
            .iter()
            .find(|(n, _)| *n == name)
            .map_or("", |(_, p)| p);
        out.push_str(&format!(
            "{name:<13} | {:>5} {:>7} {:>8} | {:>30} | {merged:>11} | {size:>17} || {paper}\n",
            found.len(),
            nodiff,
            rate,
            stats(&expl),
        ));
    }
    out
}
