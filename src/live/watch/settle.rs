//! Where a read of every node's state belongs among the transitions.
//!
//! After a loss btx reads every node's state (`S`), then the transitions
//! (`t`). The server writes a node's state and its transition under one
//! lock, so the read is the state after some first part of the
//! transitions that come next, though which part is not said: a busy
//! robot makes many between the two requests. Put before all of them, as
//! btx did, a node that moved meanwhile would start from the state it
//! reached later (a Sequence that went RUNNING→SUCCESS recorded as
//! IDLE→SUCCESS).
//!
//! The read is placed after the longest first part it can follow: every
//! node moved in that part ends as the read says, and each node's next
//! transition changes what the read says (BehaviorTree.CPP tells only
//! changes). The true place is one of those parts, so the longest is at
//! or after it; and at any such part every node is as the read says (one
//! moved since ends where the read puts it, one not moved is as it was).
//! From there each transition's status before it is exact.

use super::groot2::{self, Transition};
use crate::run::Status;
use std::collections::HashMap;

/// After how many of `ts` the state `codes` (an `S` reply: uid and code,
/// IDLE as 10 + the status it left) is exact; `None` when after none of
/// them (the read cannot come from these transitions).
pub(super) fn settled_at(codes: &[(u32, u8)], ts: &[Transition]) -> Option<usize> {
    let read: HashMap<u32, u8> = codes.iter().copied().collect();
    let ended = ends_as_read(&read, ts);
    let moves = moves_from_read(&read, ts);
    (0..=ts.len()).rev().find(|&p| ended[p] && moves[p])
}

/// Per first part of `ts` (0 to all), whether every node it moved ends
/// with the code the read says.
fn ends_as_read(read: &HashMap<u32, u8>, ts: &[Transition]) -> Vec<bool> {
    // Per node moved: its last status, and the one before it if seen.
    let mut last: HashMap<u32, (Status, Option<Status>)> = HashMap::new();
    let mut wrong = 0usize;
    let mut out = Vec::with_capacity(ts.len() + 1);
    out.push(true);
    for t in ts {
        let before = last.get(&t.uid).copied();
        let now = (t.status, before.map(|b| b.0));
        let agrees = |s: Option<(Status, Option<Status>)>| {
            s.is_none_or(|s| read.get(&t.uid).is_none_or(|&c| code_agrees(c, s)))
        };
        match (agrees(before), agrees(Some(now))) {
            (true, false) => wrong += 1,
            (false, true) => wrong -= 1,
            _ => {}
        }
        last.insert(t.uid, now);
        out.push(wrong == 0);
    }
    out
}

/// Whether a node whose last status is `s.0` (after `s.1`, if seen) can
/// have the code `code`.
fn code_agrees(code: u8, s: (Status, Option<Status>)) -> bool {
    match s {
        (Status::Idle, Some(before)) => code == groot2::code_after(before.code(), Status::Idle),
        // IDLE after a status not seen: any IDLE code.
        (Status::Idle, None) => code >= 10,
        (status, _) => code == status.code(),
    }
}

/// Per first part of `ts` (0 to all), whether each node's next transition
/// after it changes the status the read says.
fn moves_from_read(read: &HashMap<u32, u8>, ts: &[Transition]) -> Vec<bool> {
    let mut next: HashMap<u32, Status> = HashMap::new();
    let mut still = 0usize;
    let mut out = vec![true; ts.len() + 1];
    let same = |uid: u32, s: Option<Status>| {
        s.is_some_and(|s| {
            read.get(&uid)
                .is_some_and(|&c| groot2::status_of(c) == Some(s))
        })
    };
    for (i, t) in ts.iter().enumerate().rev() {
        let was = next.insert(t.uid, t.status);
        match (same(t.uid, was), same(t.uid, Some(t.status))) {
            (true, false) => still -= 1,
            (false, true) => still += 1,
            _ => {}
        }
        out[i] = still == 0;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(uid: u32, status: Status) -> Transition {
        Transition {
            time_us: 0,
            uid,
            status,
        }
    }

    use Status::{Idle, Running, Success};

    #[test]
    fn a_read_is_placed_after_the_transitions_it_already_holds() {
        // A Sequence (#1) of one leaf (#2), as the robot moved them.
        let ts = [
            t(1, Running),
            t(2, Success),
            t(1, Success),
            t(2, Idle),
            t(1, Idle),
        ];
        // Read once the leaf had succeeded, before the Sequence did.
        assert_eq!(settled_at(&[(1, 1), (2, 2)], &ts), Some(2));
        // Read once the Sequence started, the leaf IDLE since its last
        // success.
        assert_eq!(settled_at(&[(1, 1), (2, 12)], &ts), Some(1));
        // Both IDLE after a success, before all of them or after: the
        // state is the same at both places, and the last is taken.
        assert_eq!(settled_at(&[(1, 12), (2, 12)], &ts), Some(5));
        assert_eq!(settled_at(&[(1, 12), (2, 12)], &[]), Some(0));
    }

    #[test]
    fn of_places_the_read_may_come_from_the_last_is_taken() {
        // The leaf goes SUCCESS then IDLE twice over: the read (#1
        // RUNNING, #2 IDLE after SUCCESS) fits after 1, 3 and 5 of them.
        let ts = [
            t(1, Running),
            t(2, Success),
            t(2, Idle),
            t(2, Success),
            t(2, Idle),
            t(1, Success),
        ];
        assert_eq!(settled_at(&[(1, 1), (2, 12)], &ts), Some(5));
    }

    #[test]
    fn a_read_no_part_of_the_transitions_leads_to_has_no_place() {
        // #2 RUNNING and #1 IDLE: #1 had not started when #2 was read
        // running, yet #1 starts first.
        let ts = [t(1, Running), t(2, Running)];
        assert_eq!(settled_at(&[(1, 0), (2, 1)], &ts), None);
    }
}
