//! A robot that is running now: BehaviorTree.CPP 4's Groot2 publisher
//! (ZeroMQ, port 1667), watched without changing what the robot does (no
//! hook or breakpoint is ever inserted). Transitions are polled from the
//! server's recording buffer often enough that it never fills; the run so
//! far is a session built by the same code as a `.btlog`'s.

pub mod groot2;
pub mod zmtp;

use crate::logs::btlog::Record;
use crate::session::Session;
use crate::source::{Located, Warning};
use groot2::{Client, LiveError, SERVER_BUFFER};
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

/// A live run being watched.
pub struct Watch {
    pub endpoint: String,
    client: Option<Client>,
    /// The tree as the server sent it (XML with `_uid`s).
    pub xml: String,
    pub uuid: [u8; 16],
    /// The server's clock when recording started, µs since the epoch.
    t0: i64,
    pub records: Vec<Record>,
    pub gaps: Vec<Gap>,
}

/// A UUID as text.
pub fn uuid_text(u: &[u8; 16]) -> String {
    u.iter().map(|b| format!("{b:02x}")).collect()
}

impl Watch {
    /// Connects, reads the tree and starts recording.
    pub fn start(endpoint: &str) -> Result<Watch, LiveError> {
        let mut c = Client::connect(endpoint, TIMEOUT)?;
        let xml = c.tree_xml()?;
        let t0 = c.start_recording()?;
        Ok(Watch {
            endpoint: endpoint.to_string(),
            uuid: c.uuid,
            client: Some(c),
            xml,
            t0,
            records: Vec::new(),
            gaps: Vec::new(),
        })
    }

    pub fn connected(&self) -> bool {
        self.client.is_some()
    }

    /// Takes the transitions recorded since the last poll; how many. When
    /// the connection is gone, tries once to connect again (a robot that
    /// restarted has another tree UUID): either way the place is a gap.
    pub fn poll(&mut self) -> Result<usize, LiveError> {
        let Some(c) = self.client.as_mut() else {
            return self.reconnect().map(|()| 0);
        };
        let got = c.transitions().map(|ts| (ts, c.uuid));
        match got {
            Ok((ts, uuid)) => {
                if uuid != self.uuid {
                    self.gap("the robot restarted (its tree UUID changed)".into());
                    self.uuid = uuid;
                }
                if ts.len() >= SERVER_BUFFER {
                    self.gap(format!("the server's buffer of {SERVER_BUFFER} transitions was full: older ones may be lost"));
                }
                let n = ts.len();
                for t in ts {
                    let offset = self.records.len();
                    self.records.push(Record {
                        time_us: self.t0 + t.time_us,
                        uid: t.uid,
                        status: t.status,
                        offset,
                    });
                }
                Ok(n)
            }
            Err(e) => {
                self.client = None;
                self.gap(format!("the connection dropped ({e})"));
                Err(e)
            }
        }
    }

    fn gap(&mut self, why: String) {
        let at = self.records.len();
        if self.gaps.last().is_none_or(|g| g.at != at) {
            self.gaps.push(Gap { at, why });
        }
    }

    fn reconnect(&mut self) -> Result<(), LiveError> {
        let mut c = Client::connect(&self.endpoint, TIMEOUT)?;
        let xml = c.tree_xml()?;
        if xml != self.xml {
            return Err(LiveError(format!(
                "{}: the robot now runs another tree; watch it anew",
                self.endpoint
            )));
        }
        self.t0 = c.start_recording()?;
        if c.uuid != self.uuid {
            self.gap("the robot restarted (its tree UUID changed)".into());
            self.uuid = c.uuid;
        }
        self.client = Some(c);
        Ok(())
    }

    /// The run so far as a session (ticks reconstructed as for a `.btlog`),
    /// with each gap as a warning at its place.
    pub fn session(&self) -> Result<Session, Located> {
        let name = std::path::PathBuf::from(format!("groot2://{}", self.endpoint));
        let mut s = crate::logs::open_live(&name, &self.xml, &self.records)?;
        for g in &self.gaps {
            s.warnings.push(Warning {
                location: format!("{}: transition {}", name.display(), g.at + 1),
                message: format!("gap: {}", g.why),
            });
        }
        Ok(s)
    }
}
