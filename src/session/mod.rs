//! Sessions: the episodic memory of a run (Love et al. §5.1), as a file and
//! as an index by moment.

mod build;
pub mod columnar;
pub mod copy;
pub mod format;
pub mod index;
pub mod jsonl;
pub mod output;
pub mod parting;
pub mod read;
pub mod record;
pub mod rerun;
mod row;
pub mod scratch;
pub mod sink;
pub mod write;

pub use format::{Before, Header, Record, Source, TreeRef};
pub use index::{At, Index, Moment, TickMark, Transition, Write, EMPTY_TICKS_MAX};
pub use output::OutputLock;
pub use row::LogRow;
pub use write::SessionWriter;

use crate::model::{Tree, Uid};
use crate::source::{Located, Warning};
use std::path::{Path, PathBuf};

/// A loaded session.
pub struct Session {
    pub path: PathBuf,
    pub header: Header,
    /// The tree as it ran, inserted subgoals included.
    pub tree: Tree,
    pub index: Index,
    /// The end record, if the run finished.
    pub end: Option<(u32, crate::run::Status, String)>,
    /// Subgoals inserted during the run: (position, copy of, after, first uid, question).
    pub inserts: Vec<(u32, Uid, Uid, Uid, String)>,
    /// When the first and the last transition happened (µs since the
    /// epoch), as a log says; a session keeps no times.
    pub span_us: Option<(i64, i64)>,
    /// When each transition happened (µs since the epoch), as a log says;
    /// empty for a session, which keeps no times.
    pub times_us: Vec<i64>,
    pub warnings: Vec<Warning>,
    /// Run k of the n its log holds, when it holds several (a rosbag's
    /// goals, a `.btlog` whose tree started again).
    pub run: Option<(usize, usize)>,
}

impl Session {
    /// How the run ended, as a line: the root's last status and why it
    /// stopped, or the error that stopped it, or that nothing says.
    pub fn ending(&self) -> String {
        match &self.end {
            Some((ticks, _, reason)) if reason.starts_with("error: ") => {
                format!("stopped at tick {ticks} by an {reason}")
            }
            Some((ticks, root, reason)) if root.is_completed() => {
                format!("ended at tick {ticks}: root {} ({reason})", root.as_str())
            }
            Some((ticks, root, reason)) => format!(
                "stopped at tick {ticks} with the root {} ({reason})",
                root.as_str()
            ),
            None => format!(
                "no end recorded after tick {}: the run was cut off or is still going",
                self.index.ticks()
            ),
        }
    }

    /// The session file at `path`, JSON lines (read a line at a time) or
    /// Parquet.
    pub fn load(path: &Path) -> Result<Session, Located> {
        let mut b = build::Building::default();
        read::file(path, &mut b)?;
        Ok(b.session())
    }

    /// A session from its JSON lines.
    pub fn parse(path: &Path, text: &str) -> Result<Session, Located> {
        let mut b = build::Building::default();
        jsonl::jsonl(path, text, &mut b)?;
        Ok(b.session())
    }

    /// A session from its file's bytes, JSON lines or Parquet.
    pub fn from_bytes(path: &Path, bytes: Vec<u8>) -> Result<Session, Located> {
        let mut b = build::Building::default();
        read::any(path, bytes, &mut b)?;
        Ok(b.session())
    }

    pub fn at(&self, m: Moment) -> Result<At<'_>, String> {
        Ok(self.index.at(self.index.position(m)?))
    }

    /// `--at` as written: a moment (`10`, `10:3`, `last`, `-2`), or a time
    /// on the robot's clock, for a run that keeps one: a time of day
    /// (`01:55:41.796`, UTC, with or without `Z` or ` UTC`) or a date and
    /// time as btx's JSON writes them (`2026-11-25T01:55:41.796157Z`): the
    /// moment after the last transition at or before it. Answers say
    /// times to the microsecond, so a time an answer said is the moment
    /// it was about.
    pub fn moment_at(&self, text: &str) -> Result<Moment, String> {
        let t = text.trim();
        let clock = t
            .strip_suffix("UTC")
            .or_else(|| t.strip_suffix('Z'))
            .unwrap_or(t)
            .trim();
        if clock.matches(':').count() != 2 {
            return Moment::parse_within(text, self.index.ticks());
        }
        let bad = || {
            format!("\"{text}\" is not a time of day: write HH:MM:SS or HH:MM:SS.ffffff (UTC), e.g. 01:55:41.796, or a date and time, e.g. 2026-11-25T01:55:41.796Z")
        };
        let (date, clock) = match clock.split_once(['T', ' ']) {
            Some((d, c)) => (Some(days_of(d).ok_or_else(bad)?), c),
            None => (None, clock),
        };
        let mut parts = clock.splitn(3, ':');
        let (h, m, sec) = (parts.next(), parts.next(), parts.next());
        let num = |x: Option<&str>, max: u32| {
            x.and_then(|x| x.parse::<u32>().ok())
                .filter(|&n| n < max)
                .ok_or_else(bad)
        };
        let (h, m) = (num(h, 24)?, num(m, 60)?);
        let sec = sec
            .and_then(|x| x.parse::<f64>().ok())
            .filter(|x| (0.0..61.0).contains(x))
            .ok_or_else(bad)?;
        let (Some(&first), Some(&last)) = (self.times_us.first(), self.times_us.last()) else {
            return Err(format!(
                "\"{text}\" is a time of day, and {} keeps no times (a log or a watched robot's run does)",
                self.path.display()
            ));
        };
        let of_day =
            (i64::from(h) * 3600 + i64::from(m) * 60) * 1_000_000 + (sec * 1e6).round() as i64;
        let want = match date {
            Some(days) => days * 86_400_000_000 + of_day,
            None => {
                // The first such time at or after the run's first day
                // began; a run past midnight reads an earlier clock as the
                // next day's.
                let day = first.div_euclid(86_400_000_000) * 86_400_000_000;
                let want = day + of_day;
                if want < first && first - want > 43_200_000_000 {
                    want + 86_400_000_000
                } else {
                    want
                }
            }
        };
        let upto = self.times_us.partition_point(|&x| x <= want);
        if upto == 0 {
            return Err(format!(
                "\"{text}\" is before the run's first transition, at {}",
                crate::clock::rfc3339(first)
            ));
        }
        if want > last {
            return Err(format!(
                "\"{text}\" is after the run's last transition, at {} (--at last is the run's end)",
                crate::clock::rfc3339(last)
            ));
        }
        Ok(self.index.moment(upto as u32))
    }
}

/// Days since 1970-01-01 of a date written `YYYY-MM-DD` (Howard Hinnant's
/// days-from-civil).
fn days_of(date: &str) -> Option<i64> {
    let mut parts = date.splitn(3, '-');
    let y: i64 = parts.next()?.parse().ok()?;
    let m: i64 = parts
        .next()?
        .parse()
        .ok()
        .filter(|m| (1..=12).contains(m))?;
    let d: i64 = parts
        .next()?
        .parse()
        .ok()
        .filter(|d| (1..=31).contains(d))?;
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * (m + if m > 2 { -3 } else { 9 }) + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    Some(era * 146_097 + doe - 719_468)
}
