//! A bag's status changes as read: pieces one after the other, each kept
//! as the thread that read it wrote it. Millions of changes read on every
//! core are then never copied into one array on one thread (nor its pages
//! first touched there); a run is copied out when it is opened.

use super::Record;

#[derive(Debug, Clone, Default)]
pub struct Changes {
    pieces: Vec<Vec<Record>>,
    /// Where each piece starts among all the changes.
    starts: Vec<usize>,
    len: usize,
    /// Whether the last piece is this thread's, to push onto.
    own: bool,
}

impl Changes {
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn last(&self) -> Option<&Record> {
        self.pieces.iter().rev().find_map(|p| p.last())
    }

    /// Every change in order (each `offset` as its piece wrote it: see
    /// `range`).
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &Record> + '_ {
        self.pieces.iter().flatten()
    }

    /// Changes `from..to` in order, as `iter` gives them.
    pub fn iter_range(&self, from: usize, to: usize) -> impl Iterator<Item = &Record> + '_ {
        let first = self
            .starts
            .partition_point(|&s| s <= from)
            .saturating_sub(1);
        let skip = from - self.starts.get(first).copied().unwrap_or(0);
        self.pieces[first.min(self.pieces.len())..]
            .iter()
            .flatten()
            .skip(skip)
            .take(to.saturating_sub(from))
    }

    /// Changes `from..to`, each numbered by its place among all of them
    /// (its `offset`), as a status change of the topic is said.
    pub fn range(&self, from: usize, to: usize) -> Vec<Record> {
        self.iter_range(from, to)
            .zip(from..)
            .map(|(r, i)| Record { offset: i, ..*r })
            .collect()
    }

    /// A change read on this thread. The first piece of them gets room for
    /// `room` changes: reserved, not touched, it costs no memory.
    pub(super) fn push(&mut self, r: Record, room: usize) {
        if !self.own {
            let mut p = Vec::new();
            if self.pieces.is_empty() {
                p.reserve(room);
            }
            self.starts.push(self.len);
            self.pieces.push(p);
            self.own = true;
        }
        if let Some(p) = self.pieces.last_mut() {
            p.push(r);
            self.len += 1;
        }
    }

    /// Changes read on another thread, kept as they are.
    pub(super) fn append(&mut self, piece: Vec<Record>) {
        if piece.is_empty() {
            return;
        }
        self.starts.push(self.len);
        self.len += piece.len();
        self.pieces.push(piece);
        self.own = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Status;

    fn rec(i: usize) -> Record {
        Record {
            time_us: i as i64,
            uid: 1,
            status: Status::Running,
            offset: 0,
        }
    }

    #[test]
    fn pieces_read_as_one_run_of_changes() {
        let mut c = Changes::default();
        c.push(rec(0), 10);
        c.push(rec(1), 10);
        c.append((2..5).map(rec).collect());
        c.append(Vec::new());
        c.push(rec(5), 10);
        c.append(vec![rec(6)]);
        assert_eq!(c.len(), 7);
        assert_eq!(c.last().map(|r| r.time_us), Some(6));
        let times = |v: Vec<Record>| v.iter().map(|r| (r.time_us, r.offset)).collect::<Vec<_>>();
        assert_eq!(
            times(c.range(0, 7)),
            (0..7).map(|i| (i, i as usize)).collect::<Vec<_>>()
        );
        for from in 0..=7 {
            for to in from..=7 {
                let want: Vec<(i64, usize)> = (from..to).map(|i| (i as i64, i)).collect();
                assert_eq!(times(c.range(from, to)), want, "{from}..{to}");
            }
        }
        assert_eq!(c.iter().next_back().map(|r| r.time_us), Some(6));
    }
}
