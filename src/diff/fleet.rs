//! One reference against several runs (a fleet, or many seeds): per subgoal,
//! how far each run diverges from the reference.

use super::{Diff, Op, Side};
use serde_json::{json, Value};

pub struct Fleet {
    pub reference: String,
    pub diffs: Vec<Diff>,
    /// Subgoal names in report order: the reference's, then any only the
    /// runs have, in the order first met.
    pub subgoals: Vec<String>,
}

impl Fleet {
    pub fn new(reference: &Side, runs: &[Side]) -> Fleet {
        let diffs: Vec<Diff> = runs.iter().map(|r| Diff::new(reference, r)).collect();
        Fleet::of(reference.name.clone(), diffs)
    }

    /// The table of runs already compared with `reference`.
    pub fn of(reference: String, diffs: Vec<Diff>) -> Fleet {
        let mut subgoals: Vec<String> = Vec::new();
        for d in &diffs {
            for s in &d.sections {
                if !subgoals.contains(&s.name) {
                    subgoals.push(s.name.clone());
                }
            }
        }
        // Subgoals in which no side executes anything add only noise.
        subgoals.retain(|name| {
            diffs.iter().any(|d| {
                d.sections
                    .iter()
                    .any(|s| &s.name == name && !(s.a.is_empty() && s.b.is_empty()))
            })
        });
        Fleet {
            reference,
            diffs,
            subgoals,
        }
    }

    /// A run's cell for a subgoal: "=" (no divergence), else the edit
    /// distance with its insertions, deletions and changes.
    fn cell(d: &Diff, subgoal: &str) -> String {
        let secs: Vec<_> = d.sections.iter().filter(|s| s.name == subgoal).collect();
        if secs.is_empty() {
            return "-".into();
        }
        let count = |op| secs.iter().map(|s| s.count(op)).sum::<usize>();
        let dist: usize = secs.iter().map(|s| s.distance()).sum();
        if dist == 0 {
            return "=".into();
        }
        let mut parts = Vec::new();
        for (op, sign) in [(Op::Inserted, '+'), (Op::Deleted, '-'), (Op::Changed, '~')] {
            let n = count(op);
            if n > 0 {
                parts.push(format!("{sign}{n}"));
            }
        }
        format!("{dist} ({})", parts.join(" "))
    }

    pub fn text(&self) -> String {
        let names = self.short_names();
        let mut out = format!(
            "Reference: {}\nEach cell: edit distance from the reference (+inserted -deleted ~changed), = when the same.\n\n",
            self.reference
        );
        out.push_str(&self.table(&names));
        out.push('\n');
        out.push_str(&self.summary(&names));
        out
    }

    /// A row a subgoal and one for the whole run, a column a run, aligned.
    fn table(&self, names: &[String]) -> String {
        let label_w = self
            .subgoals
            .iter()
            .map(|s| s.chars().count())
            .chain(["in all".len(), "diverging runs".len()])
            .max()
            .unwrap_or(0);
        let mut rows: Vec<(String, Vec<String>)> = Vec::new();
        for sg in &self.subgoals {
            rows.push((
                sg.clone(),
                self.diffs.iter().map(|d| Self::cell(d, sg)).collect(),
            ));
        }
        rows.push((
            "in all".into(),
            self.diffs
                .iter()
                .map(|d| {
                    if d.is_empty() {
                        "=".into()
                    } else {
                        format!("{} (LCS {})", d.distance(), d.lcs())
                    }
                })
                .collect(),
        ));
        let widths: Vec<usize> = (0..names.len())
            .map(|i| {
                rows.iter()
                    .map(|r| r.1[i].chars().count())
                    .chain([names[i].chars().count()])
                    .max()
                    .unwrap_or(1)
            })
            .collect();
        let mut out = String::new();
        let header = std::iter::once(("subgoal".to_string(), names.to_vec()));
        for (label, cells) in header.chain(rows) {
            let mut line = format!("{label:<label_w$}");
            for (c, w) in cells.iter().zip(&widths) {
                line.push_str(&format!("  {c:<w$}"));
            }
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }

    /// How many runs diverge in each subgoal, how many do what the
    /// reference does, and where each run first diverges.
    fn summary(&self, names: &[String]) -> String {
        let mut out = String::new();
        for sg in &self.subgoals {
            let n = self
                .diffs
                .iter()
                .filter(|d| d.sections.iter().any(|s| &s.name == sg && s.diverges()))
                .count();
            if n > 0 {
                out.push_str(&format!("{sg}: {n} of {} runs diverge\n", self.diffs.len()));
            }
        }
        let same = self.diffs.iter().filter(|d| d.is_empty()).count();
        out.push_str(&format!(
            "runs that do what the reference does: {same} of {}\n",
            self.diffs.len()
        ));
        for (d, name) in self.diffs.iter().zip(names) {
            if let Some(&(s, i)) = d.divergences().first() {
                out.push_str(&format!(
                    "{name}: first divergence: {}\n",
                    d.describe_as(s, i, "the reference", "the run")
                ));
            }
        }
        out
    }

    /// Column names: the runs' file names, or their paths where two share
    /// a file name.
    fn short_names(&self) -> Vec<String> {
        let base = |n: &str| {
            std::path::Path::new(n)
                .file_name()
                .map_or(n.to_string(), |f| f.to_string_lossy().into_owned())
        };
        let bases: Vec<String> = self.diffs.iter().map(|d| base(&d.b_name)).collect();
        self.diffs
            .iter()
            .zip(&bases)
            .map(|(d, b)| {
                if bases.iter().filter(|x| *x == b).count() > 1 {
                    d.b_name.clone()
                } else {
                    b.clone()
                }
            })
            .collect()
    }

    pub fn json(&self) -> Value {
        json!({
            "reference": self.reference,
            "subgoals": self.subgoals,
            "runs": self.diffs.iter().map(|d| {
                let first = d.divergences().first().map(|&(s, i)| d.describe(s, i));
                json!({
                    "name": d.b_name,
                    "identical": d.is_empty(),
                    "distance": d.distance(),
                    "lcs": d.lcs(),
                    "first_divergence": first,
                    "sections": d.sections.iter().map(|s| json!({
                        "subgoal": s.name,
                        "distance": s.distance(),
                        "lcs": s.lcs(),
                        "inserted": s.count(Op::Inserted),
                        "deleted": s.count(Op::Deleted),
                        "changed": s.count(Op::Changed),
                    })).collect::<Vec<_>>(),
                })
            }).collect::<Vec<_>>(),
        })
    }
}
