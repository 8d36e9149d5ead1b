//! A transition as a row of `btx log`'s table: what the table, its JSON
//! and a watched robot's `--transitions` print.

use crate::model::Uid;
use crate::run::Status;

#[derive(Debug, Clone, PartialEq)]
pub struct LogRow {
    pub tick: u32,
    pub step: u32,
    pub uid: Uid,
    pub prev: Status,
    pub status: Status,
    pub decision: Option<String>,
    /// Transitions may be missing just before this one (a live run's gap;
    /// those before filtered-out rows come with the next row shown).
    pub gap: Option<String>,
    /// The robot's clock, µs since the epoch, where the source gives one.
    pub time_us: Option<i64>,
}
