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

/// The work an exact alignment of two long sequences may take, in cells of
/// the edit graph: Myers' algorithm costs (N+M)·D, so two long runs that
/// differ in a few places are aligned exactly whatever their length, and
/// only runs far apart fall back to aligning by units.
pub const WORK_MAX: usize = 60_000_000;

/// A shortest edit script, when one is cheap to find: the sequences are
/// short, or their edit distance is at most `WORK_MAX / (N+M)`. `None`
/// otherwise, found out within that much work.
pub fn edits_near<T: Eq + std::hash::Hash + Ord>(a: &[T], b: &[T]) -> Option<Vec<Edit>> {
    let n = a.len() + b.len();
    if n > EXACT_MAX {
        // The common ends cost nothing: the bound is on what lies between.
        let (head, tail) = common_ends(a, b);
        let (ma, mb) = (&a[head..a.len() - tail], &b[head..b.len() - tail]);
        distance_within(ma, mb, WORK_MAX / (ma.len() + mb.len()).max(1))?;
    }
    Some(script(&similar::capture_diff_slices(
        Algorithm::Myers,
        a,
        b,
    )))
}

/// The edit distance of `a` and `b` (insertions plus deletions) if it is at
/// most `max_d`: Myers' greedy forward pass, in O((N+M)·max_d) time and
/// O(max_d) memory, with no script kept.
pub fn distance_within<T: Eq>(a: &[T], b: &[T], max_d: usize) -> Option<usize> {
    let (n, m) = (a.len() as isize, b.len() as isize);
    let max_d = max_d.min(a.len() + b.len()) as isize;
    let off = max_d + 1;
    // The furthest x reached on each diagonal k = x - y; -1: not reached.
    let mut v = vec![-1isize; 2 * max_d as usize + 3];
    for d in 0..=max_d {
        for k in (-d..=d).step_by(2) {
            let i = (off + k) as usize;
            let x = if d == 0 {
                0
            } else {
                // Down from diagonal k+1 (an insertion) or right from k-1
                // (a deletion), whichever stays in the grid and goes further.
                let down = Some(v[i + 1]).filter(|&x| x >= 0 && x - k <= m);
                let right = Some(v[i - 1]).filter(|&x| x >= 0 && x < n).map(|x| x + 1);
                match down.max(right) {
                    Some(x) => x,
                    None => continue,
                }
            };
            let (mut x, mut y) = (x, x - k);
            while x < n && y < m && a[x as usize] == b[y as usize] {
                x += 1;
                y += 1;
            }
            v[i] = x;
            if x == n && y == m {
                return Some(d as usize);
            }
        }
    }
    None
}

/// Sequences up to this long (both together) are aligned exactly, with no
/// time bound: Myers' worst case is then some 10^7 steps.
pub const EXACT_MAX: usize = 4_000;

/// The edit script of two long sequences cut into units (the runs of the
/// root, then ticks): the units are aligned first, by their contents, and
/// the items within each pair of units that differ, the same way down to
/// sequences short enough to align exactly. Deterministic and close to
/// linear when the runs repeat a task, where Myers' algorithm on the whole
/// is quadratic and a time bound would change the answer with the load.
/// `levels[k](i)` is item i's unit at level k (non-decreasing in i).
pub fn edits_by_units<T: Eq + std::hash::Hash + Ord>(
    a: &[T],
    b: &[T],
    levels: &[&dyn Fn(bool, usize) -> u64],
) -> Vec<Edit> {
    edits_by_units_within(a, b, levels, EXACT_MAX)
}

/// The same, aligning exactly up to `max` items (the tests make it small).
pub fn edits_by_units_within<T: Eq + std::hash::Hash + Ord>(
    a: &[T],
    b: &[T],
    levels: &[&dyn Fn(bool, usize) -> u64],
    max: usize,
) -> Vec<Edit> {
    // The common start and end are the same, item by item, whatever the
    // units: so the first divergence is a plain LCS's, and a unit whose
    // first items the other run also begins with is not cut there.
    let (head, tail) = common_ends(a, b);
    let mut out: Vec<Edit> = (0..head).map(|i| same(i, i)).collect();
    let (ea, eb) = (a.len() - tail, b.len() - tail);
    units(
        &a[head..ea],
        &b[head..eb],
        (head, head),
        levels,
        max,
        &mut out,
    );
    out.extend((0..tail).map(|k| same(ea + k, eb + k)));
    out
}

fn units<T: Eq + std::hash::Hash + Ord>(
    a: &[T],
    b: &[T],
    (a0, b0): (usize, usize),
    levels: &[&dyn Fn(bool, usize) -> u64],
    max: usize,
    out: &mut Vec<Edit>,
) {
    let shift = |e: Edit| Edit {
        op: e.op,
        a: e.a.map(|i| i + a0),
        b: e.b.map(|j| j + b0),
    };
    if a.len() + b.len() <= max || levels.is_empty() {
        let edits = if a.len() + b.len() <= max {
            script(&similar::capture_diff_slices(Algorithm::Myers, a, b))
        } else {
            // Past every level: what is left is paired in place.
            in_place(a, b)
        };
        out.extend(edits.into_iter().map(shift));
        return;
    }
    let (level, rest) = (levels[0], &levels[1..]);
    let cut = |first: bool, xs: &[T], x0: usize| -> Vec<std::ops::Range<usize>> {
        let mut spans = Vec::new();
        let mut start = 0;
        for i in 1..=xs.len() {
            if i == xs.len() || level(first, x0 + i) != level(first, x0 + start) {
                spans.push(start..i);
                start = i;
            }
        }
        spans
    };
    let (ua, ub) = (cut(true, a, a0), cut(false, b, b0));
    let digest = |xs: &[T], r: &std::ops::Range<usize>| {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        xs[r.clone()].hash(&mut h);
        h.finish()
    };
    let ka: Vec<u64> = ua.iter().map(|r| digest(a, r)).collect();
    let kb: Vec<u64> = ub.iter().map(|r| digest(b, r)).collect();
    for e in align_units(&ka, &kb, max) {
        match (e.op, e.a, e.b) {
            // Units whose digests agree are compared whole, so that a
            // collision cannot pair two different ones.
            (Op::Same, Some(i), Some(j)) if a[ua[i].clone()] == b[ub[j].clone()] => {
                out.extend(ua[i].clone().zip(ub[j].clone()).map(|(x, y)| Edit {
                    op: Op::Same,
                    a: Some(x + a0),
                    b: Some(y + b0),
                }))
            }
            (Op::Same | Op::Changed, Some(i), Some(j)) => {
                let (ra, rb) = (ua[i].clone(), ub[j].clone());
                units(
                    &a[ra.clone()],
                    &b[rb.clone()],
                    (a0 + ra.start, b0 + rb.start),
                    rest,
                    max,
                    out,
                )
            }
            (_, Some(i), None) => out.extend(ua[i].clone().map(|x| Edit {
                op: Op::Deleted,
                a: Some(x + a0),
                b: None,
            })),
            (_, None, Some(j)) => out.extend(ub[j].clone().map(|y| Edit {
                op: Op::Inserted,
                a: None,
                b: Some(y + b0),
            })),
            _ => {}
        }
    }
}

/// How many items two sequences share at their start, and then at their end.
fn common_ends<T: Eq>(a: &[T], b: &[T]) -> (usize, usize) {
    let head = a.iter().zip(b).take_while(|(x, y)| x == y).count();
    let tail = a[head..]
        .iter()
        .rev()
        .zip(b[head..].iter().rev())
        .take_while(|(x, y)| x == y)
        .count();
    (head, tail)
}

/// Item `i` of the first sequence is item `j` of the second.
fn same(i: usize, j: usize) -> Edit {
    Edit {
        op: Op::Same,
        a: Some(i),
        b: Some(j),
    }
}

/// The units' alignment by their digests: exact when there are few; past
/// that, the common start and end kept and the middle paired in place (a
/// pair that is the same inside comes out the same, one item at a time).
fn align_units(ka: &[u64], kb: &[u64], max: usize) -> Vec<Edit> {
    if ka.len() + kb.len() <= max {
        return script(&similar::capture_diff_slices(Algorithm::Myers, ka, kb));
    }
    let (head, tail) = common_ends(ka, kb);
    let mut out: Vec<Edit> = (0..head).map(|i| same(i, i)).collect();
    let mid = |k: &[u64]| k[head..k.len() - tail].to_vec();
    out.extend(in_place(&mid(ka), &mid(kb)).into_iter().map(|e| Edit {
        op: e.op,
        a: e.a.map(|i| i + head),
        b: e.b.map(|j| j + head),
    }));
    out.extend((0..tail).map(|k| same(ka.len() - tail + k, kb.len() - tail + k)));
    out
}

/// Two stretches paired item by item (the same, or changed), the longer
/// one's rest inserted or deleted.
fn in_place<T: Eq>(a: &[T], b: &[T]) -> Vec<Edit> {
    let paired = a.len().min(b.len());
    let mut out: Vec<Edit> = (0..paired)
        .map(|k| Edit {
            op: if a[k] == b[k] { Op::Same } else { Op::Changed },
            a: Some(k),
            b: Some(k),
        })
        .collect();
    out.extend((paired..a.len()).map(|k| Edit {
        op: Op::Deleted,
        a: Some(k),
        b: None,
    }));
    out.extend((paired..b.len()).map(|k| Edit {
        op: Op::Inserted,
        a: None,
        b: Some(k),
    }));
    out
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
    fn the_bounded_distance_is_exact_within_its_bound() {
        let d = |a: &str, b: &str, max| {
            let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
            distance_within(&a, &b, max)
        };
        assert_eq!(d("abc", "axc", 9), Some(2));
        assert_eq!(d("abc", "axc", 1), None);
        assert_eq!(d("", "", 0), Some(0));
        assert_eq!(d("ab", "", 5), Some(2));
        assert_eq!(d("", "xyz", 3), Some(3));
        assert_eq!(d("RRUUp", "RRRUULp", 9), Some(2));
        // Long and near: a loop that goes wrong once.
        let a: Vec<u32> = (0..200_000).map(|i| i % 7).collect();
        let mut b = a.clone();
        b.splice(100_000..100_001, [9, 9, 9]);
        assert_eq!(distance_within(&a, &b, 10), Some(4));
        let e = edits_near(&a, &b).expect("near");
        assert_eq!(distance(&e), 4);
    }

    #[test]
    fn a_change_counts_as_a_deletion_and_an_insertion() {
        let e = edits(&['a', 'b', 'c'], &['a', 'x', 'c']);
        assert_eq!((distance(&e), lcs(&e)), (2, 2));
        let e = edits(&['a', 'b'], &['b', 'a']);
        assert_eq!((distance(&e), lcs(&e)), (2, 1));
    }
}
