//! The help: the keys in force and the signs, scrolled.

use crate::tui::keymap::Action;
use crate::tui::panes::{help_lines, help_window, Component, Handled, Hints, KeyHelp, Lines};
use crate::tui::shared::Shared;
use crate::tui::view::LEGEND;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::Frame;

#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Help {
    /// How far it is scrolled.
    pub scroll: Lines,
    /// The keys of the explorer and of each of its panes.
    pub parts: Vec<KeyHelp>,
}

impl Component for Help {
    /// The help scrolls, and closes.
    fn key(&mut self, a: Action, _sh: &mut Shared, _focused: bool) -> Handled {
        match a {
            Action::Back | Action::Help | Action::Quit | Action::Toggle => Handled::Close,
            _ => {
                self.scroll.key(a, 0);
                Handled::Taken
            }
        }
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("↑↓ scroll  Esc or ? close")
    }

    /// The keys and the signs, scrolled.
    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let mut lines = vec![Line::from(Span::styled(
            "Keys act wherever the focus is; the focused pane's own come last.",
            Style::default().fg(Color::DarkGray),
        ))];
        lines.extend(help_lines(&sh.keymap, &self.parts));
        lines.push(Line::from(""));
        lines.push(Line::from(Span::styled(
            "signs",
            Style::default().add_modifier(Modifier::BOLD),
        )));
        for (sign, what) in LEGEND {
            lines.push(Line::from(vec![
                Span::styled(format!("  {sign:<16}"), Style::default().fg(Color::Yellow)),
                Span::raw(*what),
            ]));
        }
        let title = " keys and signs (↑↓ scroll, ? or Esc to close) ";
        help_window(f, area, 76, title, lines, &self.scroll);
    }
}
