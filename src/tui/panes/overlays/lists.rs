//! The pick lists: the why-questions about a node, the nodes RUNNING now,
//! the run's faults, and the runs or robots to show.

use super::list_key;
use crate::model::Uid;
use crate::tui::keymap::Action;
use crate::tui::panes::{Component, Handled, Hints};
use crate::tui::pick_list::PickList;
use crate::tui::shared::Shared;
use crate::tui::view::centered;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};
use ratatui::Frame;

/// A list's keys in the status bar.
const LIST_KEYS: Hints = Hints::Text("↑↓ choose  Enter pick  Esc close");

/// The why-questions about the selected node: Enter asks one.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct WhyList {
    pub list: PickList,
    /// (target, question).
    pub targets: Vec<(String, String)>,
}

impl Component for WhyList {
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let targets = &self.targets;
        list_key(&mut self.list, a, targets.len(), |i| {
            if let (Some((t, _)), Some(m)) = (targets.get(i), sh.moment()) {
                sh.ask_why(t.clone(), Vec::new(), m);
            }
            Handled::Close
        })
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        LIST_KEYS
    }

    /// The questions, each whole.
    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        // As wide as the longest question, up to the screen; a longer
        // one wraps under itself, never cut.
        let longest = self.targets.iter().map(|(_, q)| q.chars().count()).max();
        let width = (longest.unwrap_or(0) as u16 + 2)
            .max(70)
            .min(area.width.saturating_sub(4));
        let inner = usize::from(width.saturating_sub(2)).max(1);
        let mut lines: Vec<Line> = Vec::new();
        for (i, (_, q)) in self.targets.iter().enumerate() {
            for row in textwrap::wrap(q, inner) {
                lines.push(Line::from(Span::styled(
                    row.into_owned(),
                    self.list.style(i),
                )));
            }
        }
        let r = centered(area, width, lines.len() as u16 + 2);
        f.render_widget(Clear, r);
        let title = format!(
            " why? about {} ",
            crate::text::visible(sh.tree.description(sh.asked_node()))
        );
        f.render_widget(
            Paragraph::new(lines).block(Block::default().borders(Borders::ALL).title(title)),
            r,
        );
    }
}

/// The nodes RUNNING at this moment: Enter selects one.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Running {
    pub list: PickList,
}

impl Component for Running {
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let running = sh.running_nodes();
        list_key(&mut self.list, a, running.len(), |i| {
            if let Some(&u) = running.get(i) {
                sh.select(u);
            }
            Handled::Close
        })
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        LIST_KEYS
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let rows: Vec<String> = sh
            .running_nodes()
            .iter()
            .map(|&u| {
                format!(
                    "{} #{u}  {}",
                    crate::text::visible(sh.tree.description(u)),
                    sh.tree.type_name(u)
                )
            })
            .collect();
        self.list
            .draw(f, area, 70, &rows, " RUNNING now: Enter selects ");
    }
}

/// The run's faults as a watch told them, newest first: Enter goes to
/// where one happened.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Faults {
    pub list: PickList,
    /// Each fault's line, its position in the run and the node to select.
    pub lines: Vec<(String, u32, Uid)>,
}

impl Faults {
    /// The faults of a run that grew, the selection kept.
    pub fn renew(&mut self, lines: Vec<(String, u32, Uid)>) {
        self.list.selected = self.list.selected.min(lines.len().saturating_sub(1));
        self.lines = lines;
    }
}

impl Component for Faults {
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let lines = &self.lines;
        list_key(&mut self.list, a, lines.len(), |i| {
            if let Some(&(_, p, u)) = lines.get(i) {
                sh.goto(p);
                sh.select(u);
            }
            Handled::Close
        })
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        LIST_KEYS
    }

    fn draw(&self, _sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let rows: Vec<String> = self
            .lines
            .iter()
            .map(|(l, _, _)| crate::text::visible(l).to_string())
            .collect();
        let width = area.width.saturating_sub(4).min(140);
        self.list.draw(
            f,
            area,
            width,
            &rows,
            " Faults, newest first: Enter goes to one ",
        );
    }
}

/// The runs of a log or the robots watched: Enter shows one.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Pick {
    pub list: PickList,
}

impl Component for Pick {
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let n = sh.choices.as_ref().map_or(0, |c| c.len());
        list_key(&mut self.list, a, n, Handled::Pick)
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        LIST_KEYS
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let Some(c) = &sh.choices else { return };
        let rows: Vec<String> = c
            .lines(sh.live.as_ref())
            .iter()
            .enumerate()
            .map(|(i, row)| {
                let mark = if i == c.current() { "▸ " } else { "  " };
                format!("{mark}{}", crate::text::visible(row))
            })
            .collect();
        let width = area.width.saturating_sub(4).min(110);
        self.list.draw(f, area, width, &rows, c.title());
    }
}
