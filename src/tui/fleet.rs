//! The fleet view (`btx fleet PATH... --open`): which actions fail in the
//! most runs as bars, the selected action's RUNNING spells as a sparkline,
//! the runs on a time axis by outcome and as a list; Enter on a run opens
//! it in the explorer, and quitting that comes back here. The figures are
//! the library's (`fleet`); this only shows them.

use super::app::App;
use super::keymap::{Action, Keymap};
use crate::fleet::{Fleet, NodeStats};
use crate::run::Status;
use crate::xml::LoadOptions;

/// Which list has the focus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Focus {
    Nodes,
    Runs,
}

pub struct FleetApp {
    pub fleet: Fleet,
    /// The actions and conditions that failed, most runs first.
    pub nodes: Vec<NodeStats>,
    pub focus: Focus,
    pub node: usize,
    pub run: usize,
    /// The runs listed: every run, or those the chosen node failed in.
    pub shown: Vec<usize>,
    /// The node the runs are filtered by (Enter on a node; Esc clears).
    pub only: Option<usize>,
    /// A run opened in the explorer; quitting it comes back here.
    pub opened: Option<Box<App>>,
    pub opts: LoadOptions,
    pub message: Option<String>,
    pub help: bool,
    pub quit: bool,
    pub keymap: Keymap,
}

impl FleetApp {
    pub fn new(fleet: Fleet, opts: LoadOptions) -> FleetApp {
        let nodes: Vec<NodeStats> = fleet
            .nodes()
            .into_iter()
            .filter(|n| n.leaf && n.faults > 0)
            .collect();
        let shown = (0..fleet.runs.len()).collect();
        let focus = if nodes.is_empty() {
            Focus::Runs
        } else {
            Focus::Nodes
        };
        FleetApp {
            fleet,
            nodes,
            focus,
            node: 0,
            run: 0,
            shown,
            only: None,
            opened: None,
            opts,
            message: None,
            help: false,
            quit: false,
            keymap: Keymap::default(),
        }
    }

    /// The run selected, if any.
    pub fn selected_run(&self) -> Option<&crate::fleet::summary::RunSummary> {
        self.shown.get(self.run).map(|&i| &self.fleet.runs[i])
    }

    pub fn update(&mut self, a: Action) {
        self.message = None;
        if self.help {
            if matches!(
                a,
                Action::Help | Action::Back | Action::Quit | Action::Toggle
            ) {
                self.help = false;
            } else {
                self.message = Some("the help is open: Esc or ? closes it".into());
            }
            return;
        }
        let len = match self.focus {
            Focus::Nodes => self.nodes.len(),
            Focus::Runs => self.shown.len(),
        };
        let at = match self.focus {
            Focus::Nodes => &mut self.node,
            Focus::Runs => &mut self.run,
        };
        match a {
            Action::Quit => self.quit = true,
            Action::Help => self.help = true,
            Action::Up | Action::PageUp | Action::Start if *at == 0 => {
                self.message = Some("at the top of the list".into())
            }
            Action::Down | Action::PageDown | Action::End if *at + 1 >= len => {
                self.message = Some("at the end of the list".into())
            }
            Action::Up => *at -= 1,
            Action::Down => *at += 1,
            Action::PageUp => *at = at.saturating_sub(PAGE),
            Action::PageDown => *at = (*at + PAGE).min(len - 1),
            Action::Start => *at = 0,
            Action::End => *at = len - 1,
            Action::NextPane => {
                self.focus = match self.focus {
                    Focus::Nodes => Focus::Runs,
                    Focus::Runs if self.nodes.is_empty() => {
                        self.message = Some("no action failed: there is only the runs' list".into());
                        Focus::Runs
                    }
                    Focus::Runs => Focus::Nodes,
                }
            }
            Action::Toggle | Action::Expand => match self.focus {
                Focus::Nodes => self.only_failed_in(),
                Focus::Runs => self.open_run(),
            },
            Action::Back if self.only.is_some() => {
                self.only = None;
                self.shown = (0..self.fleet.runs.len()).collect();
                self.run = 0;
            }
            Action::Back => self.message = Some("nothing to close (q quits)".into()),
            _ => {
                self.message = Some(format!(
                    "{} is not in the fleet view: ↑↓ choose, Tab nodes/runs, Enter the runs a node failed in or open a run, ? keys",
                    self.keymap.key_of(a).unwrap_or("that key")
                ))
            }
        }
    }

    /// The runs the selected node failed in, listed alone.
    fn only_failed_in(&mut self) {
        let Some(n) = self.nodes.get(self.node) else {
            return;
        };
        self.shown = self
            .fleet
            .runs
            .iter()
            .enumerate()
            .filter(|(_, r)| r.tree_key == n.tree_key && r.faulted.contains(&n.uid))
            .map(|(i, _)| i)
            .collect();
        self.only = Some(self.node);
        self.run = 0;
        self.focus = Focus::Runs;
        self.message = Some(format!(
            "the {} runs {} failed in (Esc: every run)",
            self.shown.len(),
            n.name
        ));
    }

    /// Opens the selected run in the explorer, at its end.
    fn open_run(&mut self) {
        let Some(r) = self.selected_run() else {
            return;
        };
        let mut opts = self.opts.clone();
        opts.run = r.run.or(opts.run);
        opts.topic = r.topic.clone().or(opts.topic);
        match super::open(&r.file, None, &opts) {
            Ok(mut app) => {
                app.shared.keymap =
                    self.keymap
                        .clone()
                        .saying(Action::Quit, "back", "back to the fleet");
                app.update(Action::End);
                self.opened = Some(Box::new(app));
            }
            Err(e) => self.message = Some(format!("{}: {}", r.name, e)),
        }
    }

    /// Ends of runs on a time axis: (position 0..1, outcome), when the runs
    /// say when they happened, and the axis's first and last time (µs
    /// since the epoch).
    pub fn timeline(&self) -> Option<Timeline> {
        let times: Vec<(i64, Option<Status>)> = self
            .fleet
            .runs
            .iter()
            .filter_map(|r| r.span_us.map(|s| (s.0, r.outcome)))
            .collect();
        let (lo, hi) = (
            times.iter().map(|t| t.0).min()?,
            times.iter().map(|t| t.0).max()?,
        );
        let span = (hi - lo).max(1) as f64;
        Some((
            times
                .into_iter()
                .map(|(t, o)| ((t - lo) as f64 / span, o))
                .collect(),
            (lo, hi),
        ))
    }
}

/// Runs on a time axis (`FleetApp::timeline`): each run's place (0..1) and
/// outcome, and the axis's ends (µs since the epoch).
pub type Timeline = (Vec<(f64, Option<Status>)>, (i64, i64));

/// Rows a page key moves.
const PAGE: usize = 10;
