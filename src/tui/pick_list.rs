//! The one list every pick list uses (the finder's results, the questions,
//! the why-questions, the running nodes, the faults, the runs and robots):
//! a selection moved by ↑↓, taken by Enter, closed by Esc.

use super::keymap::Action;
use super::view::{centered, fit};
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};
use ratatui::Frame;

/// A list's selection.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PickList {
    pub selected: usize,
}

/// What a key did to a list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Picked {
    /// The selection moved (or stayed at an end).
    Moved,
    /// Enter on row `i`.
    Chosen(usize),
    Closed,
    /// Not a list's key.
    Ignored,
}

impl PickList {
    pub fn at(selected: usize) -> PickList {
        PickList { selected }
    }

    /// A key over a list of `len` rows.
    pub fn key(&mut self, a: Action, len: usize) -> Picked {
        match a {
            Action::Up => self.selected = self.selected.saturating_sub(1),
            Action::Down => self.selected = (self.selected + 1).min(len.saturating_sub(1)),
            Action::Back | Action::Quit => return Picked::Closed,
            Action::Toggle => return Picked::Chosen(self.selected),
            _ => return Picked::Ignored,
        }
        Picked::Moved
    }

    /// The first row shown in `height` rows so that the selection shows.
    pub fn first(&self, height: usize) -> usize {
        self.selected.saturating_sub(height.saturating_sub(1))
    }

    /// The style of row `i`: reversed where selected.
    pub fn style(&self, i: usize) -> Style {
        if i == self.selected {
            Style::default().add_modifier(Modifier::REVERSED)
        } else {
            Style::default()
        }
    }

    /// Draws `rows` centred, `width` wide, scrolled to the selection; each
    /// row cut with `…` where it does not fit.
    pub fn draw(&self, f: &mut Frame, area: Rect, width: u16, rows: &[String], title: &str) {
        let r = centered(
            area,
            width,
            (rows.len() as u16 + 2).min(area.height.saturating_sub(2)),
        );
        f.render_widget(Clear, r);
        let h = r.height.saturating_sub(2) as usize;
        let lines: Vec<Line> = rows
            .iter()
            .enumerate()
            .skip(self.first(h))
            .take(h)
            .map(|(i, row)| {
                Line::from(Span::styled(
                    fit(row, r.width.saturating_sub(2) as usize),
                    self.style(i),
                ))
            })
            .collect();
        f.render_widget(
            Paragraph::new(lines).block(
                Block::default()
                    .borders(Borders::ALL)
                    .title(title.to_string()),
            ),
            r,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_selection_stays_within_the_list() {
        let mut l = PickList::default();
        assert_eq!(l.key(Action::Up, 3), Picked::Moved);
        assert_eq!(l.selected, 0);
        for _ in 0..5 {
            l.key(Action::Down, 3);
        }
        assert_eq!(l.selected, 2);
        assert_eq!(l.key(Action::Toggle, 3), Picked::Chosen(2));
        assert_eq!(l.key(Action::Back, 3), Picked::Closed);
        assert_eq!(l.key(Action::Why, 3), Picked::Ignored);
        assert_eq!(l.first(2), 1);
    }
}
