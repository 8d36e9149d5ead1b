//! A session's transitions as a table, like Groot's replay table.

use crate::model::Uid;
use crate::run::Status;
use crate::session::Session;
use serde_json::{json, Value};

pub use crate::session::LogRow;

/// The gaps after the last transition (a live run that ended on one).
pub fn trailing_gaps(s: &Session) -> Vec<&str> {
    let n = s.index.transitions.len() as u32;
    s.index
        .gaps
        .iter()
        .filter(|g| g.0 >= n)
        .map(|g| g.1.as_str())
        .collect()
}

/// The rows of `btx log`, filtered to one node and/or without →IDLE.
pub fn log_rows(s: &Session, only: Option<Uid>, no_idle: bool) -> Vec<LogRow> {
    let mut rows = Vec::new();
    each_log_row(s, only, no_idle, |r| rows.push(r));
    rows
}

/// Which transitions a table shows: `btx log`'s `--node` and `--no-idle`,
/// and the explorer's filters.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LogFilter {
    /// One node.
    pub node: Option<Uid>,
    /// A node and everything below it.
    pub below: Option<Uid>,
    /// Leave out transitions to IDLE (resets and halts).
    pub no_idle: bool,
    /// Only transitions to this status.
    pub status: Option<Status>,
    /// Only nodes whose description contains this (any case).
    pub text: String,
}

impl LogFilter {
    pub fn is_empty(&self) -> bool {
        *self == LogFilter::default()
    }

    pub fn keeps(&self, tree: &crate::model::Tree, t: &crate::session::Transition) -> bool {
        !(self.node.is_some_and(|u| u != t.uid)
            || self
                .below
                .is_some_and(|u| u != t.uid && !tree.is_ancestor(u, t.uid))
            || (self.no_idle && t.status == Status::Idle)
            || self.status.is_some_and(|x| x != t.status)
            || (!self.text.is_empty()
                && !tree
                    .description(t.uid)
                    .to_lowercase()
                    .contains(&self.text.to_lowercase())))
    }
}

/// The rows of `btx log` one at a time, in order: a log of millions of
/// transitions is written as it is read, never held whole.
pub fn each_log_row(s: &Session, only: Option<Uid>, no_idle: bool, mut f: impl FnMut(LogRow)) {
    let idx = &s.index;
    let filter = LogFilter {
        node: only,
        no_idle,
        ..LogFilter::default()
    };
    let (mut gi, mut gap): (usize, Option<String>) = (0, None);
    let timed = s.times_us.len() == idx.transitions.len();
    for tick in 1..=idx.ticks() {
        let r = idx.tick_range(tick);
        for (k, i) in r.clone().enumerate() {
            while let Some((_, why)) = idx.gaps.get(gi).filter(|g| g.0 as usize <= i) {
                gap = Some(match gap.take() {
                    Some(g) => format!("{g}; {why}"),
                    None => why.clone(),
                });
                gi += 1;
            }
            let t = idx.transitions[i];
            if !filter.keeps(&s.tree, &t) {
                continue;
            }
            f(LogRow {
                gap: gap.take(),
                tick,
                step: k as u32 + 1,
                uid: t.uid,
                prev: t.prev,
                status: t.status,
                decision: idx.transition_decision(i).map(str::to_string),
                time_us: timed.then(|| s.times_us[i]),
            });
        }
    }
}

/// What `btx log`'s table is read from: a session, or a log numbered
/// into ticks and not indexed (`logs::Numbered`), which prints as it is
/// read without the cost of an index.
pub trait Table {
    fn path(&self) -> &std::path::Path;
    fn tree(&self) -> &crate::model::Tree;
    fn ticks(&self) -> u32;
    /// `each_log_row`.
    fn each_row(&self, only: Option<Uid>, no_idle: bool, f: &mut dyn FnMut(LogRow));
    /// The gaps after the last transition (a live run that ended on one).
    fn trailing_gaps(&self) -> Vec<&str>;
    /// What reading it noticed.
    fn warnings(&self) -> &[crate::source::Warning];
    /// The robot's clock at the first transition (µs since the epoch),
    /// where the source gave times.
    fn first_time_us(&self) -> Option<i64>;
}

impl Table for Session {
    fn path(&self) -> &std::path::Path {
        &self.path
    }
    fn tree(&self) -> &crate::model::Tree {
        &self.tree
    }
    fn ticks(&self) -> u32 {
        self.index.ticks()
    }
    fn each_row(&self, only: Option<Uid>, no_idle: bool, f: &mut dyn FnMut(LogRow)) {
        each_log_row(self, only, no_idle, f)
    }
    fn trailing_gaps(&self) -> Vec<&str> {
        trailing_gaps(self)
    }
    fn warnings(&self) -> &[crate::source::Warning] {
        &self.warnings
    }
    fn first_time_us(&self) -> Option<i64> {
        self.times_us.first().copied()
    }
}

impl Table for crate::logs::Numbered {
    fn path(&self) -> &std::path::Path {
        &self.path
    }
    fn tree(&self) -> &crate::model::Tree {
        &self.tree
    }
    fn ticks(&self) -> u32 {
        crate::logs::Numbered::ticks(self)
    }
    /// The rows as `each_log_row` gives them from the session this log
    /// would be: a log has no gaps and no decisions.
    fn each_row(&self, only: Option<Uid>, no_idle: bool, f: &mut dyn FnMut(LogRow)) {
        let filter = LogFilter {
            node: only,
            no_idle,
            ..LogFilter::default()
        };
        // A log's row: no gap, no decision.
        let mut row = |i: usize, step: u32, t: crate::session::Transition| {
            if filter.keeps(&self.tree, &t) {
                f(LogRow {
                    tick: t.tick,
                    step,
                    uid: t.uid,
                    prev: t.prev,
                    status: t.status,
                    decision: None,
                    gap: None,
                    time_us: self.times_us.get(i).copied(),
                });
            }
        };
        match only {
            // One node's rows: the others need not be followed.
            Some(u) => self.each_transition_of(u, row),
            None => {
                let (mut tick, mut step) = (0, 0);
                self.each_transition(|i, t| {
                    step = if t.tick == tick { step + 1 } else { 1 };
                    tick = t.tick;
                    row(i, step, t)
                });
            }
        }
    }
    fn trailing_gaps(&self) -> Vec<&str> {
        Vec::new()
    }
    fn warnings(&self) -> &[crate::source::Warning] {
        &self.warnings
    }
    fn first_time_us(&self) -> Option<i64> {
        self.times_us.first().copied()
    }
}

/// The transition of each row `each_log_row` gives, in order, without
/// building the rows (their decisions, their gaps).
pub fn log_transitions(
    s: &Session,
    only: Option<Uid>,
    no_idle: bool,
) -> impl Iterator<Item = &crate::session::Transition> + '_ {
    let filter = LogFilter {
        node: only,
        no_idle,
        ..LogFilter::default()
    };
    s.index
        .transitions
        .iter()
        .filter(move |t| filter.keeps(&s.tree, t))
}

pub const LOG_TEXT_HEADER: &str =
    " tick  step   uid  node                                     prev        status   decision\n";

/// One row of the text table.
pub fn log_text_row(tree: &crate::model::Tree, r: &LogRow) -> String {
    let mut out = String::new();
    TextRows::new(tree).write(&mut out, "", r);
    out
}

/// `btx log`'s text rows, written into the caller's buffer: a log of
/// millions of rows is printed without a string made for each, and each
/// node's name is cut to its column once.
pub struct TextRows<'t> {
    tree: &'t crate::model::Tree,
    /// Each node's name, cut and padded to its column, by uid.
    names: Vec<Option<String>>,
}

impl<'t> TextRows<'t> {
    pub fn new(tree: &'t crate::model::Tree) -> TextRows<'t> {
        TextRows {
            tree,
            names: Vec::new(),
        }
    }

    /// Appends the row to `out`, `cell` (the time column) first; a gap
    /// before the row is said on a line of its own, without it.
    pub fn write(&mut self, out: &mut String, cell: &str, r: &LogRow) {
        use std::fmt::Write;
        if let Some(g) = &r.gap {
            let _ = writeln!(out, "  --- gap: {g} ---");
        }
        let at = r.uid as usize;
        if self.names.len() <= at {
            self.names.resize(at + 1, None);
        }
        let name = self.names[at].get_or_insert_with(|| {
            let mut name = self.tree.description(r.uid).to_string();
            if name.chars().count() > 40 {
                name = name.chars().take(39).collect::<String>() + "…";
            }
            format!("{name:<40}")
        });
        let decision = if r.prev == Status::Running && r.status == Status::Idle {
            "(halted)"
        } else {
            r.decision.as_deref().unwrap_or("")
        };
        let _ = writeln!(
            out,
            "{cell}{:>5} {:>5} {:>5}  {name} {:<8} -> {:<8} {decision}",
            r.tick, r.step, r.uid, r.prev, r.status,
        );
    }
}

/// The time column `btx log --time` adds before the others.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// The time of day, UTC, to the microsecond.
    Utc,
    /// The time of day in the local time zone (its offset at each row, so
    /// a change to summer time shows); the header names the offset at the
    /// run's start (µs since the epoch).
    Local(i64),
    /// Seconds since this time (µs since the epoch): the run's start.
    Relative(i64),
}

impl Clock {
    pub fn header(self) -> String {
        match self {
            Clock::Utc => "     time (UTC) ".into(),
            Clock::Local(t0) => format!(
                "{:>16} ",
                format!(
                    "time ({})",
                    crate::clock::utc_offset(crate::clock::local_offset_s(t0))
                )
            ),
            Clock::Relative(_) => "    time s ".into(),
        }
    }

    /// A row's time as the column shows it ("?" where it has none).
    pub fn cell(self, us: Option<i64>) -> String {
        match (self, us) {
            (Clock::Utc, Some(t)) => format!(
                "{}.{:06} ",
                &crate::clock::utc(t)[11..19],
                t.rem_euclid(1_000_000)
            ),
            (Clock::Local(_), Some(t)) => {
                let local = t + crate::clock::local_offset_s(t) * 1_000_000;
                format!(
                    " {}.{:06} ",
                    &crate::clock::utc(local)[11..19],
                    local.rem_euclid(1_000_000)
                )
            }
            (Clock::Relative(base), Some(t)) => {
                let d = t - base;
                let secs = format!(
                    "{}.{:03}",
                    d.div_euclid(1_000_000),
                    d.rem_euclid(1_000_000) / 1000
                );
                format!("{secs:>10} ")
            }
            (Clock::Utc, None) => format!("{:>15} ", "?"),
            (Clock::Local(_), None) => format!("{:>16} ", "?"),
            (Clock::Relative(_), None) => format!("{:>10} ", "?"),
        }
    }
}

pub fn log_text(s: &Session, rows: &[LogRow]) -> String {
    let mut out = LOG_TEXT_HEADER.to_string();
    let mut text = TextRows::new(&s.tree);
    for r in rows {
        text.write(&mut out, "", r);
    }
    out
}

/// One row as `btx.log/1` has it.
pub fn log_json_row(tree: &crate::model::Tree, r: &LogRow) -> Value {
    let mut v = json!({
        "tick": r.tick,
        "step": r.step,
        "uid": r.uid,
        "node": tree.description(r.uid),
        "type": tree.type_name(r.uid),
        "prev": r.prev,
        "status": r.status,
        "decision": r.decision,
        "halted": r.prev == Status::Running && r.status == Status::Idle,
    });
    if let Some(g) = &r.gap {
        v["gap"] = Value::from(g.clone());
    }
    if let Some(t) = r.time_us {
        v["time"] = Value::from(crate::clock::rfc3339(t));
        v["time_us"] = Value::from(t);
    }
    v
}

/// `btx.log/1`, pretty-printed as `log_json` would be, written row by row.
pub fn write_log_json(
    w: &mut impl std::io::Write,
    s: &(impl Table + ?Sized),
    only: Option<Uid>,
    no_idle: bool,
) -> std::io::Result<()> {
    write!(
        w,
        "{{\n  \"schema\": \"btx.log/1\",\n  \"session\": {},\n  \"ticks\": {},\n  \"transitions\": [",
        Value::from(s.path().display().to_string()),
        s.ticks()
    )?;
    let mut first = true;
    let mut result = Ok(());
    s.each_row(only, no_idle, &mut |r| {
        if result.is_err() {
            return;
        }
        // The row as `to_string_pretty` lays it out inside the array,
        // written directly: a million rows cost no JSON tree.
        let text = |x: &str| serde_json::to_string(x).expect("strings serialise");
        let gap = r
            .gap
            .as_deref()
            .map_or(String::new(), |g| format!(",\n      \"gap\": {}", text(g)));
        let time = r.time_us.map_or(String::new(), |t| {
            format!(
                ",\n      \"time\": \"{}\",\n      \"time_us\": {t}",
                crate::clock::rfc3339(t)
            )
        });
        let gap = gap + time.as_str();
        let chunk = format!(
            "{}    {{\n      \"tick\": {},\n      \"step\": {},\n      \"uid\": {},\n      \"node\": {},\n      \"type\": {},\n      \"prev\": \"{}\",\n      \"status\": \"{}\",\n      \"decision\": {},\n      \"halted\": {}{}\n    }}",
            if first { "\n" } else { ",\n" },
            r.tick,
            r.step,
            r.uid,
            text(s.tree().description(r.uid)),
            text(s.tree().type_name(r.uid)),
            r.prev,
            r.status,
            r.decision.as_deref().map_or_else(|| "null".to_string(), text),
            r.prev == Status::Running && r.status == Status::Idle,
            gap
        );
        first = false;
        result = w.write_all(chunk.as_bytes());
    });
    result?;
    let end = s.trailing_gaps();
    let end = if end.is_empty() {
        String::new()
    } else {
        format!(
            ",\n  \"gaps_at_end\": {}",
            serde_json::to_string(&end).expect("strings serialise")
        )
    };
    if first {
        writeln!(w, "]{end}\n}}")
    } else {
        writeln!(w, "\n  ]{end}\n}}")
    }
}

/// One JSON object a line, for a log followed as it grows.
pub fn log_json_lines(s: &Session, rows: &[LogRow]) -> String {
    let mut out = String::new();
    if let Some(all) = log_json(s, rows)["transitions"].as_array() {
        for r in all {
            out.push_str(&r.to_string());
            out.push('\n');
        }
    }
    out
}

pub fn log_json(s: &Session, rows: &[LogRow]) -> Value {
    json!({
        "schema": "btx.log/1",
        "session": s.path.display().to_string(),
        "ticks": s.index.ticks(),
        "transitions": rows.iter().map(|r| log_json_row(&s.tree, r)).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_streamed_json_is_the_json_value_pretty_printed() {
        let s = Session::load(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("sessions/kitting-lookat-fails-once.jsonl"),
        )
        .unwrap();
        // A log keeps each transition's time: the rows carry it.
        let timed = crate::input::open(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("tests/fixtures/logs/kitting_lookat_fails_once.btlog"),
            &Default::default(),
        )
        .unwrap();
        let timed = timed.session().unwrap();
        assert!(
            log_json(timed, &log_rows(timed, Some(18), false))["transitions"][1]["time"]
                .as_str()
                .is_some_and(|t| t.ends_with('Z') && t.len() == 27)
        );
        for s in [&s, timed] {
            for (only, no_idle) in [(None, false), (Some(18), true), (Some(2), true)] {
                let rows = log_rows(s, only, no_idle);
                let whole = serde_json::to_string_pretty(&log_json(s, &rows)).unwrap() + "\n";
                let mut streamed = Vec::new();
                write_log_json(&mut streamed, s, only, no_idle).unwrap();
                assert_eq!(String::from_utf8(streamed).unwrap(), whole, "{only:?}");
            }
        }
    }
}
