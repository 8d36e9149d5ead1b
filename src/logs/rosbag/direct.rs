//! Nav2's change as Jazzy and later lay it out (a time, the node's name,
//! its uid, two statuses), read straight into records. `Flat` reads any
//! layout into slots, op by op; a bag is millions of changes of this one
//! layout, so it is read here in one pass with nothing in between. A
//! message this does not read whole and plain (another byte order, bytes
//! that do not fit, a uid that does not name the tree's node of that
//! name) is left to `Flat`, which says what is wrong.

use super::{Record, Status, Uid};
use crate::logs::cdr::{Flat, Op};

/// The fields before the sequence of changes, as the sizes of their
/// integers (a header of anything else is not this layout).
#[derive(Debug)]
pub(super) struct Direct {
    head: Vec<usize>,
}

/// A change's fields as `CHANGE_PATHS` slots them: `timestamp.sec`,
/// `timestamp.nanosec`, `node_name`, `uid`, `previous_status`,
/// `current_status`.
const CHANGE: [Op; 6] = [
    Op::Int {
        size: 4,
        signed: true,
        slot: Some(1),
    },
    Op::Int {
        size: 4,
        signed: false,
        slot: Some(2),
    },
    Op::Text { slot: Some(3) },
    Op::Int {
        size: 2,
        signed: false,
        slot: Some(4),
    },
    Op::Text { slot: Some(5) },
    Op::Text { slot: Some(6) },
];

impl Direct {
    /// Where `flat` is this layout.
    pub(super) fn of(flat: &Flat) -> Option<Direct> {
        let [head, items, tail] = flat.ops();
        if items != CHANGE || !tail.is_empty() {
            return None;
        }
        let head = head
            .iter()
            .map(|op| match *op {
                Op::Int { size, .. } => Some(size),
                Op::Text { .. } => None,
            })
            .collect::<Option<Vec<usize>>>()?;
        Some(Direct { head })
    }

    /// One message's changes onto `out`, each its node (by uid, whose
    /// name in `named` must be the change's) and status, offsets counted
    /// in `out`; `None` where any is not plain, `out` then holding some.
    pub(super) fn read(
        &self,
        data: &[u8],
        named: &[Box<[u8]>],
        out: &mut Vec<Record>,
    ) -> Option<()> {
        // Little-endian CDR, plain or XCDR2 (as `Reader::open`).
        if !matches!(data.get(..2), Some([0, 1] | [0, 3])) {
            return None;
        }
        let b = data.get(4..)?;
        let mut at = 0;
        for &n in &self.head {
            at = align(at, n) + n;
        }
        let (n, mut at) = int32(b, align(at, 4))?;
        if n as usize > b.len() - at {
            return None;
        }
        out.reserve(n as usize);
        for _ in 0..n {
            let (sec, next) = int32(b, align(at, 4))?;
            let (nsec, next) = int32(b, next)?;
            let (name, next) = text(b, next)?;
            let at16 = align(next, 2);
            let uid = u16::from_le_bytes(b.get(at16..at16 + 2)?.try_into().ok()?) as Uid;
            let (_, next) = text(b, at16 + 2)?;
            let (now, next) = text(b, next)?;
            at = next;
            if **named.get((uid as usize).wrapping_sub(1))? != *name {
                return None;
            }
            out.push(Record {
                time_us: (sec as i32 as i64)
                    .saturating_mul(1_000_000)
                    .saturating_add(nsec as i64 / 1000),
                uid,
                status: Status::parse_bytes(now)?,
                offset: out.len(),
            });
        }
        // As `Reader::finish`: no more than padding left.
        (b.len() - at < 4).then_some(())
    }
}

fn align(at: usize, n: usize) -> usize {
    (at + n - 1) & !(n - 1)
}

/// A little-endian 32-bit integer at `at`, and where it ends.
#[inline(always)]
fn int32(b: &[u8], at: usize) -> Option<(u32, usize)> {
    let end = at.checked_add(4)?;
    Some((u32::from_le_bytes(b.get(at..end)?.try_into().ok()?), end))
}

/// A string at `at` (aligned there), its closing NUL left out, and where
/// it ends.
#[inline(always)]
fn text(b: &[u8], at: usize) -> Option<(&[u8], usize)> {
    let (n, start) = int32(b, align(at, 4))?;
    let end = start.checked_add(n as usize)?;
    let t = b.get(start..end)?;
    Some((t.strip_suffix(&[0]).unwrap_or(t), end))
}

#[cfg(test)]
mod tests {
    use super::super::{definitions, pool::by_slots, CHANGE_PATHS, JAZZY};
    use super::*;
    use std::path::Path;

    /// The fixture bag's log messages, and each node's name by uid.
    fn bag() -> (Vec<Vec<u8>>, Vec<Box<[u8]>>) {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rosbag");
        let tree = crate::xml::load_file(&dir.join("navigator.xml"), &Default::default())
            .unwrap()
            .tree;
        let named = (1..=tree.len() as Uid)
            .map(|u| super::super::bt_name(&tree, u).as_bytes().into())
            .collect();
        let bytes = std::fs::read(dir.join("two_goals/two_goals.mcap")).unwrap();
        let messages = mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(|m| m.unwrap().data.into_owned())
            .collect();
        (messages, named)
    }

    #[test]
    fn a_message_is_read_as_its_definition_reads_it_whatever_its_bytes() {
        let (messages, named) = bag();
        let (defs, _) = definitions(Some(JAZZY), None).unwrap();
        let flat = defs.flat("event_log", &CHANGE_PATHS).unwrap();
        let direct = Direct::of(&flat).expect("Jazzy's layout");
        let read = |data: &[u8]| {
            let mut out = Vec::new();
            direct.read(data, &named, &mut out).map(|_| out)
        };
        let by_definition = |data: &[u8]| {
            let mut out = Vec::new();
            by_slots(&flat, &named, data, &mut Vec::new(), &mut out).map(|_| out)
        };
        let mut plain = 0;
        for m in &messages {
            assert!(read(m).is_some());
            // Cut anywhere, and each byte changed: both read the same, or
            // neither reads it.
            let mut tries: Vec<Vec<u8>> = (0..m.len()).map(|n| m[..n].to_vec()).collect();
            for i in 0..m.len() {
                for b in [0, 1, 3, 0x41, 0x80, 0xff] {
                    let mut t = m.clone();
                    t[i] = b;
                    tries.push(t);
                }
            }
            for t in &tries {
                let (a, b) = (read(t), by_definition(t));
                plain += usize::from(a.is_some());
                assert_eq!(a, b, "{t:?}");
            }
        }
        assert!(plain > messages.len());
    }

    #[test]
    fn only_nav2s_layout_with_uids_is_read_directly() {
        let humble = definitions(Some(super::super::HUMBLE), None).unwrap().0;
        let flat = humble.flat("event_log", &CHANGE_PATHS).unwrap();
        assert!(Direct::of(&flat).is_none());
        let jazzy = definitions(Some(JAZZY), None).unwrap().0;
        let flat = jazzy.flat("event_log", &CHANGE_PATHS).unwrap();
        assert_eq!(Direct::of(&flat).unwrap().head, vec![4, 4]);
    }
}
