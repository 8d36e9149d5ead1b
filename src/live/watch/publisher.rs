//! Watching a BehaviorTree.CPP 3 robot (Groot 1's protocol): its
//! publisher's messages taken into the watch, each lost or broken one a
//! gap, the states after it taken again. The protocol itself is
//! `live::groot1`'s.

use super::*;
use crate::live::groot1::{
    befores, fingerprint, follows, parse_message, publisher_endpoint, states_before, FIRST_WAIT,
    NO_BLACKBOARD,
};
use crate::live::groot2::Transition;
use crate::live::sub::Sub;
use std::collections::HashMap;
use std::time::Duration;

/// A connection to a BehaviorTree.CPP 3 robot's publisher, and what its
/// messages said so far.
pub(in crate::live) struct Link {
    /// None once the connection dropped, until it is made again.
    pub(super) sub: Option<Sub>,
    /// Each node's status, as the messages left it.
    known: HashMap<u32, Status>,
    /// No message has come yet.
    first: bool,
    /// The place is a gap already (said when the connection dropped, or
    /// when a message could not be read): the next statuses that do not
    /// follow are taken without another.
    quiet: bool,
}

impl Watch {
    /// Watches a BehaviorTree.CPP 3 robot whose server sent `tree`: its
    /// publisher at `publisher` (see `publisher_endpoint`). Its first
    /// message, when it comes soon, gives the nodes' states.
    pub(super) fn start_groot1(
        endpoint: &str,
        publisher: Option<u16>,
        tree: &[u8],
    ) -> Result<Watch, LiveError> {
        let source = Protocol::Groot1.source(endpoint);
        let xml = crate::logs::fbl::tree_xml(&source, tree, 0, "tree the server sent").map_err(|e| {
            LiveError(format!(
                "{endpoint}: the reply is not a Groot2 reply, nor a BehaviorTree.CPP 3 tree ({}): is this a BehaviorTree.CPP Groot2Publisher or PublisherZMQ?",
                e.message
            ))
        })?;
        let sub = connect_publisher(endpoint, publisher)?;
        let mut w = Watch::new(endpoint, Protocol::Groot1, xml, fingerprint(tree), 0);
        w.publisher = publisher;
        w.notes.push(NO_BLACKBOARD.to_string());
        w.groot1 = Some(Link {
            sub: Some(sub),
            known: HashMap::new(),
            first: true,
            quiet: false,
        });
        w.poll_groot1(FIRST_WAIT)?;
        Ok(w)
    }

    /// Takes the messages that came; how many transitions they held.
    pub(super) fn poll_groot1(&mut self, wait: Duration) -> Result<usize, LiveError> {
        let Some(sub) = self.groot1.as_mut().and_then(|l| l.sub.as_mut()) else {
            return self.reconnect_groot1().map(|()| 0);
        };
        match sub.receive(wait) {
            Ok(messages) => Ok(messages.iter().map(|m| self.take_message(m)).sum()),
            Err(e) => {
                if let Some(l) = self.groot1.as_mut() {
                    l.sub = None;
                    l.quiet = true;
                }
                let e = LiveError(e.to_string());
                if self.end_of_run() {
                    return Ok(0);
                }
                self.gap(format!("the connection dropped ({e}); btx takes every node's state from the robot's first message once it reconnects"));
                Err(e)
            }
        }
    }

    /// Keeps one message's transitions, after a gap and the states it
    /// carries when those do not follow from what came before.
    fn take_message(&mut self, parts: &[Vec<u8>]) -> usize {
        let m = match parts {
            [one] => parse_message(one),
            _ => Err(format!("a message in {} parts, not one", parts.len())),
        };
        let Some(link) = self.groot1.as_mut() else {
            return 0;
        };
        let m = match m {
            Ok(m) => m,
            Err(_) if link.quiet => return 0,
            Err(why) => {
                link.quiet = true;
                self.gap(format!(
                    "the publisher sent a message btx cannot read ({why}): the transitions it held are lost; btx takes every node's state from the next"
                ));
                return 0;
            }
        };
        let (first, quiet) = (link.first, link.quiet);
        link.first = false;
        link.quiet = false;
        if !follows(&link.known, &m) {
            link.known = states_before(&m);
            let states = befores(&link.known);
            let at = self.received();
            self.resyncs.push((at, states));
            if first {
                self.gaps.push(Gap {
                    at,
                    why: "btx attached to a robot that had been running: before this, each node's state then is known, not its transitions".into(),
                });
                self.gap_count += 1;
            } else if !quiet {
                self.gap(format!(
                    "messages of the publisher were lost (the statuses it sent do not follow from the transitions before){RESYNCED}"
                ));
            }
        }
        let link = self.groot1.as_mut().expect("connected");
        for (r, _) in &m.transitions {
            link.known.insert(r.uid, r.status);
        }
        self.keep(m.transitions.into_iter().map(|(r, _)| Transition {
            time_us: r.time_us,
            uid: r.uid,
            status: r.status,
        }))
    }

    /// Every node's state as the publisher's messages left it (the nodes
    /// not IDLE), once one came.
    pub(super) fn groot1_now(&self) -> Option<Vec<Before>> {
        let l = self.groot1.as_ref().filter(|l| !l.first)?;
        Some(befores(&l.known))
    }

    /// Connects again: the same tree, then its publisher.
    fn reconnect_groot1(&mut self) -> Result<(), LiveError> {
        let mut c = super::groot2::Client::connect(&self.endpoint, TIMEOUT)?;
        match c.tree()? {
            super::groot2::Served::Groot1(tree) if fingerprint(&tree) == self.uuid => {}
            super::groot2::Served::Groot1(_) => {
                return Err(LiveError(format!(
                    "{}: the robot now runs another tree; watch it anew",
                    self.endpoint
                )))
            }
            super::groot2::Served::Xml(_) => {
                return Err(LiveError(format!(
                    "{}: the robot now speaks Groot2 (BehaviorTree.CPP 4); watch it anew",
                    self.endpoint
                )))
            }
        }
        let sub = connect_publisher(&self.endpoint, self.publisher)?;
        if let Some(l) = self.groot1.as_mut() {
            l.sub = Some(sub);
        }
        Ok(())
    }
}

fn connect_publisher(endpoint: &str, publisher: Option<u16>) -> Result<Sub, LiveError> {
    let at = publisher_endpoint(endpoint, publisher)?;
    Sub::connect(&at, TIMEOUT).map_err(|e| {
        LiveError(format!(
            "{e} (the publisher of the BehaviorTree.CPP 3 robot at {endpoint}{})",
            if publisher.is_some() {
                String::new()
            } else {
                "; if it publishes on another port, give it with --publisher-port".into()
            }
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::live::groot1::tests::message;

    /// A watch of a three-node tree fed messages by hand.
    fn watching() -> Watch {
        let mut w = Watch::new("robot:1667", Protocol::Groot1, String::new(), [0; 16], 0);
        w.groot1 = Some(Link {
            sub: None,
            known: HashMap::new(),
            first: true,
            quiet: false,
        });
        w
    }

    #[test]
    fn a_lost_or_broken_message_is_a_gap_and_the_next_states_are_taken() {
        let mut w = watching();
        // The first message: from all IDLE, nothing to say.
        let n = w.take_message(&[message(
            &[(1, 0), (2, 0)],
            &[(1, 0, 1, 0, 1), (1, 0, 2, 0, 1)],
        )]);
        assert_eq!((n, w.gaps.len(), w.resyncs.len()), (2, 0, 0));
        // A message went missing: node 2 SUCCEEDED and went IDLE unseen.
        w.take_message(&[message(&[(1, 1), (2, 0)], &[(2, 0, 2, 0, 1)])]);
        assert_eq!(w.gaps.len(), 1);
        assert!(
            w.gaps[0]
                .why
                .contains("messages of the publisher were lost"),
            "{:?}",
            w.gaps
        );
        assert_eq!(w.gaps[0].at, 2);
        assert_eq!(
            w.resyncs,
            vec![(2, befores(&[(1, Status::Running)].into()))]
        );
        // A broken message: a gap, and the states after it are taken
        // without another.
        assert_eq!(w.take_message(&[vec![1, 2, 3]]), 0);
        assert_eq!(w.take_message(&[b"a".to_vec(), b"b".to_vec()]), 0);
        assert_eq!(w.gaps.len(), 2, "{:?}", w.gaps);
        assert!(w.gaps[1].why.contains("cannot read"), "{:?}", w.gaps);
        w.take_message(&[message(&[(1, 2), (2, 0)], &[])]);
        assert_eq!((w.gaps.len(), w.resyncs.len()), (2, 2));
        // Every transition kept is a record of the run, in order.
        let uids: Vec<u32> = w.records.iter().map(|r| r.uid).collect();
        assert_eq!(uids, vec![1, 2, 2]);
    }

    #[test]
    fn attached_to_a_running_robot_the_first_states_are_a_gap_at_zero() {
        let mut w = watching();
        w.take_message(&[message(&[(1, 1), (2, 1)], &[(1, 0, 2, 1, 2)])]);
        assert_eq!(w.gaps.len(), 1);
        assert!(w.gaps[0]
            .why
            .contains("attached to a robot that had been running"));
        assert_eq!(w.resyncs[0].0, 0);
        assert_eq!(w.groot1_now().unwrap().len(), 2);
    }
}
