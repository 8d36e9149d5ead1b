//! The help: the keys in force and the signs, scrolled.

use crate::tui::keymap::Action;
use crate::tui::panes::{Component, Handled, Hints};
use crate::tui::shared::Shared;
use crate::tui::view::{centered, LEGEND};
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};
use ratatui::Frame;

#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Help {
    /// Lines scrolled down.
    pub scroll: usize,
}

impl Component for Help {
    /// The help scrolls, and closes.
    fn key(&mut self, a: Action, _sh: &mut Shared, _focused: bool) -> Handled {
        match a {
            Action::Back | Action::Help | Action::Quit | Action::Toggle => return Handled::Close,
            Action::Down => self.scroll += 1,
            Action::Up => self.scroll = self.scroll.saturating_sub(1),
            Action::End => self.scroll = usize::MAX,
            Action::Start => self.scroll = 0,
            _ => {}
        }
        Handled::Taken
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("↑↓ scroll  Esc or ? close")
    }

    /// The keys and the signs, scrolled.
    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let scroll = &self.scroll;
        let mut lines: Vec<Line> = sh
            .keymap
            .keys
            .iter()
            .map(|b| {
                Line::from(vec![
                    Span::styled(
                        format!("{:<16}", b.0.join(" ")),
                        Style::default().fg(Color::Yellow),
                    ),
                    Span::raw(b.2),
                ])
            })
            .collect();
        lines.push(Line::from(""));
        for (sign, what) in LEGEND {
            lines.push(Line::from(vec![
                Span::styled(format!("{sign:<16}"), Style::default().fg(Color::Yellow)),
                Span::raw(*what),
            ]));
        }
        let r = centered(area, 76, lines.len() as u16 + 2);
        let shown = r.height.saturating_sub(2) as usize;
        let top = (*scroll).min(lines.len().saturating_sub(shown));
        let more = if top + shown < lines.len() {
            " ↓ more "
        } else {
            ""
        };
        f.render_widget(Clear, r);
        f.render_widget(
            Paragraph::new(lines).scroll((top as u16, 0)).block(
                Block::default()
                    .borders(Borders::ALL)
                    .title(" keys and signs (↑↓ scroll, ? or Esc to close) ")
                    .title_bottom(more),
            ),
            r,
        );
    }
}
