//! The finder: a node found by a fuzzy match of its uid, description, ID
//! or path.

use super::list_key;
use crate::tui::keymap::Action;
use crate::tui::panes::{Component, Handled, Hints};
use crate::tui::pick_list::PickList;
use crate::tui::shared::Shared;
use crate::tui::text_input::TextInput;
use crate::tui::view::centered;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};
use ratatui::Frame;

#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Finder {
    pub input: TextInput,
    pub list: PickList,
}

impl Component for Finder {
    /// Enter selects the node found.
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let results = sh.finder_results(&self.input.text);
        list_key(&mut self.list, a, results.len(), |i| {
            if let Some(&(u, _)) = results.get(i) {
                sh.select(u);
            }
            Handled::Close
        })
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("type to find  ↑↓ choose  Enter go  Esc close")
    }

    /// The query, and the nodes it matches.
    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let query = &self.input.text;
        let selected = &self.list.selected;
        let r = centered(
            area,
            area.width.saturating_sub(8),
            area.height.saturating_sub(4),
        );
        f.render_widget(Clear, r);
        let b = Block::default()
            .borders(Borders::ALL)
            .title(self.input.title("find: ", r.width));
        let inner = b.inner(r);
        f.render_widget(b, r);
        let results = sh.finder_results(query);
        let h = inner.height as usize;
        let first = self.list.first(h);
        let mut lines = Vec::new();
        for (i, (u, idx)) in results.iter().enumerate().skip(first).take(h) {
            let label = sh.finder_label(*u);
            // A row too long ends in … (its path, usually), never cut bare.
            let (n, w) = (label.chars().count(), inner.width as usize);
            let keep = if n > w { w.saturating_sub(1) } else { n };
            let mut spans = Vec::new();
            for (ci, ch) in label.chars().enumerate().take(keep) {
                let mut st = Style::default();
                if idx.contains(&ci) {
                    st = st.fg(Color::Yellow).add_modifier(Modifier::BOLD);
                }
                if i == *selected {
                    st = st.add_modifier(Modifier::REVERSED);
                }
                spans.push(Span::styled(ch.to_string(), st));
            }
            if keep < n {
                spans.push(Span::raw("…"));
            }
            lines.push(Line::from(spans));
        }
        f.render_widget(Paragraph::new(lines), inner);
    }
}
