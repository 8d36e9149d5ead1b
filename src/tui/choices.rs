//! Several runs behind one explorer: a rosbag's goals, or several robots
//! watched at once. The picker (`R`) lists each with how it stands;
//! picking one shows its run, and the others go on (each robot's feed is
//! still read and its session written as the run comes).

use super::app::{App, Overlay};
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

impl App {
    /// `R`: the picker, when there is more than one run to pick from.
    pub(crate) fn open_picker(&mut self) {
        match &self.choices {
            Some(c) if c.len() > 1 => {
                self.overlay = Overlay::Pick {
                    selected: c.current(),
                }
            }
            _ => {
                self.message = Some(
                    "one run here: R picks among a rosbag's runs (goals) or the robots of btx open --live A B"
                        .into(),
                )
            }
        }
    }

    /// Shows choice `i`: its run in a fresh view, the keys, the layout and
    /// the other choices kept.
    pub(crate) fn pick(&mut self, i: usize) {
        let Some(mut choices) = self.choices.take() else {
            return;
        };
        let stay = i == choices.current() || i >= choices.len();
        let shown = match &mut choices {
            _ if stay => Err(None),
            Choices::Runs { runs, current } => {
                runs[*current].session = self.session.take();
                *current = i;
                let s = runs[i].session.take().expect("a run not shown is kept");
                Ok((s.tree.clone(), s, runs[i].title.clone(), None))
            }
            Choices::Robots { robots, current } => match robots[i].feed.take() {
                None => Err(Some(format!(
                    "{} could not be reached when the explorer opened",
                    robots[i].endpoint
                ))),
                Some(feed) => match feed.session() {
                    Ok(s) => {
                        robots[*current].feed = self.live.take();
                        *current = i;
                        let title = format!("live {}", robots[i].endpoint);
                        Ok((s.tree.clone(), s, title, Some(feed)))
                    }
                    Err(e) => {
                        let m = e.to_string();
                        robots[i].feed = Some(feed);
                        Err(Some(m))
                    }
                },
            },
        };
        match shown {
            Ok((tree, session, title, feed)) => {
                let mut next = App::new(tree, Some(session), title);
                next.keymap = std::mem::take(&mut self.keymap);
                next.split = self.split;
                next.live = feed.or_else(|| self.live.take());
                next.choices = Some(choices);
                if next.live.is_some() {
                    // A robot is followed at its present.
                    next.update(super::keymap::Action::End);
                }
                *self = next;
            }
            Err(message) => {
                self.choices = Some(choices);
                self.message = message;
            }
        }
    }
}
