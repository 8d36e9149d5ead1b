//! A robot that runs BehaviorTree.CPP 3 (Nav2 Humble), watched as Groot 1
//! watched it. Its `PublisherZMQ` answers any request on the server port
//! with the tree (the flatbuffer an `.fbl` holds), and publishes on the
//! port below, at most about 25 times a second, every node's status and
//! the transitions since its last message (each an `.fbl` record). Nothing
//! is numbered: a lost message shows as statuses that do not follow from
//! the transitions before them (`follows`). There is no blackboard.

use super::groot2::LiveError;
use crate::logs::btlog::Record;
use crate::run::Status;
use crate::session::Before;
use std::collections::HashMap;
use std::time::Duration;

/// What a BehaviorTree.CPP 3 robot cannot tell, said once when watching
/// begins.
pub const NO_BLACKBOARD: &str = "this robot runs BehaviorTree.CPP 3 (Groot 1's protocol), which does not send the blackboard: its entries cannot be shown";

/// How long watching waits for the publisher's first message, which brings
/// the nodes' states (a robot whose tree does not tick sends none).
pub(super) const FIRST_WAIT: Duration = Duration::from_millis(600);

/// Said when the publisher sent nothing while btx waited for the states.
pub const NO_MESSAGE: &str = "the robot published nothing within 0.6 s (a BehaviorTree.CPP 3 robot publishes only when a node's status changes): its nodes' states are not known, and are shown IDLE";

/// How long one poll waits for a message.
pub(super) const POLL_WAIT: Duration = Duration::from_millis(20);

/// One message of the publisher.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// Every node's status when the publisher sent its previous message
    /// (it builds the next message's statuses as it sends one).
    pub states: Vec<(u32, Status)>,
    /// The transitions since, each with the status before it.
    pub transitions: Vec<(Record, Status)>,
}

/// `u32 n | n bytes of (u16 uid, u8 status) | u32 k | k records of 12 bytes`.
pub fn parse_message(b: &[u8]) -> Result<Message, String> {
    let u32_at = |at: usize| {
        b.get(at..at + 4)
            .map(|x| u32::from_le_bytes(x.try_into().expect("4 bytes")) as usize)
    };
    let n = u32_at(0).ok_or("a message shorter than its first size field")?;
    let states_end = 4usize
        .checked_add(n)
        .filter(|&e| e <= b.len() && n % 3 == 0)
        .ok_or_else(|| {
            format!(
                "a message says {n} bytes of statuses (3 a node), but has {} after the field",
                b.len().saturating_sub(4)
            )
        })?;
    let mut states = Vec::with_capacity(n / 3);
    for (i, s) in b[4..states_end].chunks_exact(3).enumerate() {
        let uid = u32::from(u16::from_le_bytes([s[0], s[1]]));
        let status = Status::from_code(s[2])
            .filter(|s| *s != Status::Skipped)
            .ok_or_else(|| {
                format!(
                    "byte {}: a status byte {} is not 0 to 3",
                    4 + 3 * i + 2,
                    s[2]
                )
            })?;
        states.push((uid, status));
    }
    let k = u32_at(states_end).ok_or("a message ends before its count of transitions")?;
    let start = states_end + 4;
    if b.len() - start != k.saturating_mul(12) {
        return Err(format!(
            "a message says {k} transitions (12 bytes each), but has {} bytes for them",
            b.len() - start
        ));
    }
    let transitions = b[start..]
        .chunks_exact(12)
        .enumerate()
        .map(|(i, r)| {
            let at = start + 12 * i;
            crate::logs::fbl::record(r.try_into().expect("12 bytes"), at)
                .map_err(|m| format!("byte {}: {m}", at + 10))
        })
        .collect::<Result<_, _>>()?;
    Ok(Message {
        states,
        transitions,
    })
}

/// The nodes' states before a message's transitions: its statuses, and
/// for each node with transitions in it, the status before its first.
/// BehaviorTree.CPP 3 sends the statuses it read when it sent its previous
/// message: the states before, but for a node whose status changed a
/// moment before its transition was queued. btview's mock sends those
/// after. The status each record says it left settles both.
pub fn states_before(m: &Message) -> HashMap<u32, Status> {
    let mut before: HashMap<u32, Status> = m.states.iter().copied().collect();
    let mut seen = std::collections::HashSet::new();
    for (r, prev) in &m.transitions {
        if seen.insert(r.uid) {
            before.insert(r.uid, *prev);
        }
    }
    before
}

/// Whether a message follows from the states known (a node not known is
/// IDLE): nothing was lost between them.
pub fn follows(known: &HashMap<u32, Status>, m: &Message) -> bool {
    states_before(m)
        .iter()
        .all(|(u, s)| known.get(u).copied().unwrap_or(Status::Idle) == *s)
}

/// States as a resync holds them: the nodes not IDLE, by uid (a
/// completed status is the node's last completion too).
pub(super) fn befores(states: &HashMap<u32, Status>) -> Vec<Before> {
    let mut states: Vec<(u32, Status)> = states.iter().map(|(&u, &s)| (u, s)).collect();
    states.sort_unstable();
    states
        .into_iter()
        .filter(|(_, s)| *s != Status::Idle)
        .map(|(uid, status)| Before {
            uid,
            status,
            done: status.is_completed().then_some(status),
        })
        .collect()
}

/// The publisher's endpoint: the server's host, and `port` or the port
/// below the server's (BehaviorTree.CPP 3's defaults are 1666 and 1667).
pub fn publisher_endpoint(server: &str, port: Option<u16>) -> Result<String, LiveError> {
    let (host, server_port) = server
        .rsplit_once(':')
        .and_then(|(h, p)| Some((h, p.parse::<u16>().ok()?)))
        .ok_or_else(|| LiveError(format!("{server}: not HOST:PORT")))?;
    let port = match port {
        Some(p) => p,
        None => server_port.checked_sub(1).ok_or_else(|| {
            LiveError(format!(
                "{server}: the publisher's port is the one below the server's, and there is none below 0: give it with --publisher-port"
            ))
        })?,
    };
    Ok(format!("{host}:{port}"))
}

/// A 16-byte fingerprint of the tree, in place of the UUID a Groot2
/// server gives its tree (two FNV-1a hashes).
pub fn fingerprint(tree: &[u8]) -> [u8; 16] {
    let h = |seed: u64| {
        tree.iter()
            .fold(seed, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100000001b3))
    };
    let mut out = [0u8; 16];
    out[..8].copy_from_slice(&h(0xcbf29ce484222325).to_be_bytes());
    out[8..].copy_from_slice(&h(0x84222325cbf29ce4).to_be_bytes());
    out
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A publisher's message: its states, then its transitions.
    pub(in crate::live) fn message(
        states: &[(u16, u8)],
        records: &[(u32, u32, u16, u8, u8)],
    ) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(&(3 * states.len() as u32).to_le_bytes());
        for &(u, s) in states {
            b.extend_from_slice(&u.to_le_bytes());
            b.push(s);
        }
        b.extend_from_slice(&(records.len() as u32).to_le_bytes());
        for &(sec, usec, u, p, s) in records {
            b.extend_from_slice(&sec.to_le_bytes());
            b.extend_from_slice(&usec.to_le_bytes());
            b.extend_from_slice(&u.to_le_bytes());
            b.extend_from_slice(&[p, s]);
        }
        b
    }

    #[test]
    fn a_message_is_read_as_the_publisher_writes_it() {
        let b = message(&[(1, 1), (2, 0)], &[(10, 5, 2, 0, 1), (10, 6, 2, 1, 2)]);
        let m = parse_message(&b).unwrap();
        assert_eq!(m.states, vec![(1, Status::Running), (2, Status::Idle)]);
        assert_eq!(m.transitions.len(), 2);
        assert_eq!(m.transitions[1].0.time_us, 10_000_006);
        assert_eq!(m.transitions[1].0.status, Status::Success);
        assert_eq!(m.transitions[1].1, Status::Running);
        for cut in [0, 3, 7, 10, b.len() - 1] {
            assert!(parse_message(&b[..cut]).is_err(), "cut at {cut}");
        }
        let mut bad = b.clone();
        bad[6] = 7;
        assert!(parse_message(&bad).unwrap_err().contains("status byte 7"));
    }

    #[test]
    fn a_message_follows_when_its_states_before_are_the_known_ones() {
        let known: HashMap<u32, Status> = [(1, Status::Running)].into();
        let m = |states: &[(u16, u8)], recs: &[(u32, u32, u16, u8, u8)]| {
            parse_message(&message(states, recs)).unwrap()
        };
        assert!(follows(&known, &m(&[(1, 1), (2, 0)], &[])));
        // Node 2's status was read as it changed, its transition queued
        // after (BehaviorTree.CPP 3); or the statuses are those after the
        // transitions (btview's mock).
        assert!(follows(&known, &m(&[(1, 1), (2, 1)], &[(1, 0, 2, 0, 1)])));
        assert!(follows(
            &known,
            &m(&[(1, 2), (2, 1)], &[(1, 0, 2, 0, 1), (1, 0, 1, 1, 2)])
        ));
        // A transition nobody sent: node 1 SUCCESS, known RUNNING.
        assert!(!follows(&known, &m(&[(1, 2), (2, 0)], &[(1, 0, 2, 0, 1)])));
        // From a status that is not the known one.
        assert!(!follows(&known, &m(&[(1, 1)], &[(1, 0, 1, 0, 1)])));
        assert!(!follows(&HashMap::new(), &m(&[(1, 1)], &[])));
    }

    #[test]
    fn the_publisher_is_on_the_port_below_unless_given() {
        assert_eq!(
            publisher_endpoint("10.0.0.2:1667", None).unwrap(),
            "10.0.0.2:1666"
        );
        assert_eq!(
            publisher_endpoint("[::1]:1667", Some(2000)).unwrap(),
            "[::1]:2000"
        );
        assert!(publisher_endpoint("h:0", None).is_err());
    }
}
