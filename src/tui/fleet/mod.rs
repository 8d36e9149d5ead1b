//! The fleet view (`btx fleet PATH... --open`): which actions fail in the
//! most runs as bars, the selected action's RUNNING spells as a sparkline,
//! the runs on a time axis by outcome and as a list; Enter on a run opens
//! it in the explorer, and quitting that comes back here. The figures are
//! the library's (`fleet`); this only shows them.
//!
//! Its panes are components as the explorer's are (`panes::Component`,
//! over [`FleetShared`]): the failing actions and the runs are lists that
//! take keys, the action chosen and the run's ending only draw, and the
//! help is a window. The app routes keys and holds the focus.

pub mod panes;

use super::app::App;
use super::keymap::{Action, Keymap};
use super::panes::{Component, Handled};
use crate::fleet::{Fleet, NodeStats};
use crate::run::Status;
use crate::xml::LoadOptions;
use panes::{Failures, FleetHelp, RunDetail, Runs, Spells};
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Style};
use ratatui::text::Span;
use ratatui::widgets::Paragraph;
use ratatui::Frame;

/// Which list has the focus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Focus {
    Nodes,
    Runs,
}

/// What the fleet view's panes share: the fleet, the actions that failed,
/// the runs listed and the selection in each list.
pub struct FleetShared {
    pub fleet: Fleet,
    /// The actions and conditions that failed, most runs first.
    pub nodes: Vec<NodeStats>,
    pub node: usize,
    pub run: usize,
    /// The runs listed: every run, or those the chosen node failed in.
    pub shown: Vec<usize>,
    /// The node the runs are filtered by (Enter on a node; Esc clears).
    pub only: Option<usize>,
    pub message: Option<String>,
}

pub struct FleetApp {
    pub shared: FleetShared,
    pub focus: Focus,
    failures: Failures,
    spells: Spells,
    runs: Runs,
    detail: RunDetail,
    /// The help window, when open.
    help: Option<FleetHelp>,
    /// A run opened in the explorer; quitting it comes back here.
    pub opened: Option<Box<App>>,
    pub opts: LoadOptions,
    pub quit: bool,
    pub keymap: Keymap,
}

impl FleetShared {
    /// The run selected, if any.
    pub fn selected_run(&self) -> Option<&crate::fleet::summary::RunSummary> {
        self.shown.get(self.run).map(|&i| &self.fleet.runs[i])
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

/// Runs on a time axis (`FleetShared::timeline`): each run's place (0..1)
/// and outcome, and the axis's ends (µs since the epoch).
pub type Timeline = (Vec<(f64, Option<Status>)>, (i64, i64));

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
            shared: FleetShared {
                fleet,
                nodes,
                node: 0,
                run: 0,
                shown,
                only: None,
                message: None,
            },
            focus,
            failures: Failures,
            spells: Spells,
            runs: Runs,
            detail: RunDetail,
            help: None,
            opened: None,
            opts,
            quit: false,
            keymap: Keymap::default(),
        }
    }

    /// A key: to the help when it is open, else the view's own keys
    /// (quit, help, Tab), else the list focused, then the other.
    pub fn update(&mut self, a: Action) {
        let sh = &mut self.shared;
        sh.message = None;
        if let Some(help) = &mut self.help {
            if help.key(a, sh, true) == Handled::Close {
                self.help = None;
            }
            return;
        }
        match a {
            Action::Quit => self.quit = true,
            Action::Help => {
                let parts = [panes::FLEET_KEYS, self.failures.help(), self.runs.help()];
                self.help = Some(FleetHelp {
                    keymap: self.keymap.clone(),
                    parts: parts.to_vec(),
                    scroll: Default::default(),
                })
            }
            Action::NextPane => {
                self.focus = match self.focus {
                    Focus::Nodes => Focus::Runs,
                    Focus::Runs if sh.nodes.is_empty() => {
                        sh.message = Some("no action failed: there is only the runs' list".into());
                        Focus::Runs
                    }
                    Focus::Runs => Focus::Nodes,
                }
            }
            _ => {
                let nodes = self.focus == Focus::Nodes;
                let mut handled = if nodes {
                    self.failures.key(a, sh, true)
                } else {
                    self.runs.key(a, sh, true)
                };
                if handled == Handled::Ignored {
                    handled = if nodes {
                        self.runs.key(a, sh, false)
                    } else {
                        self.failures.key(a, sh, false)
                    };
                }
                match handled {
                    // Enter on an action listed the runs it failed in.
                    Handled::Pick(_) if nodes => self.focus = Focus::Runs,
                    Handled::Pick(i) => self.open_run(i),
                    Handled::Ignored if a == Action::Back => {
                        sh.message = Some("nothing to close (q quits)".into())
                    }
                    Handled::Ignored => {
                        sh.message = Some(format!(
                            "{} is not in the fleet view: ↑↓ choose, Tab nodes/runs, Enter the runs a node failed in or open a run, ? keys",
                            self.keymap.key_of(a).unwrap_or("that key")
                        ))
                    }
                    _ => {}
                }
            }
        }
    }

    /// Opens run `row` of the list in the explorer, at its end.
    fn open_run(&mut self, row: usize) {
        let Some(r) = self
            .shared
            .shown
            .get(row)
            .map(|&i| &self.shared.fleet.runs[i])
        else {
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
            Err(e) => self.shared.message = Some(format!("{}: {}", r.name, e)),
        }
    }

    /// The failures and the action chosen above, the runs and the chosen
    /// run's ending below, the status line, and the help over them.
    pub fn view(&self, f: &mut Frame) {
        if let Some(run) = &self.opened {
            return run.draw(f);
        }
        let v = Layout::default()
            .direction(Direction::Vertical)
            .constraints([
                Constraint::Percentage(45),
                Constraint::Min(6),
                Constraint::Length(1),
            ])
            .split(f.area());
        let top = halves(v[0]);
        let middle = halves(v[1]);
        let sh = &self.shared;
        self.failures
            .draw(sh, f, top[0], self.focus == Focus::Nodes);
        self.spells.draw(sh, f, top[1], false);
        self.runs.draw(sh, f, middle[0], self.focus == Focus::Runs);
        self.detail.draw(sh, f, middle[1], false);
        let status = match &sh.message {
            Some(m) => Span::styled(
                super::view::fit(m, v[2].width as usize),
                Style::default().fg(Color::Yellow),
            ),
            None => Span::styled(
                super::view::first_fitting(
                    &[
                        "↑↓ choose  Tab nodes/runs  Enter the runs it failed in / open the run  Esc every run  q quit  ? help",
                        "↑↓ choose  Tab nodes/runs  Enter its runs / open  Esc every run  q quit  ? help",
                        "↑↓  Tab  Enter  Esc  q quit  ? help",
                    ],
                    v[2].width as usize,
                ),
                Style::default().fg(Color::DarkGray),
            ),
        };
        f.render_widget(Paragraph::new(status), v[2]);
        if let Some(help) = &self.help {
            help.draw(sh, f, f.area(), true);
        }
    }
}

fn halves(area: Rect) -> std::rc::Rc<[Rect]> {
    Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Percentage(60), Constraint::Percentage(40)])
        .split(area)
}
