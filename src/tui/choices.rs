//! Several runs behind one explorer: a rosbag's goals, or several robots
//! watched at once. The picker (`R`) lists each with how it stands;
//! picking one shows its run, and the others go on (each robot's feed is
//! still read and its session written as the run comes).

use crate::live::Feed;
use crate::session::Session;

/// One run of a log: what the picker says of it, and the run while it is
/// not the one shown.
pub struct RunChoice {
    pub label: String,
    pub title: String,
    pub session: Option<Session>,
}

/// One robot: its endpoint, and its feed while it is not the one shown
/// (none either when it could not be reached at the start: `unreachable`).
pub struct RobotChoice {
    pub endpoint: String,
    pub feed: Option<Feed>,
    pub unreachable: Option<String>,
}

pub enum Choices {
    Runs {
        runs: Vec<RunChoice>,
        current: usize,
    },
    Robots {
        robots: Vec<RobotChoice>,
        current: usize,
    },
}

impl Choices {
    /// The runs of a log, `(label, title, session)` each, showing `current`
    /// (its session is the explorer's).
    pub fn runs(runs: Vec<(String, String, Session)>, current: usize) -> Choices {
        Choices::Runs {
            runs: runs
                .into_iter()
                .map(|(label, title, s)| RunChoice {
                    label,
                    title,
                    session: Some(s),
                })
                .collect(),
            current,
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Choices::Runs { runs, .. } => runs.len(),
            Choices::Robots { robots, .. } => robots.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn current(&self) -> usize {
        match self {
            Choices::Runs { current, .. } | Choices::Robots { current, .. } => *current,
        }
    }

    /// What the picker's window is titled.
    pub fn title(&self) -> &'static str {
        match self {
            Choices::Runs { .. } => " the log's runs · Enter shows one · Esc ",
            Choices::Robots { .. } => " robots · Enter shows one · Esc ",
        }
    }

    /// One line a choice, how it stands now; `shown` is the feed of the
    /// robot on screen (the explorer holds it).
    pub fn lines(&self, shown: Option<&Feed>) -> Vec<String> {
        match self {
            Choices::Runs { runs, .. } => runs.iter().map(|r| r.label.clone()).collect(),
            Choices::Robots { robots, current } => robots
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let feed = if i == *current {
                        shown
                    } else {
                        r.feed.as_ref()
                    };
                    match (feed, &r.unreachable) {
                        (Some(f), _) => format!(
                            "{}  {} · {} transitions · {}",
                            r.endpoint,
                            f.glance(),
                            f.status.transitions,
                            f.status.gaps_text()
                        ),
                        (None, Some(e)) => format!("{}  unreachable ({e})", r.endpoint),
                        (None, None) => r.endpoint.clone(),
                    }
                })
                .collect(),
        }
    }

    /// Takes what the robots not shown sent, writing it to their sessions.
    pub fn poll(&mut self) {
        if let Choices::Robots { robots, .. } = self {
            for f in robots.iter_mut().filter_map(|r| r.feed.as_mut()) {
                f.poll_for(std::time::Duration::from_millis(30));
            }
        }
    }
}
