//! Node statuses, as BehaviorTree.CPP numbers and names them.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum Status {
    #[default]
    Idle,
    Running,
    Success,
    Failure,
    Skipped,
}

impl Status {
    pub const ALL: [Status; 5] = [
        Status::Idle,
        Status::Running,
        Status::Success,
        Status::Failure,
        Status::Skipped,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Status::Idle => "IDLE",
            Status::Running => "RUNNING",
            Status::Success => "SUCCESS",
            Status::Failure => "FAILURE",
            Status::Skipped => "SKIPPED",
        }
    }

    /// The library's code (`.btlog` status byte).
    pub fn code(self) -> u8 {
        match self {
            Status::Idle => 0,
            Status::Running => 1,
            Status::Success => 2,
            Status::Failure => 3,
            Status::Skipped => 4,
        }
    }

    pub fn from_code(c: u8) -> Option<Status> {
        Status::ALL.get(c as usize).copied()
    }

    pub fn parse(s: &str) -> Option<Status> {
        // As robots write them first: a rosbag gives two a transition.
        if let Some(&x) = Status::ALL.iter().find(|x| x.as_str() == s) {
            return Some(x);
        }
        Status::ALL
            .into_iter()
            .find(|x| x.as_str().eq_ignore_ascii_case(s.trim()))
    }

    /// `parse` of text as bytes: a bag's statuses are matched before
    /// they are checked as UTF-8.
    pub fn parse_bytes(b: &[u8]) -> Option<Status> {
        // Matched as written first: a bag has millions of them.
        match b {
            b"RUNNING" => Some(Status::Running),
            b"SUCCESS" => Some(Status::Success),
            b"FAILURE" => Some(Status::Failure),
            b"IDLE" => Some(Status::Idle),
            b"SKIPPED" => Some(Status::Skipped),
            _ => std::str::from_utf8(b).ok().and_then(Status::parse),
        }
    }

    /// How a node ended, by its last transition (`prev` to `self`): its
    /// completion, also when it was reset to IDLE right after, as
    /// BehaviorTree.CPP resets a finished tree.
    pub fn ended(self, prev: Status) -> Option<Status> {
        match (prev, self) {
            (_, s) if s.is_completed() => Some(s),
            (p, Status::Idle) if p.is_completed() => Some(p),
            _ => None,
        }
    }

    /// SUCCESS or FAILURE.
    pub fn is_completed(self) -> bool {
        matches!(self, Status::Success | Status::Failure)
    }

    /// Neither IDLE nor SKIPPED.
    pub fn is_active(self) -> bool {
        !matches!(self, Status::Idle | Status::Skipped)
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.as_str())
    }
}

impl serde::Serialize for Status {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> serde::Deserialize<'de> for Status {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        Status::parse(&s).ok_or_else(|| serde::de::Error::custom(format!("unknown status {s:?}")))
    }
}
