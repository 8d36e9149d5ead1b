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

use super::btlog::{Packed, Record};
use crate::model::{Tree, Uid};
use crate::run::{Executor, LeafCall, LeafOutcome, Leaves, RunOptions, Status};
use crate::session::EMPTY_TICKS_MAX;

#[derive(Clone)]
struct Replay<R> {
    recs: R,
    cursor: usize,
    diverged: bool,
    /// The replay asked for a record past the last one: the tick it was in
    /// is not whole yet (a live run still arriving).
    ran_out: bool,
}

/// The records a replay follows: each one's uid and status.
trait Keys {
    fn key(&self, i: usize) -> Option<(u32, Status)>;
}

impl Keys for Vec<Record> {
    fn key(&self, i: usize) -> Option<(u32, Status)> {
        self.get(i).map(|r| (r.uid, r.status))
    }
}

impl Keys for Packed<'_> {
    fn key(&self, i: usize) -> Option<(u32, Status)> {
        Packed::key(self, i)
    }
}

impl<R: Keys + Clone> Leaves for Replay<R> {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        let now = if call.resumed {
            Status::Running
        } else {
            Status::Idle
        };
        let status = match self.recs.key(self.cursor) {
            // The log ends inside this tick (it is still being written, or
            // the logger lost its queue): what follows is unknown, not wrong.
            None => {
                self.ran_out = true;
                Status::Running
            }
            Some((uid, status)) if uid == call.uid && status != now => status,
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
        match self.recs.key(self.cursor) {
            Some(k) if k == (uid, status) => self.cursor += 1,
            None => self.ran_out = true,
            _ => self.diverged = true,
        }
    }
}

/// Records below which a log is replayed in one piece.
const PARALLEL_MIN: usize = 1 << 17;

/// Structural tick of each record, or the index of the first record the
/// replay could not follow. A long log is replayed in pieces at once, one
/// a core: it is cut where the root went back to IDLE, the end of a tick
/// after which BehaviorTree.CPP has reset the whole tree, so each piece
/// replays from a fresh tree as it would have from the one before it. A
/// node that keeps state past that (Nav2's RoundRobin keeps its child,
/// a script its blackboard) makes a piece's replay not follow its
/// records, and then the log is replayed in one piece.
fn by_structure(tree: &Tree, recs: Packed) -> Result<Vec<u32>, usize> {
    let cores = super::cores();
    if let Some(ticks) = by_distinct_runs(tree, recs, cores) {
        return Ok(ticks);
    }
    by_structure_in(tree, recs, cores)
}

/// A robot that does one job again and again logs the same run again and
/// again (the same nodes changing to the same statuses in the same order:
/// the ticks spent running leave no record), and a replay from the reset
/// tree numbers the same records the same way. So each distinct run is
/// replayed once, the distinct runs one after the other as the log first
/// has them, and every repeat takes its first's numbers. `None` where no
/// run repeats, or where the distinct runs cannot be replayed one after
/// the other (a node keeps state from run to run): the log is then
/// replayed as it is.
fn by_distinct_runs(tree: &Tree, recs: Packed, pieces: usize) -> Option<Vec<u32>> {
    let root = super::btlog::pack(tree.root().uid, Status::Idle);
    let mut runs = vec![0];
    runs.extend(
        recs.moves
            .iter()
            .enumerate()
            .filter(|(_, &m)| m == root)
            .map(|(i, _)| i + 1)
            .filter(|&i| i < recs.len()),
    );
    runs.push(recs.len());
    // Each run's distinct run; the distinct ones' ranges in `recs`.
    let mut seen: std::collections::HashMap<(usize, u64), Vec<usize>> = Default::default();
    let mut distinct: Vec<std::ops::Range<usize>> = Vec::new();
    let mut of_run = Vec::with_capacity(runs.len() - 1);
    for w in runs.windows(2) {
        let run = &recs.moves[w[0]..w[1]];
        let hash = run.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &m| {
            (h ^ u64::from(m)).wrapping_mul(0x0100_0000_01b3)
        });
        let ids = seen.entry((run.len(), hash)).or_default();
        let id = match ids
            .iter()
            .find(|&&d| recs.moves[distinct[d].clone()] == *run)
        {
            Some(&d) => d,
            None => {
                distinct.push(w[0]..w[1]);
                ids.push(distinct.len() - 1);
                distinct.len() - 1
            }
        };
        of_run.push(id);
    }
    if distinct.len() == of_run.len() {
        return None;
    }
    let once = super::btlog::Columns {
        moves: distinct
            .iter()
            .flat_map(|d| recs.moves[d.clone()].iter().copied())
            .collect(),
        times: distinct
            .iter()
            .flat_map(|d| recs.times[d.clone()].iter().copied())
            .collect(),
    };
    let numbered = by_structure_in(tree, once.view(), pieces).ok()?;
    // Each distinct run's ticks in `numbered`, which count its first as 1
    // more than the tick before it.
    let mut at = 0;
    let spans: Vec<&[u32]> = distinct
        .iter()
        .map(|d| {
            at += d.len();
            &numbered[at - d.len()..at]
        })
        .collect();
    let mut out = crate::pages::with_capacity(recs.len());
    for &id in &of_run {
        let base = out.last().copied().unwrap_or(0) + 1;
        let first = spans[id][0];
        out.extend(spans[id].iter().map(|t| t - first + base));
    }
    Some(out)
}

fn by_structure_in(tree: &Tree, recs: Packed, pieces: usize) -> Result<Vec<u32>, usize> {
    let cuts = cuts(tree, recs, pieces);
    if cuts.len() > 2 {
        let parts: Vec<Result<Vec<u32>, usize>> = std::thread::scope(|scope| {
            let handles: Vec<_> = cuts
                .windows(2)
                .map(|w| {
                    let part = recs.part(w[0]..w[1]);
                    scope.spawn(move || by_structure_whole(tree, part))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or(Err(0)))
                .collect()
        });
        if parts.iter().all(Result::is_ok) {
            let mut out = Vec::with_capacity(recs.len());
            for part in parts.into_iter().flatten() {
                let base = out.last().copied().unwrap_or(0);
                out.extend(part.into_iter().map(|t| t + base));
            }
            return Ok(out);
        }
    }
    by_structure_whole(tree, recs)
}

/// Where to cut `recs` into about `pieces` of like length: just after a
/// record of the root going back to IDLE. The first cut is 0, the last
/// the length.
fn cuts(tree: &Tree, recs: Packed, pieces: usize) -> Vec<usize> {
    let mut cuts = vec![0];
    if pieces < 2 || recs.len() < PARALLEL_MIN {
        cuts.push(recs.len());
        return cuts;
    }
    let root = super::btlog::pack(tree.root().uid, Status::Idle);
    for k in 1..pieces {
        let aim = recs.len() * k / pieces;
        let from = aim.max(*cuts.last().expect("seeded"));
        if let Some(i) = recs.moves[from..].iter().position(|&m| m == root) {
            let cut = from + i + 1;
            if cut < recs.len() {
                cuts.push(cut);
            }
        }
    }
    cuts.push(recs.len());
    cuts.dedup();
    cuts
}

fn by_structure_whole(tree: &Tree, recs: Packed) -> Result<Vec<u32>, usize> {
    let mut ex = Executor::new(
        tree,
        Replay {
            recs,
            cursor: 0,
            diverged: false,
            ran_out: false,
        },
        RunOptions::default(),
    );
    let mut ticks = crate::pages::with_capacity(recs.len());
    ticks.resize(recs.len(), 0u32);
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
    let (mut last, mut n) = (0, 0);
    for t in &mut ticks {
        if *t != last {
            last = *t;
            n += 1;
        }
        *t = n;
    }
    Ok(ticks)
}

/// Timing alone: a new tick after a gap of 1 ms or more.
fn by_timing(times: &[i64]) -> Vec<u32> {
    let mut n = 0;
    let mut prev: Option<i64> = None;
    times
        .iter()
        .map(|&t| {
            if prev.is_none_or(|p| t.saturating_sub(p) >= 1000) {
                n += 1;
            }
            prev = Some(t);
            n
        })
        .collect()
}

/// Empty ticks one gap may stand for; all gaps together stand for at most
/// `EMPTY_TICKS_MAX`.
const EMPTY_PER_GAP: f64 = 1e6;

/// The ticks from one tick's first record to the next one's: a gap
/// almost k periods long is k ticks, the k - 1 between them ones in which
/// nothing changed (a leaf kept RUNNING). A tree its last tick left IDLE
/// (its run over: BehaviorTree.CPP reset it) is not being ticked: a tick
/// of it would have started it again, so the gap is one tick whatever
/// its length (the pause between two runs of a robot).
fn ticks_in_gap(gap_us: i64, period: Option<i64>, root_idle: bool) -> u32 {
    match period {
        Some(p) if !root_idle => (gap_us as f64 / p.max(1) as f64 + 0.1)
            .floor()
            .clamp(1.0, EMPTY_PER_GAP) as u32,
        _ => 1,
    }
}

/// Puts back the ticks in which nothing changed, from the time between
/// ticks, into the structural numbers in place; and the record from which
/// gaps counted for one tick each, if the empty ticks ran past
/// `EMPTY_TICKS_MAX`. Two passes over the records, the gaps the only thing
/// kept between them: a log of millions is numbered without a copy.
fn with_empty_ticks(recs: Packed, mut ticks: Vec<u32>) -> (Vec<u32>, Option<usize>) {
    let mut gaps: Vec<i64> = Vec::new();
    let mut prev_first: Option<i64> = None;
    for (i, &time) in recs.times.iter().enumerate() {
        if i == 0 || ticks[i] != ticks[i - 1] {
            if let Some(p) = prev_first {
                let g = time.saturating_sub(p);
                if g > 0 {
                    gaps.push(g);
                }
            }
            prev_first = Some(time);
        }
    }
    // A late tick makes a long gap, never a short one: measure the period
    // by the short gaps, and count a gap as k ticks only once it is almost
    // k periods long.
    if gaps.is_empty() {
        return (ticks, None);
    }
    let tenth = gaps.len() / 10;
    let period = *gaps.select_nth_unstable(tenth).1;
    drop(gaps);
    let mut empty = 0u32;
    let mut capped = None;
    // Whether the root was left IDLE by the tick before each record.
    let mut root_idle = false;
    let (mut structural, mut number, mut first) = (0u32, 0u32, 0i64);
    for (i, (&m, &time)) in recs.moves.iter().zip(recs.times).enumerate() {
        if i == 0 {
            (structural, number, first) = (ticks[0], 1, time);
        } else if ticks[i] != structural {
            let steps = ticks_in_gap(time.saturating_sub(first), Some(period), root_idle);
            let extra = (steps - 1).min(EMPTY_TICKS_MAX - empty);
            if extra < steps - 1 && capped.is_none() {
                capped = Some(i);
            }
            empty += extra;
            (structural, number, first) = (ticks[i], number + 1 + extra, time);
        }
        ticks[i] = number;
        let (uid, status) = super::btlog::unpack(m);
        if uid == Tree::ROOT {
            root_idle = status == Status::Idle;
        }
    }
    (ticks, capped)
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

pub fn reconstruct(tree: &Tree, recs: Packed) -> Ticks {
    let (structural, fell_back) = match by_structure(tree, recs) {
        Ok(t) => (t, None),
        Err(at) => (by_timing(recs.times), Some(at)),
    };
    let (numbers, capped) = with_empty_ticks(recs, structural);
    Ticks {
        numbers,
        fell_back,
        capped,
    }
}

/// Tick numbers given as records arrive (a live run), by the rule of
/// `reconstruct`, with one difference: a number once given is final, so
/// that the run streams to its file and nothing of it need be held. The
/// tick period is measured over the ticks so far (the first `SETTLE`
/// ticks wait for it), where `reconstruct` measures it over the whole log;
/// after a gap (records lost) ticks are told apart by timing, as
/// `reconstruct` does from where its replay cannot follow.
pub struct Stream<'t> {
    /// The replay at the last whole tick (its leaves hold the records not
    /// numbered yet); `None` once ticks go by timing.
    replay: Option<Executor<'t, Replay<Vec<Record>>>>,
    /// Records not numbered yet, when ticks go by timing.
    waiting: Vec<Record>,
    /// Whole ticks not numbered yet: the first ones wait for the period.
    held: Vec<Vec<Record>>,
    /// The last tick numbered: its first record's time and its number.
    last: Option<(i64, u32)>,
    /// The last record's time, when ticks go by timing.
    timing_last: Option<i64>,
    /// The time between ticks' first records, as counts by value (bounded:
    /// past `GAP_VALUES_MAX` values, they are rounded coarser).
    gaps: std::collections::BTreeMap<i64, u64>,
    gap_count: u64,
    coarse: u32,
    empty: u32,
    /// Records given a number so far, and taken in all.
    pub numbered: usize,
    received: usize,
    pub fell_back: Option<usize>,
    pub capped: Option<usize>,
    /// Where a tick ran past `TICK_RECORDS_MAX` records and was closed.
    pub overlong: Option<usize>,
    /// Whether the last tick numbered left the root IDLE (see
    /// `ticks_in_gap`).
    root_idle: bool,
}

/// The records one tick holds at most while it waits for its end (a tick
/// of a 100,000-node tree in which every node runs makes 200,000): a robot
/// that sends more without a tick's end has that tick closed there (said
/// by the caller), so that what waits is bounded: about 100 MB at most
/// with the copies numbering makes, measured on a flooding publisher.
pub const TICK_RECORDS_MAX: usize = 1 << 18;

/// Ticks numbered only once the period is measured over this many.
const SETTLE: usize = 8;
/// Distinct gap values kept to measure the period.
const GAP_VALUES_MAX: usize = 1 << 16;

impl<'t> Stream<'t> {
    pub fn new(tree: &'t Tree) -> Stream<'t> {
        let replay = Executor::new(
            tree,
            Replay {
                recs: Vec::new(),
                cursor: 0,
                diverged: false,
                ran_out: false,
            },
            RunOptions::default(),
        );
        Stream {
            replay: Some(replay),
            waiting: Vec::new(),
            held: Vec::new(),
            last: None,
            timing_last: None,
            gaps: Default::default(),
            gap_count: 0,
            coarse: 0,
            empty: 0,
            numbered: 0,
            received: 0,
            fell_back: None,
            capped: None,
            overlong: None,
            root_idle: false,
        }
    }

    /// Takes records as they arrive; the records now numbered, in order.
    pub fn push(&mut self, recs: &[Record]) -> Vec<(Record, u32)> {
        self.received += recs.len();
        let whole = match self.replay.as_mut() {
            Some(ex) => {
                ex.leaves.recs.extend_from_slice(recs);
                match whole_ticks(ex) {
                    Ok(ticks) => ticks,
                    Err(mut ticks) => {
                        // The replay cannot follow: what it held goes by
                        // timing, and so does the rest of the run.
                        let rest = std::mem::take(&mut ex.leaves.recs);
                        self.replay = None;
                        self.fell_back.get_or_insert(self.received - rest.len());
                        ticks.extend(self.by_timing(&rest));
                        ticks
                    }
                }
            }
            None => self.by_timing(recs),
        };
        let mut out = self.number(whole, false);
        let waiting = match &self.replay {
            Some(ex) => ex.leaves.recs.len(),
            None => self.waiting.len(),
        };
        if waiting > TICK_RECORDS_MAX {
            self.overlong.get_or_insert(self.received - waiting);
            out.extend(self.gap());
        }
        out
    }

    /// Records may be missing here: what arrived is numbered as it is, and
    /// from here ticks go by timing.
    pub fn gap(&mut self) -> Vec<(Record, u32)> {
        let mut whole = Vec::new();
        if let Some(mut ex) = self.replay.take() {
            self.fell_back.get_or_insert(self.received);
            let mut t = whole_ticks(&mut ex).unwrap_or_else(|t| t);
            let rest = std::mem::take(&mut ex.leaves.recs);
            if !rest.is_empty() {
                t.push(rest);
            }
            whole = t;
        }
        whole.extend(self.waiting_tick());
        self.timing_last = None;
        self.number(whole, true)
    }

    /// The robot has gone quiet: the whole ticks held for the period are
    /// numbered now, by the period measured so far (a run of fewer than
    /// `SETTLE` ticks would otherwise wait for its end to be shown).
    /// Ticks told apart by timing (after a gap, or attached to a robot
    /// already running) end at a pause of 1 ms: the tick the quiet follows
    /// is whole too, and numbered now, where it waited for the next record
    /// (a watch `--until-end` of a robot joined while it ran waited for
    /// ever for its run's last tick).
    pub fn settle(&mut self) -> Vec<(Record, u32)> {
        let quiet_tick = if self.replay.is_none() {
            self.waiting_tick()
        } else {
            None
        };
        if self.held.is_empty() && quiet_tick.is_none() {
            return Vec::new();
        }
        self.number(quiet_tick.into_iter().collect(), true)
    }

    /// The run is over: everything is numbered.
    pub fn finish(&mut self) -> Vec<(Record, u32)> {
        let mut whole = Vec::new();
        if let Some(ex) = self.replay.as_mut() {
            whole = whole_ticks(ex).unwrap_or_else(|t| t);
            let rest = std::mem::take(&mut ex.leaves.recs);
            ex.leaves.cursor = 0;
            if !rest.is_empty() {
                whole.push(rest);
            }
        }
        whole.extend(self.waiting_tick());
        self.number(whole, true)
    }

    /// Ticks by timing: a new one after 1 ms or more. The last one waits
    /// for the next record (or `finish`).
    fn by_timing(&mut self, recs: &[Record]) -> Vec<Vec<Record>> {
        let mut out = Vec::new();
        for r in recs {
            if self
                .timing_last
                .is_some_and(|p| r.time_us.saturating_sub(p) >= 1000)
            {
                out.push(std::mem::take(&mut self.waiting));
            }
            self.timing_last = Some(r.time_us);
            self.waiting.push(*r);
        }
        out
    }

    fn waiting_tick(&mut self) -> Option<Vec<Record>> {
        (!self.waiting.is_empty()).then(|| std::mem::take(&mut self.waiting))
    }

    /// Numbers whole ticks (the first `SETTLE` wait, unless `now`).
    fn number(&mut self, ticks: Vec<Vec<Record>>, now: bool) -> Vec<(Record, u32)> {
        let mut out = Vec::new();
        for t in ticks.into_iter().filter(|t| !t.is_empty()) {
            let prev = self
                .held
                .last()
                .map(|h| h[0].time_us)
                .or(self.last.map(|l| l.0));
            if let Some(g) = prev.map(|p| t[0].time_us.saturating_sub(p)) {
                if g > 0 {
                    self.count_gap(g);
                }
            }
            self.held.push(t);
        }
        if now || self.held.len() > SETTLE || (self.last.is_some() && !self.held.is_empty()) {
            self.release(&mut out);
        }
        out
    }

    fn count_gap(&mut self, g: i64) {
        *self.gaps.entry(g >> self.coarse).or_default() += 1;
        self.gap_count += 1;
        if self.gaps.len() > GAP_VALUES_MAX {
            self.coarse += 1;
            let old = std::mem::take(&mut self.gaps);
            for (k, n) in old {
                *self.gaps.entry(k >> 1).or_default() += n;
            }
        }
    }

    /// The period as `reconstruct` measures it: the gap a tenth of the way
    /// up the sorted gaps.
    fn period(&self) -> Option<i64> {
        let want = self.gap_count / 10;
        let mut seen = 0;
        for (&k, &n) in &self.gaps {
            seen += n;
            if seen > want {
                return Some(k << self.coarse);
            }
        }
        None
    }

    fn release(&mut self, out: &mut Vec<(Record, u32)>) {
        let period = self.period();
        for t in std::mem::take(&mut self.held) {
            let first = t[0].time_us;
            let n = match self.last {
                None => 1,
                Some((prev, n)) => {
                    let steps = ticks_in_gap(first.saturating_sub(prev), period, self.root_idle);
                    let extra = (steps - 1).min(EMPTY_TICKS_MAX - self.empty);
                    if extra < steps - 1 && self.capped.is_none() {
                        self.capped = Some(self.numbered);
                    }
                    self.empty += extra;
                    n + 1 + extra
                }
            };
            self.last = Some((first, n));
            if let Some(r) = t.iter().rev().find(|r| r.uid == Tree::ROOT) {
                self.root_idle = r.status == Status::Idle;
            }
            self.numbered += t.len();
            out.extend(t.into_iter().map(|r| (r, n)));
        }
    }
}

/// Runs the replay over the records it holds, tick by tick, as far as
/// whole ticks go; their records, taken out of it. A tick that asks past
/// the last record is not whole: the replay goes back to before it. An
/// error: the replay cannot follow (with the whole ticks before).
fn whole_ticks(
    ex: &mut Executor<'_, Replay<Vec<Record>>>,
) -> Result<Vec<Vec<Record>>, Vec<Vec<Record>>> {
    let mut ticks = Vec::new();
    let mut stuck = 0;
    loop {
        let before = ex.leaves.cursor;
        if before == ex.leaves.recs.len() {
            break;
        }
        ex.leaves.ran_out = false;
        let saved = ex.clone();
        let r = ex.tick_once();
        ex.take_events();
        let after = ex.leaves.cursor;
        if ex.leaves.ran_out && !ex.leaves.diverged && r.is_ok() {
            *ex = saved;
            break;
        }
        if r.is_err() || ex.leaves.diverged {
            *ex = saved;
            let done = take_ticks(ex, &mut ticks);
            return Err(done);
        }
        if after == before {
            stuck += 1;
            if stuck > 2 {
                *ex = saved;
                let done = take_ticks(ex, &mut ticks);
                return Err(done);
            }
        } else {
            stuck = 0;
            ticks.push(after);
        }
    }
    Ok(take_ticks(ex, &mut ticks))
}

/// The records of the whole ticks that end at `ends`, taken out of the
/// replay's leaves.
fn take_ticks(
    ex: &mut Executor<'_, Replay<Vec<Record>>>,
    ends: &mut Vec<usize>,
) -> Vec<Vec<Record>> {
    let mut out = Vec::new();
    let mut start = 0;
    for &end in ends.iter() {
        out.push(ex.leaves.recs[start..end].to_vec());
        start = end;
    }
    ex.leaves.recs.drain(..start);
    ex.leaves.cursor -= start;
    ends.clear();
    out
}

#[cfg(test)]
mod tests;
