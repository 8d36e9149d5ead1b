//! A robot that is running now: BehaviorTree.CPP 4's Groot2 publisher
//! (ZeroMQ, port 1667), watched without changing what the robot does (no
//! hook or breakpoint is ever inserted). Transitions are polled from the
//! server's recording buffer often enough that it never fills; the run so
//! far is a session built by the same code as a `.btlog`'s.

pub mod groot1;
pub mod groot2;
pub mod recorder;
pub mod rep;
pub mod serve;
pub mod sub;
pub mod zmtp;

mod feed;
mod watch;

pub use feed::*;
pub use watch::*;

use std::time::Duration;

/// How long a request may take before the server counts as gone (a
/// message naming the endpoint comes within 2 s).
pub const TIMEOUT: Duration = Duration::from_millis(1500);

/// A place in the run where transitions may be missing, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Gap {
    /// Transitions received before it.
    pub at: usize,
    pub why: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Status;
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    use std::sync::Arc;

    /// A Groot2 server of a two-node tree (`T`, `r`), whose `S` replies
    /// are `before` until the first `t` reply with records was sent and
    /// `after` from then, and whose `t` replies are `second` then `third`
    /// (the first, taken when btx attaches, and those after are empty).
    fn scripted_server(
        before: Vec<u8>,
        after: Vec<u8>,
        second: Vec<u8>,
        third: Vec<u8>,
    ) -> (String, Arc<AtomicBool>) {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = l.local_addr().unwrap().to_string();
        let stop = Arc::new(AtomicBool::new(false));
        let ts = Arc::new(AtomicUsize::new(0));
        let answer: zmtp::Answer = Arc::new(move |parts: &[Vec<u8>]| {
            let mut h = parts[0].clone();
            h.extend_from_slice(&[7; 16]);
            let body = match parts[0][1] {
                b'T' => b"<root/>".to_vec(),
                b'r' => b"1700000000000000".to_vec(),
                b'S' if ts.load(Ordering::SeqCst) < 2 => before.clone(),
                b'S' => after.clone(),
                b't' => match ts.fetch_add(1, Ordering::SeqCst) {
                    1 => second.clone(),
                    2 => third.clone(),
                    _ => Vec::new(),
                },
                _ => Vec::new(),
            };
            vec![h, body]
        });
        let halt = Arc::clone(&stop);
        std::thread::spawn(move || rep::serve_rep(l, answer, &[], halt));
        (addr, stop)
    }

    /// Records of a `t` reply: uid and status each.
    fn records(of: &[(u16, u8)]) -> Vec<u8> {
        let mut out = Vec::new();
        for &(uid, status) in of {
            out.extend_from_slice(&1_000u64.to_le_bytes()[..6]);
            out.extend_from_slice(&uid.to_le_bytes());
            out.push(status);
        }
        out
    }

    /// A server whose second `t` reply holds a zeroed record between two
    /// whole ones, as BehaviorTree.CPP 4.8's publisher sends when its
    /// buffer grows while it answers; `S` then says where the lost
    /// transition left the nodes (the root RUNNING, the leaf SUCCESS).
    fn racing_server() -> (String, Arc<AtomicBool>) {
        let second = [records(&[(1, 1)]), vec![0; 9], records(&[(2, 1)])].concat();
        scripted_server(
            vec![1, 0, 10, 2, 0, 10],
            vec![1, 0, 1, 2, 0, 2],
            second,
            Vec::new(),
        )
    }

    #[test]
    fn zeroed_records_are_a_gap_after_which_every_nodes_state_is_read_again() {
        let (addr, stop) = racing_server();
        let mut w = Watch::start(&addr, None).unwrap();
        assert_eq!(w.poll().unwrap(), 3);
        let uids: Vec<u32> = w.records.iter().map(|r| r.uid).collect();
        assert_eq!(uids, vec![1, 2]);
        assert_eq!(w.gaps.len(), 1, "{:?}", w.gaps);
        assert!(
            w.gaps[0].why.contains("1 zeroed records") && w.gaps[0].why.ends_with(RESYNCED),
            "{:?}",
            w.gaps
        );
        // After the batch, the states the lost transition left.
        let (at, states) = w.resyncs.last().unwrap();
        assert_eq!(*at, 2);
        assert!(states
            .iter()
            .any(|b| b.uid == 2 && b.status == Status::Success));
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// A server of a Sequence (#1) of one leaf (#2) that fills its buffer
    /// of 1,000 once, and went on between btx's two requests after: its
    /// `S` reply (the Sequence RUNNING, the leaf SUCCESS) is the state
    /// after the first two transitions of the `t` reply that follows.
    fn busy_server() -> (String, Arc<AtomicBool>) {
        // RUNNING, the leaf's SUCCESS, the Sequence's, both reset.
        let cycle = [(1, 1), (2, 2), (1, 2), (2, 0), (1, 0)];
        scripted_server(
            vec![1, 0, 10, 2, 0, 10],
            vec![1, 0, 1, 2, 0, 2],
            records(&cycle.repeat(200)),
            records(&[cycle.as_slice(), &[(1, 1)]].concat()),
        )
    }

    #[test]
    fn a_read_after_a_full_buffer_is_placed_where_the_robot_was_when_it_answered() {
        let (addr, stop) = busy_server();
        let mut w = Watch::start(&addr, None).unwrap();
        assert_eq!(w.poll().unwrap(), 1006);
        assert!(w
            .gaps
            .iter()
            .any(|g| g.at == 0 && g.why.contains("was full")));
        // Not after the 1,000, where btx asked: the robot had moved two
        // more by then.
        let (at, states) = w.resyncs.last().unwrap();
        assert_eq!(*at, 1002);
        let leaf = states.iter().find(|b| b.uid == 2).unwrap();
        assert_eq!(leaf.status, Status::Success);
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}
