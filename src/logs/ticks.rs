//! Tick numbers for logs that have none (`.btlog`, `.fbl`, `.db3`).
//!
//! The rule: replay the log through the executor, with each leaf doing what
//! the log says it did next. A tick ends where the executor's tick ends, so
//! a new tick starts exactly when the root, or a branch that was left
//! RUNNING, is ticked again. A leaf that stays RUNNING through ticks in which
//! nothing changes leaves no trace, so those empty ticks are counted from the
//! time between ticks: the gap from one tick's first record to the next,
//! over the period (the 10th percentile of those gaps, as a late tick only
//! lengthens a gap), counted as k ticks from 0.9·k periods on. If the replay cannot follow the
//! log (a custom control node, a lost record), ticks fall back to timing
//! alone: a new tick after a gap of 1 ms or more, as Groot 1 does.

use super::btlog::Record;
use crate::model::{Tree, Uid};
use crate::run::{Executor, LeafCall, LeafOutcome, Leaves, RunOptions, Status};
use crate::session::EMPTY_TICKS_MAX;

struct Replay<'a> {
    recs: &'a [Record],
    cursor: usize,
    diverged: bool,
}

impl Leaves for Replay<'_> {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        let now = if call.resumed {
            Status::Running
        } else {
            Status::Idle
        };
        let status = match self.recs.get(self.cursor) {
            // The log ends inside this tick (it is still being written, or
            // the logger lost its queue): what follows is unknown, not wrong.
            None => Status::Running,
            Some(r) if r.uid == call.uid && r.status != now => r.status,
            _ if now == Status::Running => Status::Running,
            _ => {
                self.diverged = true;
                Status::Failure
            }
        };
        LeafOutcome {
            status,
            decision: None,
        }
    }

    fn observe(&mut self, uid: Uid, _prev: Status, status: Status) {
        match self.recs.get(self.cursor) {
            Some(r) if r.uid == uid && r.status == status => self.cursor += 1,
            None => {}
            _ => self.diverged = true,
        }
    }
}

/// Structural tick of each record, or the index of the first record the
/// replay could not follow.
fn by_structure(tree: &Tree, recs: &[Record]) -> Result<Vec<u32>, usize> {
    let mut ex = Executor::new(
        tree,
        Replay {
            recs,
            cursor: 0,
            diverged: false,
        },
        RunOptions::default(),
    );
    let mut ticks = vec![0u32; recs.len()];
    let mut stuck = 0;
    while ex.leaves.cursor < recs.len() {
        let before = ex.leaves.cursor;
        let r = ex.tick_once();
        ex.take_events();
        let after = ex.leaves.cursor;
        if r.is_err() || ex.leaves.diverged {
            return Err(after);
        }
        for t in &mut ticks[before..after] {
            *t = ex.ticks();
        }
        if after == before {
            stuck += 1;
            if stuck > 2 {
                return Err(after);
            }
        } else {
            stuck = 0;
        }
    }
    // Compact: ticks without records are put back from timing below.
    let mut out = Vec::with_capacity(ticks.len());
    let (mut last, mut n) = (0, 0);
    for t in ticks {
        if t != last {
            last = t;
            n += 1;
        }
        out.push(n);
    }
    Ok(out)
}

/// Timing alone: a new tick after a gap of 1 ms or more.
fn by_timing(recs: &[Record]) -> Vec<u32> {
    let mut n = 0;
    let mut prev: Option<i64> = None;
    recs.iter()
        .map(|r| {
            if prev.is_none_or(|p| r.time_us.saturating_sub(p) >= 1000) {
                n += 1;
            }
            prev = Some(r.time_us);
            n
        })
        .collect()
}

/// Empty ticks one gap may stand for; all gaps together stand for at most
/// `EMPTY_TICKS_MAX`.
const EMPTY_PER_GAP: f64 = 1e6;

/// Puts back the ticks in which nothing changed, from the time between
/// ticks; and the record from which gaps counted for one tick each, if
/// the empty ticks ran past `EMPTY_TICKS_MAX`.
fn with_empty_ticks(recs: &[Record], ticks: &[u32]) -> (Vec<u32>, Option<usize>) {
    let mut firsts: Vec<i64> = Vec::new();
    let mut first_rec: Vec<usize> = Vec::new();
    for (i, r) in recs.iter().enumerate() {
        if i == 0 || ticks[i] != ticks[i - 1] {
            firsts.push(r.time_us);
            first_rec.push(i);
        }
    }
    let mut gaps: Vec<i64> = firsts
        .windows(2)
        .map(|w| w[1].saturating_sub(w[0]))
        .filter(|g| *g > 0)
        .collect();
    gaps.sort_unstable();
    // A late tick makes a long gap, never a short one: measure the period
    // by the short gaps, and count a gap as k ticks only once it is almost
    // k periods long.
    let Some(&period) = gaps.get(gaps.len() / 10) else {
        return (ticks.to_vec(), None);
    };
    let mut numbers = vec![1u32];
    let mut empty = 0u32;
    let mut capped = None;
    for (k, w) in firsts.windows(2).enumerate() {
        let steps = ((w[1].saturating_sub(w[0])) as f64 / period.max(1) as f64 + 0.1)
            .floor()
            .clamp(1.0, EMPTY_PER_GAP) as u32;
        let extra = (steps - 1).min(EMPTY_TICKS_MAX - empty);
        if extra < steps - 1 && capped.is_none() {
            capped = Some(first_rec[k + 1]);
        }
        empty += extra;
        let last = *numbers.last().expect("seeded");
        numbers.push(last + 1 + extra);
    }
    (
        ticks.iter().map(|&t| numbers[t as usize - 1]).collect(),
        capped,
    )
}

/// A log's tick numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    /// Per record, from 1.
    pub numbers: Vec<u32>,
    /// The record where the replay lost the structure and timing took over.
    pub fell_back: Option<usize>,
    /// The record from which empty ticks were no longer counted (past
    /// `EMPTY_TICKS_MAX`).
    pub capped: Option<usize>,
}

pub fn reconstruct(tree: &Tree, recs: &[Record]) -> Ticks {
    let (structural, fell_back) = match by_structure(tree, recs) {
        Ok(t) => (t, None),
        Err(at) => (by_timing(recs), Some(at)),
    };
    let (numbers, capped) = with_empty_ticks(recs, &structural);
    Ticks {
        numbers,
        fell_back,
        capped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Status;

    fn rec(time_us: i64) -> Record {
        Record {
            time_us,
            uid: 1,
            status: Status::Running,
            offset: 0,
        }
    }

    #[test]
    fn a_log_cut_inside_a_tick_keeps_its_structural_ticks() {
        let bytes = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/logs/kitting_lookat_fails_once.btlog"
        ))
        .unwrap();
        let path = std::path::Path::new("log.btlog");
        let raw = crate::logs::btlog::parse(path, &bytes).unwrap();
        let tree = crate::xml::load_str(
            path,
            &raw.xml,
            &crate::xml::LoadOptions {
                embedded: true,
                ..Default::default()
            },
        )
        .unwrap()
        .tree;
        let full = reconstruct(&tree, &raw.records);
        assert_eq!((full.fell_back, full.capped), (None, None));
        for cut in [1, 5, 40, 100, raw.records.len() - 1] {
            let part = reconstruct(&tree, &raw.records[..cut]);
            assert_eq!(part.fell_back, None, "cut at {cut}");
            assert_eq!(part.numbers[..], full.numbers[..cut], "cut at {cut}");
        }
    }

    #[test]
    fn a_corrupt_timestamp_cannot_overflow_the_tick_numbers() {
        let recs: Vec<Record> = [0, 10_000, 20_000, i64::MAX / 4, i64::MAX / 2, 0]
            .into_iter()
            .map(rec)
            .collect();
        let (ticks, capped) = with_empty_ticks(&recs, &by_timing(&recs));
        assert_eq!(&ticks[..3], [1, 2, 3]);
        assert_eq!(ticks[3], 3 + 1_000_000);
        assert!(ticks.iter().all(|&t| t <= u32::MAX / 2));
        assert_eq!(capped, None);
    }

    #[test]
    fn empty_ticks_stop_being_counted_past_the_limit() {
        // Ticks every 10 ms, then gaps of a million periods each: the first
        // ten fill the budget, later ones count for one tick.
        let mut times: Vec<i64> = (0..20).map(|i| i * 10_000).collect();
        let mut t = *times.last().unwrap();
        for _ in 0..15 {
            t += 10_000 * 1_000_000;
            times.push(t);
        }
        let recs: Vec<Record> = times.into_iter().map(rec).collect();
        let (ticks, capped) = with_empty_ticks(&recs, &by_timing(&recs));
        assert_eq!(capped, Some(30));
        let last = *ticks.last().unwrap();
        assert_eq!(last, 35 + EMPTY_TICKS_MAX);
        assert_eq!(ticks[30] - ticks[29], 1 + 10);
        assert_eq!(ticks[31] - ticks[30], 1);
    }
}
