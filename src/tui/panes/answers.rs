//! The answers pane: Han's questions, why-answers with their explanations
//! to pick and follow up, the earlier answers, and copying.

use crate::tui::app::{App, Overlay, Pane};
use crate::tui::keymap::Action;
use crate::tui::view::*;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::Frame;

/// The answers pane's own state.
#[derive(Debug, Clone, Default)]
pub struct AnswersState {
    /// Lines scrolled.
    pub scroll: usize,
    /// Earlier answers, most recent first, each with what it was about.
    pub history: Vec<String>,
}

impl AnswersState {
    /// Up, Down, a page, Home and End within the pane (`max`: how far it
    /// could scroll when last drawn).
    pub fn scroll(&mut self, a: Action, max: usize) -> bool {
        super::scroll_lines(&mut self.scroll, a, max)
    }
}

impl App {
    /// Keys while the answers pane has the focus: ↑↓ pick a why-answer's
    /// explanation and Enter asks why its reason holds; otherwise the pane
    /// scrolls.
    pub(crate) fn answers_focused_key(&mut self, a: Action) -> bool {
        if let Some(w) = &mut self.why {
            let n = w.why.groups().len();
            match a {
                Action::Up => w.selected = w.selected.saturating_sub(1),
                Action::Down => w.selected = (w.selected + 1).min(n.saturating_sub(1)),
                Action::Toggle => self.follow_up(),
                _ => return self.answers.scroll(a, self.scroll_max.get().1),
            }
            return true;
        }
        self.answers.scroll(a, self.scroll_max.get().1)
    }

    /// Asking, whichever pane has the focus.
    pub(crate) fn answers_key(&mut self, a: Action) -> bool {
        match a {
            Action::Ask => self.overlay = Overlay::Ask { selected: 0 },
            Action::Why => self.open_why(),
            Action::Graph => match &mut self.why {
                Some(w) => w.graph = !w.graph,
                None => {
                    self.message =
                        Some("ask why first (w): the causal graph is the answer's".into())
                }
            },
            Action::ExportGraph => self.export_graph(),
            Action::Back => {
                self.answer = None;
                self.why = None;
            }
            Action::Running => {
                if self.running_nodes().is_empty() {
                    self.message = Some("nothing is RUNNING at this moment".into());
                } else {
                    self.overlay = Overlay::Running { selected: 0 };
                }
            }
            Action::Copy => self.copy_answer(),
            _ => return false,
        }
        true
    }
}

/// Earlier answers under the one on screen (scroll down to read them).
fn push_history(app: &App, lines: &mut Vec<Line<'static>>) {
    if app.answers.history.is_empty() {
        return;
    }
    lines.push(Line::from(Span::styled(
        format!("── {} earlier (PageDown) ──", app.answers.history.len()),
        Style::default().fg(Color::DarkGray),
    )));
    for h in &app.answers.history {
        for (i, l) in h.lines().enumerate() {
            let st = if i == 0 {
                Style::default().fg(Color::DarkGray)
            } else {
                Style::default()
            };
            lines.push(Line::from(Span::styled(l.to_string(), st)));
        }
    }
}

pub(crate) fn draw(app: &App, f: &mut Frame, area: Rect) {
    let b = block(" ask (a) ".into(), app.focus == Pane::Ask);
    // An answer on screen names what it was asked about, wherever the
    // selection has gone since.
    let about = match &app.asked {
        Some((u, at)) if app.answer.is_some() || app.why.is_some() => format!(
            "about {} #{u}{}",
            app.tree.description(*u),
            at.as_ref()
                .map_or(String::new(), |m| format!(" at moment {m}"))
        ),
        _ => format!(
            "about {} #{}",
            app.tree.description(app.asked_node()),
            app.asked_node()
        ),
    };
    let mut lines = vec![Line::from(Span::styled(
        about,
        Style::default().fg(Color::DarkGray),
    ))];
    if let Some(w) = &app.why {
        let q = &w.why;
        lines.push(Line::from(Span::styled(
            crate::causal::english::question(&q.model, &q.query),
            Style::default().add_modifier(Modifier::BOLD),
        )));
        let sentences = q.sentences();
        if sentences.is_empty() && q.answer.stopped.is_some() {
            let text = crate::causal::english::stopped_text(&q.answer);
            lines.push(Line::from(text.trim_end().to_string()));
        } else if sentences.is_empty() {
            lines.push(Line::from(format!(
                "No explanation up to depth {}.",
                q.answer.max_depth
            )));
        }
        for (i, s) in sentences.iter().enumerate() {
            let st = if i == w.selected {
                Style::default().add_modifier(Modifier::REVERSED)
            } else {
                Style::default()
            };
            lines.push(Line::from(Span::styled(format!("{}. {s}", i + 1), st)));
        }
        lines.push(Line::from(Span::styled(
            "↑↓ pick · Enter: why that reason? · m: causal model · x: DOT file · y: copy",
            Style::default().fg(Color::DarkGray),
        )));
        push_history(app, &mut lines);
        f.render_widget(
            {
                let (p, last) = scrolled(lines, app.answers.scroll, area);
                note_max(app, false, last);
                p.block(block(" why (w) ".into(), app.focus == Pane::Ask))
            },
            area,
        );
        return;
    }
    match &app.answer {
        Some(a) => {
            lines.push(Line::from(Span::styled(
                a.question.wording(),
                Style::default().add_modifier(Modifier::BOLD),
            )));
            // Q5's steps come a line each.
            lines.extend(a.text.lines().map(|l| Line::from(l.to_string())));
            let used: Vec<String> = a.nodes.iter().map(|u| format!("#{u}")).collect();
            lines.push(Line::from(Span::styled(
                format!("from {}", used.join(" ")),
                Style::default().fg(Color::Cyan),
            )));
        }
        None => lines.push(Line::from(
            "press a to ask a question about the selected node",
        )),
    }
    push_history(app, &mut lines);
    let (p, last) = scrolled(lines, app.answers.scroll, area);
    note_max(app, false, last);
    f.render_widget(p.block(b), area);
}
