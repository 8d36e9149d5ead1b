//! A shortest edit script between two action sequences. The `similar`
//! crate's Myers diff is exact: it finds a longest common subsequence, so
//! the edit distance it implies (insertions plus deletions) is the one
//! Wu et al.'s O(NP) algorithm, which Han et al. cite, computes.

use similar::{Algorithm, DiffOp};

/// What happened to one position of the two sequences.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Op {
    /// In both, unchanged (part of the longest common subsequence).
    Same,
    /// Only in the second sequence.
    Inserted,
    /// Only in the first sequence.
    Deleted,
    /// The first sequence's item replaced by the second's: one deletion and
    /// one insertion at the same place.
    Changed,
}

/// One line of an edit script: indices into the first (`a`) and second (`b`)
/// sequences.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edit {
    pub op: Op,
    pub a: Option<usize>,
    pub b: Option<usize>,
}

/// How long an alignment may take before the best one found so far is
/// taken: Myers' algorithm costs time in proportion to length × distance,
/// so two long runs with little in common would take minutes.
pub const ALIGN_TIME_MAX: std::time::Duration = std::time::Duration::from_secs(2);

/// The edit script turning `a` into `b`, in order.
pub fn edits<T: Eq + std::hash::Hash + Ord>(a: &[T], b: &[T]) -> Vec<Edit> {
    edits_bounded(a, b).0
}

/// The edit script, and whether it is a shortest one (`false`: the time
/// bound was reached and the script is the best found by then, longer
/// than the shortest perhaps, never wrong).
pub fn edits_bounded<T: Eq + std::hash::Hash + Ord>(a: &[T], b: &[T]) -> (Vec<Edit>, bool) {
    // Sequences with nothing in common: every item changes, exactly, at
    // no cost (the case where Myers' algorithm is slowest).
    let common = {
        let (small, large) = if a.len() <= b.len() { (a, b) } else { (b, a) };
        let set: std::collections::HashSet<&T> = small.iter().collect();
        large.iter().any(|x| set.contains(x))
    };
    if !common {
        let ops = if a.is_empty() && b.is_empty() {
            Vec::new()
        } else {
            vec![DiffOp::Replace {
                old_index: 0,
                old_len: a.len(),
                new_index: 0,
                new_len: b.len(),
            }]
        };
        return (script(&ops), true);
    }
    let started = std::time::Instant::now();
    let deadline = started + ALIGN_TIME_MAX;
    let ops = similar::capture_diff_deadline(
        Algorithm::Myers,
        a,
        0..a.len(),
        b,
        0..b.len(),
        Some(deadline),
    );
    let exact = std::time::Instant::now() < deadline;
    (script(&ops), exact)
}

fn script(ops: &[DiffOp]) -> Vec<Edit> {
    let mut out = Vec::new();
    for &op in ops {
        match op {
            DiffOp::Equal {
                old_index,
                new_index,
                len,
            } => out.extend((0..len).map(|k| Edit {
                op: Op::Same,
                a: Some(old_index + k),
                b: Some(new_index + k),
            })),
            DiffOp::Delete {
                old_index, old_len, ..
            } => out.extend((0..old_len).map(|k| Edit {
                op: Op::Deleted,
                a: Some(old_index + k),
                b: None,
            })),
            DiffOp::Insert {
                new_index, new_len, ..
            } => out.extend((0..new_len).map(|k| Edit {
                op: Op::Inserted,
                a: None,
                b: Some(new_index + k),
            })),
            DiffOp::Replace {
                old_index,
                old_len,
                new_index,
                new_len,
            } => {
                let paired = old_len.min(new_len);
                out.extend((0..paired).map(|k| Edit {
                    op: Op::Changed,
                    a: Some(old_index + k),
                    b: Some(new_index + k),
                }));
                out.extend((paired..old_len).map(|k| Edit {
                    op: Op::Deleted,
                    a: Some(old_index + k),
                    b: None,
                }));
                out.extend((paired..new_len).map(|k| Edit {
                    op: Op::Inserted,
                    a: None,
                    b: Some(new_index + k),
                }));
            }
        }
    }
    out
}

/// The length of the longest common subsequence an edit script keeps.
pub fn lcs(edits: &[Edit]) -> usize {
    edits.iter().filter(|e| e.op == Op::Same).count()
}

/// The edit distance of a script: insertions plus deletions, so a changed
/// item counts twice (the measure Myers and Wu et al. minimise).
pub fn distance(edits: &[Edit]) -> usize {
    edits
        .iter()
        .map(|e| match e.op {
            Op::Same => 0,
            Op::Inserted | Op::Deleted => 1,
            Op::Changed => 2,
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn script(a: &str, b: &str) -> String {
        let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
        edits(&a, &b)
            .iter()
            .map(|e| match e.op {
                Op::Same => format!(" {}", a[e.a.unwrap()]),
                Op::Inserted => format!("+{}", b[e.b.unwrap()]),
                Op::Deleted => format!("-{}", a[e.a.unwrap()]),
                Op::Changed => format!("~{}{}", a[e.a.unwrap()], b[e.b.unwrap()]),
            })
            .collect::<Vec<_>>()
            .join(" ")
    }

    #[test]
    fn scripts_name_what_changed() {
        assert_eq!(script("RRUUp", "RRRUULp"), " R  R +R  U  U +L  p");
        assert_eq!(script("abc", "axc"), " a ~bx  c");
        assert_eq!(script("ab", ""), "-a -b");
        assert_eq!(script("", ""), "");
    }

    #[test]
    fn a_change_counts_as_a_deletion_and_an_insertion() {
        let e = edits(&['a', 'b', 'c'], &['a', 'x', 'c']);
        assert_eq!((distance(&e), lcs(&e)), (2, 2));
        let e = edits(&['a', 'b'], &['b', 'a']);
        assert_eq!((distance(&e), lcs(&e)), (2, 1));
    }
}
