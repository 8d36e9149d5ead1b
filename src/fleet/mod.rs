//! A fleet's runs answered at once (#31): per node, in how many runs it ran
//! and failed, how long it kept RUNNING, and what recovered its failures;
//! per run, how it ended and, when it failed, what went wrong; the failed
//! runs grouped by that answer. Each run is summarised as it is read
//! (`summary`), on every core, and only the summaries are kept.

pub mod export;
pub mod partition;
pub mod summary;

use crate::model::Uid;
use crate::run::Status;
use crate::session::Session;
use crate::text::counted as count;
use rayon::prelude::*;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use summary::{summarise, RunSummary};

/// A run file, and the path given that named it (itself, or a directory
/// it was found in).
#[derive(Debug, Clone)]
pub struct Source {
    pub file: PathBuf,
    pub given: PathBuf,
}

/// The files of a fleet: each path as given, a directory's run files
/// (`.jsonl`, `.parquet` sessions, `.btlog`, `.fbl`, `.db3`, `.mcap`,
/// recursively, in name order).
pub fn files(paths: &[PathBuf]) -> Result<Vec<Source>, crate::Located> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut found = Vec::new();
            walk(p, &mut found)?;
            out.extend(found.into_iter().map(|file| Source {
                file,
                given: p.clone(),
            }));
        } else {
            out.push(Source {
                file: p.clone(),
                given: p.clone(),
            });
        }
    }
    Ok(out)
}

/// The extensions of the files a directory is searched for.
pub const RUN_EXTENSIONS: [&str; 6] = ["jsonl", "parquet", "btlog", "fbl", "db3", "mcap"];

/// A run file by its extension; a Parquet file only if it is a session
/// (a fleet's own `--export` tables may lie among its runs).
fn is_run_file(p: &Path) -> bool {
    match p.extension().and_then(|e| e.to_str()) {
        Some("parquet") => crate::session::columnar::is_session_file(p),
        Some(e) => RUN_EXTENSIONS.contains(&e),
        None => false,
    }
}

/// A directory's run files, its subdirectories' too; a link to a
/// directory is not followed (a link back up would never end).
fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), crate::Located> {
    let read = std::fs::read_dir(dir)
        .map_err(|e| crate::Located::file(dir, format!("cannot read the directory: {e}")))?;
    let mut entries: Vec<(PathBuf, bool)> = read
        .filter_map(|e| {
            let e = e.ok()?;
            Some((e.path(), e.file_type().ok()?.is_dir()))
        })
        .collect();
    entries.sort();
    for (p, is_dir) in entries {
        if is_dir {
            walk(&p, out)?;
        } else if p.is_file() && is_run_file(&p) {
            out.push(p);
        }
    }
    Ok(())
}

/// The runs of many files, summarised.
pub struct Fleet {
    /// Each run's summary, without its nodes: they are counted into
    /// `stats` as the run is read, so that a run costs its summary only.
    pub runs: Vec<RunSummary>,
    /// Each node of each tree, across the runs.
    stats: BTreeMap<(String, Uid), NodeStats>,
    /// Files that could not be read, with why.
    pub errors: Vec<(String, String)>,
    /// Tables that could not be written (`--export`), with why.
    pub unwritten: Vec<String>,
    /// With a reference run: each run compared with it (`btx diff REF RUN...`).
    pub reference: Option<crate::diff::fleet::Fleet>,
}

/// A node across the runs, paired by its path.
#[derive(Debug, Clone, Default)]
pub struct NodeStats {
    pub uid: Uid,
    /// Its tree (`RunSummary::tree_key`), and the tree's name.
    pub tree_key: String,
    pub tree: String,
    pub path: String,
    pub name: String,
    pub leaf: bool,
    /// Runs in which it ran, and in which it failed.
    pub ran_in: usize,
    pub failed_in: usize,
    pub failures: u64,
    /// Runs in which its failure was a fault, and its faults; its other
    /// failures are branches taken.
    pub faulted_in: usize,
    pub faults: u64,
    /// Its RUNNING spells' lengths in ticks, counted by length.
    pub running: Spells,
    /// Failures recovered, by the handler that recovered them.
    pub recovered: BTreeMap<String, u64>,
    /// Failures no handler recovered by the run's end.
    pub unrecovered: u64,
}

impl NodeStats {
    /// The spell length below which `q` of them are (nearest rank).
    pub fn running_quantile(&self, q: f64) -> Option<u32> {
        self.running.quantile(q)
    }
}

/// RUNNING spells counted by their length in ticks: a fleet keeps a count
/// a length, not every spell (bounded by the lengths that occurred).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Spells {
    by_length: BTreeMap<u32, u64>,
    count: u64,
}

impl Spells {
    pub fn add(&mut self, length: u32) {
        *self.by_length.entry(length).or_default() += 1;
        self.count += 1;
    }

    pub fn len(&self) -> u64 {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    pub fn max(&self) -> Option<u32> {
        self.by_length.keys().next_back().copied()
    }

    /// The length below which `q` of the spells are (nearest rank).
    pub fn quantile(&self, q: f64) -> Option<u32> {
        if self.count == 0 {
            return None;
        }
        let rank = ((q * self.count as f64).ceil() as u64).clamp(1, self.count);
        let mut seen = 0;
        for (&length, &k) in &self.by_length {
            seen += k;
            if seen >= rank {
                return Some(length);
            }
        }
        self.max()
    }
}

impl FromIterator<u32> for Spells {
    fn from_iter<I: IntoIterator<Item = u32>>(lengths: I) -> Spells {
        let mut s = Spells::default();
        for l in lengths {
            s.add(l);
        }
        s
    }
}

/// A file's runs summarised, or the file's name and why it could not be
/// read; and what could not be written of it.
type Read = (Result<Vec<RunSummary>, (String, String)>, Vec<String>);

/// Reads and summarises each run of a file (a bag of several robots'
/// logs: each its own robot), its transitions and nodes written under
/// `out` if given.
fn read_file(
    src: &Source,
    opts: &crate::xml::LoadOptions,
    reference: Option<&Session>,
    out: Option<&export::Files>,
) -> Read {
    let f = &src.file;
    let mut runs = Vec::new();
    let mut unwritten = Vec::new();
    let r = crate::input::each_robot_run(f, opts, |t, k, n, s: Session| {
        let path = match t {
            Some(t) => format!("{}:{}", crate::text::path(f), crate::text::visible(t)),
            None => crate::text::path(f),
        };
        let name = if n > 1 { format!("{path}#{k}") } else { path };
        let mut run = summarise(name, &s, reference);
        run.file = f.clone();
        run.run = (n > 1).then_some(k);
        run.topic = t.map(str::to_string);
        if let Some(files) = out {
            let at = partition::Partition::of(f, &src.given, t, &s);
            if let Err(e) = export::transitions(files, &at, &run.name, &s) {
                unwritten.push(e.to_string());
            }
            if let Err(e) = export::nodes(files, &at, &run) {
                unwritten.push(e.to_string());
            }
            run.partition = Some(at);
        }
        runs.push(run);
        Ok(())
    });
    let r = r.map(|()| runs).map_err(|e| {
        // The file's name is said once, before its error.
        let (name, e) = (crate::text::path(f), e.to_string());
        let e = e
            .strip_prefix(&format!("{name}: "))
            .unwrap_or(&e)
            .to_string();
        (name, e)
    });
    (r, unwritten)
}

impl Fleet {
    /// Reads and summarises every run of `files` on every core, each
    /// compared with `reference` if given and its transitions written
    /// under `export` if given, calling `done` after each file.
    pub fn read(
        files: &[Source],
        opts: &crate::xml::LoadOptions,
        reference: Option<&Session>,
        export: Option<&Path>,
        done: &(dyn Fn() + Sync),
    ) -> Fleet {
        let mut fleet = Fleet {
            runs: Vec::new(),
            stats: BTreeMap::new(),
            errors: Vec::new(),
            unwritten: Vec::new(),
            reference: None,
        };
        // A few files a core at a time, each run's nodes counted into the
        // fleet's as its chunk ends: what a fleet holds is its runs'
        // summaries, whatever the number of files.
        let chunk = rayon::current_num_threads().max(1) * 8;
        let out = export.map(export::Files::new);
        for part in files.chunks(chunk) {
            let read: Vec<Read> = part
                .par_iter()
                .map(|src| {
                    let r = read_file(src, opts, reference, out.as_ref());
                    done();
                    r
                })
                .collect();
            for (r, unwritten) in read {
                match r {
                    Ok(runs) => {
                        for run in runs {
                            fleet.add(run);
                        }
                    }
                    Err(e) => fleet.errors.push(e),
                }
                fleet.unwritten.extend(unwritten);
            }
        }
        if let (Some(root), Some(files)) = (export, out) {
            fleet.unwritten.extend(files.close());
            if let Err(e) = export::tables(root, &fleet) {
                fleet.unwritten.push(e.to_string());
            }
            let said = export::commit(root);
            fleet.unwritten.extend(said);
        }
        let diffs: Vec<crate::diff::Diff> = fleet
            .runs
            .iter_mut()
            .filter_map(|r| r.diff.take())
            .collect();
        if let Some(first) = diffs.first() {
            let name = first.a_name.clone();
            fleet.reference = Some(crate::diff::fleet::Fleet::of(name, diffs));
        }
        fleet
    }

    /// Counts a run's nodes into the fleet's, and keeps its summary
    /// without them (the nodes it faulted in, by uid, stay).
    fn add(&mut self, mut r: RunSummary) {
        for n in std::mem::take(&mut r.nodes) {
            let s = self
                .stats
                .entry((r.tree_key.clone(), n.uid))
                .or_insert_with(|| NodeStats {
                    uid: n.uid,
                    tree_key: r.tree_key.clone(),
                    tree: r.tree.clone(),
                    path: n.path.clone(),
                    name: n.name.clone(),
                    leaf: n.leaf,
                    ..Default::default()
                });
            s.ran_in += 1;
            s.failed_in += usize::from(n.failures > 0);
            s.failures += u64::from(n.failures);
            s.faulted_in += usize::from(n.faults > 0);
            s.faults += u64::from(n.faults);
            for &d in &n.running {
                s.running.add(d);
            }
            for rec in n.recoveries {
                match rec {
                    Some(h) => *s.recovered.entry(h).or_default() += 1,
                    None => s.unrecovered += 1,
                }
            }
            if n.faults > 0 {
                r.faulted.push(n.uid);
            }
        }
        r.nodes = Vec::new();
        self.runs.push(r);
    }

    /// Every node that ran in some run, most at fault first (by the runs
    /// its failure was a fault in, then its faults, then its failures),
    /// then by path.
    pub fn nodes(&self) -> Vec<NodeStats> {
        let trees = self.trees().len();
        let mut out: Vec<NodeStats> = self.stats.values().cloned().collect();
        // Nodes of several trees say whose they are.
        if trees > 1 {
            for s in &mut out {
                s.name = format!("{} (in {})", s.name, s.tree);
            }
        }
        out.sort_by(|a, b| {
            (b.faulted_in, b.faults, b.failed_in, b.failures)
                .cmp(&(a.faulted_in, a.faults, a.failed_in, a.failures))
                .then_with(|| a.path.cmp(&b.path))
        });
        out
    }

    /// The failed runs grouped by what went wrong, the largest group first:
    /// (the answer, the runs).
    pub fn causes(&self) -> Vec<(String, Vec<&str>)> {
        let mut by: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for r in &self.runs {
            if let Some(w) = &r.wrong {
                by.entry(w).or_default().push(&r.name);
            }
        }
        let mut out: Vec<(String, Vec<&str>)> =
            by.into_iter().map(|(w, r)| (w.to_string(), r)).collect();
        out.sort_by(|a, b| b.1.len().cmp(&a.1.len()).then_with(|| a.0.cmp(&b.0)));
        out
    }

    /// The trees run, by name, each once.
    pub fn trees(&self) -> Vec<&str> {
        let mut seen: Vec<(&str, &str)> = self
            .runs
            .iter()
            .map(|r| (r.tree_key.as_str(), r.tree.as_str()))
            .collect();
        seen.sort_unstable();
        seen.dedup();
        let mut names: Vec<&str> = seen.into_iter().map(|(_, n)| n).collect();
        names.sort_unstable();
        names
    }

    fn count(&self, outcome: Option<Status>) -> usize {
        self.runs.iter().filter(|r| r.outcome == outcome).count()
    }

    /// How the runs ended, as a clause: "3 SUCCESS, 1 FAILURE".
    fn outcomes(&self) -> String {
        let mut parts = Vec::new();
        for (o, w) in [
            (Some(Status::Success), "SUCCESS"),
            (Some(Status::Failure), "FAILURE"),
            (None, "unfinished"),
        ] {
            let n = self.count(o);
            if n > 0 {
                parts.push(format!("{n} {w}"));
            }
        }
        parts.join(", ")
    }

    pub fn text(&self) -> String {
        let transitions: usize = self.runs.iter().map(|r| r.transitions).sum();
        let ticks: u64 = self.runs.iter().map(|r| u64::from(r.ticks)).sum();
        let trees = self.trees();
        let mut out = format!(
            "{} of {} ({}): {}; {} in {}\n",
            count(self.runs.len(), "run"),
            count(trees.len(), "tree"),
            trees.join(", "),
            self.outcomes(),
            count(transitions, "transition"),
            count(ticks as usize, "tick"),
        );
        for (f, e) in &self.errors {
            out.push_str(&format!("not read: {f}: {e}\n"));
        }
        let nodes = self.nodes();
        failures_text(&nodes, &mut out);
        running_text(&nodes, &mut out);
        let causes = self.causes();
        if !causes.is_empty() {
            out.push_str("\nFailed runs, by what went wrong:\n");
            for (why, runs) in &causes {
                out.push_str(&format!("  {}: {why}\n", count(runs.len(), "run")));
                out.push_str(&format!("    {}\n", names(runs)));
            }
        }
        if let Some(f) = &self.reference {
            out.push('\n');
            out.push_str(&f.text());
        }
        out
    }

    pub fn json(&self) -> Value {
        let nodes = self.nodes();
        json!({
            "schema": "btx.fleet/1",
            "runs": self.runs.len(),
            "outcomes": {
                "SUCCESS": self.count(Some(Status::Success)),
                "FAILURE": self.count(Some(Status::Failure)),
                "unfinished": self.count(None),
            },
            "transitions": self.runs.iter().map(|r| r.transitions).sum::<usize>(),
            "nodes": nodes.iter().map(|n| json!({
                "uid": n.uid,
                "path": n.path,
                "name": n.name,
                "leaf": n.leaf,
                "ran_in": n.ran_in,
                "failed_in": n.failed_in,
                "failures": n.failures,
                "faulted_in": n.faulted_in,
                "faults": n.faults,
                "running_ticks": {
                    "spells": n.running.len(),
                    "median": n.running_quantile(0.5),
                    "p95": n.running_quantile(0.95),
                    "max": n.running.max(),
                },
                "recovered": n.recovered.iter().map(|(by, k)| json!({"by": by, "failures": k})).collect::<Vec<_>>(),
                "unrecovered": n.unrecovered,
            })).collect::<Vec<_>>(),
            "causes": self.causes().iter().map(|(why, runs)| json!({"what_went_wrong": why, "runs": runs})).collect::<Vec<_>>(),
            "each_run": self.runs.iter().map(|r| json!({
                "name": r.name,
                "tree": r.tree,
                "ticks": r.ticks,
                "transitions": r.transitions,
                "outcome": r.outcome.map(|o| o.as_str()),
                "ending": r.ending,
                "what_went_wrong": r.wrong,
                "gaps": r.gaps,
            })).collect::<Vec<_>>(),
            "errors": self.errors.iter().map(|(f, e)| json!({"file": f, "error": e})).collect::<Vec<_>>(),
            "reference": self.reference.as_ref().map(|f| f.json()),
        })
    }
}

/// Nodes listed with their RUNNING times, at most.
const LEAVES_SHOWN: usize = 15;

/// "; 29 recovered by RetryUntilSuccessful #7, 2 not recovered".
fn recoveries(n: &NodeStats) -> String {
    if !n.leaf || (n.recovered.is_empty() && n.unrecovered == 0) {
        return String::new();
    }
    let mut parts: Vec<(u64, String)> = n
        .recovered
        .iter()
        .map(|(by, k)| (*k, format!("{k} recovered by {by}")))
        .collect();
    parts.sort_by(|a, b| b.0.cmp(&a.0).then_with(|| a.1.cmp(&b.1)));
    let mut parts: Vec<String> = parts.into_iter().map(|p| p.1).collect();
    if n.unrecovered > 0 {
        parts.push(format!("{} not recovered", n.unrecovered));
    }
    format!("; {}", parts.join(", "))
}

/// Up to three names, then how many more.
fn names(runs: &[&str]) -> String {
    let shown: Vec<&str> = runs.iter().take(3).copied().collect();
    match runs.len() {
        n if n > 3 => format!("{}, and {} more", shown.join(", "), n - 3),
        _ => shown.join(", "),
    }
}

/// How many spells lasted how long, as eight bars from none to longest.
pub fn sparkline(spells: &Spells) -> String {
    const BARS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    let Some(max) = spells.max() else {
        return String::new();
    };
    let buckets = 8usize;
    let mut counts = vec![0u64; buckets];
    for (&d, &k) in &spells.by_length {
        let b = if max == 0 {
            0
        } else {
            (d as usize * (buckets - 1)) / max as usize
        };
        counts[b] += k;
    }
    let top = counts.iter().copied().max().unwrap_or(1).max(1);
    counts
        .iter()
        .map(|&c| {
            if c == 0 {
                ' '
            } else {
                BARS[(c * (BARS.len() as u64 - 1)).div_ceil(top) as usize]
            }
        })
        .collect()
}

/// The actions and conditions that failed, in the most runs first, with
/// what recovered them; the checks that answered no as designed, apart.
fn failures_text(nodes: &[NodeStats], out: &mut String) {
    // The actions and conditions: a control node fails as its
    // children do, and says nothing more (the JSON lists it).
    let failed: Vec<&NodeStats> = nodes.iter().filter(|n| n.faults > 0).collect();
    let (leaves, controls): (Vec<&NodeStats>, Vec<&NodeStats>) =
        failed.iter().partition(|n| n.leaf);
    if !leaves.is_empty() {
        out.push_str("\nActions and conditions that failed, in the most runs first:\n");
        for n in &leaves {
            let runs = match n.ran_in {
                1 => "the one run it ran in".to_string(),
                k => format!("{} of the {k} runs it ran in", n.faulted_in),
            };
            out.push_str(&format!(
                "  {} failed in {runs} ({}){}.\n",
                n.name,
                count(n.faults as usize, "failure"),
                recoveries(n)
            ));
        }
    }
    // Checks that answered no as designed: said apart, in one line.
    let branches: Vec<String> = nodes
        .iter()
        .filter(|n| n.leaf && n.failures > n.faults)
        .map(|n| {
            format!(
                "{} ({} in {})",
                n.name,
                count((n.failures - n.faults) as usize, "time"),
                count(n.failed_in, "run")
            )
        })
        .collect();
    if !branches.is_empty() {
        out.push_str(&format!(
            "  Branches taken, not faults (checks that answered no as the tree is designed to): {}.\n",
            branches.join(", ")
        ));
    }
    if !controls.is_empty() {
        out.push_str(&format!(
            "  ({} failed as their children did; --format json lists every node.)\n",
            count(controls.len(), "control node")
        ));
    }
}

/// How long the actions kept RUNNING, the longest first.
fn running_text(nodes: &[NodeStats], out: &mut String) {
    // The actions' times: a control node RUNNING is its children's.
    let mut slow: Vec<&NodeStats> = nodes
        .iter()
        .filter(|n| n.leaf && n.running.max().is_some_and(|m| m > 0))
        .collect();
    slow.sort_by(|a, b| {
        (b.running_quantile(0.95), b.running_quantile(0.5))
            .cmp(&(a.running_quantile(0.95), a.running_quantile(0.5)))
            .then_with(|| a.path.cmp(&b.path))
    });
    if !slow.is_empty() {
        let shown = slow.len().min(LEAVES_SHOWN);
        out.push_str(&format!(
            "\nTicks actions kept RUNNING (median, 95th percentile, longest, and the spells by length; {}):\n",
            if shown < slow.len() {
                format!("{shown} longest of {}", slow.len())
            } else {
                count(shown, "action")
            }
        ));
        let width = slow[..shown]
            .iter()
            .map(|n| n.name.chars().count())
            .max()
            .unwrap_or(0);
        for n in &slow[..shown] {
            out.push_str(&format!(
                "  {:<width$}  {:>5} {:>5} {:>5}  {}\n",
                n.name,
                n.running_quantile(0.5).unwrap_or(0),
                n.running_quantile(0.95).unwrap_or(0),
                n.running.max().unwrap_or(0),
                sparkline(&n.running),
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_nearest_rank() {
        let n = NodeStats {
            running: (1..=20).collect(),
            ..Default::default()
        };
        assert_eq!(n.running_quantile(0.5), Some(10));
        assert_eq!(n.running_quantile(0.95), Some(19));
        assert_eq!(n.running_quantile(1.0), Some(20));
        assert_eq!(NodeStats::default().running_quantile(0.5), None);
    }

    #[test]
    fn a_sparkline_has_a_bar_for_each_length_that_occurred() {
        assert_eq!(sparkline(&Spells::default()), "");
        assert_eq!(sparkline(&[0, 0].into_iter().collect()), "█       ");
        // Lengths 0..=7, one each, then seven more of the longest.
        let mut s: Vec<u32> = (0..=7).collect();
        s.extend([7; 7]);
        let line: Vec<char> = sparkline(&s.into_iter().collect()).chars().collect();
        assert_eq!(line.len(), 8);
        assert_eq!(line[7], '█');
        assert!(line[..7].iter().all(|&c| c == '▂'), "{line:?}");
    }
}
