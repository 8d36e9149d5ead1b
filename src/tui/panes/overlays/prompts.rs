//! The prompts: a question in your own words (with the questions about the
//! node as completions), "Can you …?", the timeline's filter and the path
//! to write the causal model to. Each types into one [`TextInput`].

use super::{list_key, Overlay};
use crate::explain::Question;
use crate::tui::keymap::Action;
use crate::tui::panes::{Component, Handled, Hints};
use crate::tui::pick_list::PickList;
use crate::tui::shared::{Exported, Shared};
use crate::tui::text_input::{self, TextInput};
use crate::tui::view::{centered, fit};
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};
use ratatui::Frame;

/// The ask prompt's row that opens "Can you …?".
pub const CAN_YOU_ROW: &str = "Can you …? (type any subgoal or step)";

/// A question in your own words, with its completions to choose from.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Words {
    pub input: TextInput,
    pub list: PickList,
    /// Whether a completion was chosen with ↑↓ (Enter then asks it; else
    /// what was typed, as typed).
    pub picked: bool,
}

impl Words {
    /// What the prompt offers for `text`: with nothing typed, the
    /// questions about the selected node; as one types, the whole
    /// questions that complete it (node names after a lead) and those of
    /// the list that match.
    pub fn completions(sh: &Shared, text: &str) -> Vec<String> {
        let listed: Vec<String> = sh
            .questions()
            .iter()
            .map(|q| match q {
                Question::CanYou(x) if x.is_empty() => CAN_YOU_ROW.to_string(),
                q => q.wording(),
            })
            .collect();
        if text.trim().is_empty() {
            if !sh.did_you_mean.is_empty() {
                return sh.did_you_mean.clone();
            }
            return listed;
        }
        let mut out = crate::ask::complete::complete(&sh.tree, text, 8);
        let keyed: Vec<(String, String)> = listed
            .iter()
            .filter(|l| *l != CAN_YOU_ROW)
            .map(|l| (l.clone(), l.clone()))
            .collect();
        for c in crate::rank::rank(text, &keyed, 8) {
            if !out.contains(&c) {
                out.push(c);
            }
        }
        out.truncate(8);
        out
    }

    /// Enter: the completion chosen (with ↑↓, or the first when nothing is
    /// typed), else what was typed, as typed.
    fn ask(&self, sh: &mut Shared, completions: &[String]) -> Handled {
        let text = self.input.text.clone();
        let q = if self.picked || text.trim().is_empty() {
            completions.get(self.list.selected).cloned().unwrap_or(text)
        } else {
            text
        };
        sh.did_you_mean.clear();
        if q == CAN_YOU_ROW {
            return Handled::Open(Overlay::can_you());
        }
        // A question of the list is answered as the list answers it.
        if let Some(known) = sh.questions().into_iter().find(|k| k.wording() == q) {
            sh.ask(&known);
        } else if !q.trim().is_empty() && sh.ask_words(&q) {
            // Not sure of its reading: the others, to pick from.
            return Handled::Open(Overlay::words());
        }
        Handled::Close
    }
}

impl Component for Words {
    /// ↑↓ choose a completion, Tab takes it into the text, Enter asks.
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let completions = Words::completions(sh, &self.input.text);
        match a {
            Action::Back | Action::Quit => {
                sh.did_you_mean.clear();
                return Handled::Close;
            }
            Action::Up | Action::Down => {
                self.list.key(a, completions.len());
                self.picked = true;
            }
            Action::NextPane => {
                if let Some(c) = completions.get(self.list.selected) {
                    if c != CAN_YOU_ROW {
                        self.input.set(c.clone());
                        self.list.selected = 0;
                        self.picked = false;
                    }
                }
            }
            Action::Toggle => return self.ask(sh, &completions),
            _ => {}
        }
        Handled::Taken
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("type a question  ↑↓ choose  Tab complete  Enter ask  Ctrl-u clear  Esc cancel")
    }

    /// The prompt, with its completions.
    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let rows = Words::completions(sh, &self.input.text);
        let r = centered(
            area,
            area.width.saturating_sub(8).min(80),
            (rows.len() as u16 + 2)
                .max(4)
                .min(area.height.saturating_sub(2)),
        );
        f.render_widget(Clear, r);
        let about = format!("ask about {}: ", sh.tree.description(sh.asked_node()));
        let b = Block::default()
            .borders(Borders::ALL)
            .title(self.input.title(&about, r.width));
        let inner = b.inner(r);
        f.render_widget(b, r);
        let h = inner.height as usize;
        let lines: Vec<Line> = rows
            .into_iter()
            .enumerate()
            .skip(self.list.first(h))
            .take(h)
            .map(|(i, q)| {
                Line::from(Span::styled(
                    fit(&q, inner.width as usize),
                    self.list.style(i),
                ))
            })
            .collect();
        f.render_widget(Paragraph::new(lines), inner);
    }
}

/// "Can you …?" being typed, with the subgoals and steps it completes to.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CanYou {
    pub input: TextInput,
    pub list: PickList,
}

impl Component for CanYou {
    /// ↑↓ pick a completion, Enter asks.
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        let text = &self.input.text;
        let candidates = sh.can_you_candidates(text);
        list_key(&mut self.list, a, candidates.len(), |i| {
            let x = candidates.get(i).cloned().unwrap_or(text.clone());
            if !x.trim().is_empty() {
                sh.ask(&Question::CanYou(x.trim().to_string()));
            }
            Handled::Close
        })
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("type  ←→ move  Ctrl-w word  Ctrl-u clear  Enter take  Esc cancel")
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let text = &self.input.text;
        let r = centered(
            area,
            area.width.saturating_sub(8).min(70),
            area.height.saturating_sub(4).min(16),
        );
        f.render_widget(Clear, r);
        let b = Block::default()
            .borders(Borders::ALL)
            .title(text_input::title(
                "Can you ",
                &format!("{text}?"),
                Some(self.input.cursor.unwrap_or(text.chars().count())),
                r.width,
            ));
        let inner = b.inner(r);
        f.render_widget(b, r);
        let h = inner.height as usize;
        let lines: Vec<Line> = sh
            .can_you_candidates(text)
            .into_iter()
            .enumerate()
            .skip(self.list.first(h))
            .take(h)
            .map(|(i, d)| {
                Line::from(Span::styled(
                    crate::text::visible(&d).into_owned(),
                    self.list.style(i),
                ))
            })
            .collect();
        f.render_widget(Paragraph::new(lines), inner);
    }
}

/// The text the timeline's transitions are filtered by: Enter applies it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Filter {
    pub input: TextInput,
}

impl Component for Filter {
    fn key(&mut self, a: Action, _sh: &mut Shared, _focused: bool) -> Handled {
        match a {
            Action::Back | Action::Quit => Handled::Close,
            Action::Toggle => Handled::Filter(std::mem::take(&mut self.input.text)),
            _ => Handled::Taken,
        }
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("type  ←→ move  Ctrl-w word  Ctrl-u clear  Enter take  Esc cancel")
    }

    fn draw(&self, _sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let r = centered(area, area.width.saturating_sub(8).min(70), 3);
        f.render_widget(Clear, r);
        f.render_widget(
            Paragraph::new(self.input.window(usize::from(r.width.saturating_sub(2)))).block(
                Block::default()
                    .borders(Borders::ALL)
                    .title(" show transitions of nodes named: Enter applies, empty for all "),
            ),
            r,
        );
    }
}

/// Where to write the why-answer's causal model (DOT): a path to edit,
/// and whether the file there is to be replaced on the next Enter.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Export {
    pub input: TextInput,
    pub replace: bool,
}

impl Component for Export {
    /// Enter writes, or asks before replacing a file.
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        match a {
            Action::Back | Action::Quit => Handled::Close,
            Action::Toggle => match sh.export_to(&self.input.text, self.replace) {
                Exported::Written => Handled::Close,
                Exported::Exists => {
                    self.replace = true;
                    Handled::Taken
                }
                Exported::Failed => {
                    self.replace = false;
                    Handled::Taken
                }
            },
            _ => Handled::Taken,
        }
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Text("type a file name  Enter write  Esc cancel")
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, _focused: bool) {
        let r = centered(area, area.width.saturating_sub(8).min(90), 4);
        f.render_widget(Clear, r);
        let title = if self.replace {
            " a file is there: Enter replaces it, Esc keeps it "
        } else {
            " write the causal model (DOT) to: Enter writes, Esc cancels "
        };
        let note = sh.message.clone().unwrap_or_default();
        f.render_widget(
            Paragraph::new(vec![
                Line::from(self.input.window(usize::from(r.width.saturating_sub(2)))),
                Line::from(crate::text::visible(&note).into_owned()),
            ])
            .block(Block::default().borders(Borders::ALL).title(title)),
            r,
        );
    }
}
