//! The answers pane: Han's questions, why-answers with their explanations
//! to pick and follow up, the earlier answers, and copying.

use crate::ask::Reply;
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
        // + and - say more or less of the answer on screen.
        if matches!(a, Action::Faster | Action::Slower)
            && (self.why.is_some() || self.reply.is_some())
        {
            self.change_detail(a == Action::Faster);
            return true;
        }
        if let Some(w) = &mut self.why {
            let n = w.why.groups().len().min(w.why.shown.unwrap_or(usize::MAX));
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

    /// More (`+`) or less (`-`) detail: a why-answer shows one
    /// explanation, three, or every one; a question typed in words is
    /// asked again at the new level.
    fn change_detail(&mut self, more: bool) {
        use crate::ask::Detail;
        self.detail = match (self.detail, more) {
            (Detail::Brief, true) | (Detail::Full, false) => Detail::Normal,
            (Detail::Normal, true) | (Detail::Full, true) => Detail::Full,
            (Detail::Normal, false) | (Detail::Brief, false) => Detail::Brief,
        };
        if let Some(w) = &mut self.why {
            w.why.shown = shown(self.detail);
            w.selected = w
                .selected
                .min(w.why.shown.unwrap_or(usize::MAX).saturating_sub(1));
        }
        if let Some(q) = self.reply.as_ref().map(|r| r.question.clone()) {
            self.ask_words(&q);
        }
        self.message = Some(format!("detail: {:?}", self.detail).to_lowercase());
    }

    /// Asking, whichever pane has the focus.
    pub(crate) fn answers_key(&mut self, a: Action) -> bool {
        match a {
            // One prompt: the questions about the node are its first
            // completions, and any question can be typed.
            Action::Ask | Action::AskWords => {
                self.overlay = Overlay::Words {
                    text: String::new(),
                    selected: 0,
                    picked: false,
                };
                self.cursor = None;
            }
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
                self.reply = None;
            }
            Action::Running => {
                if self.running_nodes().is_empty() {
                    self.message = Some("nothing is RUNNING at this moment".into());
                } else {
                    self.overlay = Overlay::Running { selected: 0 };
                }
            }
            Action::Faults => self.open_faults(),
            Action::Copy => self.copy_answer(),
            _ => return false,
        }
        true
    }
}

/// How many explanations a why-answer shows at a level of detail, as
/// `btx why --detail` does.
pub(crate) fn shown(d: crate::ask::Detail) -> Option<usize> {
    match d {
        crate::ask::Detail::Brief => Some(1),
        crate::ask::Detail::Normal => Some(3),
        crate::ask::Detail::Full => None,
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
    let mut lines = vec![Line::from(Span::styled(
        about(app),
        Style::default().fg(Color::DarkGray),
    ))];
    let title = match (&app.why, &app.reply, &app.answer) {
        (Some(w), ..) => {
            why_lines(app, w, &mut lines);
            " why (w) "
        }
        (None, Some(r), _) => {
            reply_lines(r, &mut lines);
            " ask (a) "
        }
        (None, None, Some(a)) => {
            lines.push(Line::from(Span::styled(
                a.question.wording(),
                Style::default().add_modifier(Modifier::BOLD),
            )));
            // Q5's steps come a line each.
            lines.extend(a.text.lines().map(|l| Line::from(l.to_string())));
            lines.push(used(&a.nodes));
            " ask (a) "
        }
        (None, None, None) => {
            lines.push(Line::from(
                "press a to ask a question about the selected node",
            ));
            " ask (a) "
        }
    };
    push_history(app, &mut lines);
    let (p, last) = scrolled(lines, app.answers.scroll, area);
    note_max(app, false, last);
    f.render_widget(p.block(block(title.into(), app.focus == Pane::Ask)), area);
}

/// What the answer on screen was asked about, wherever the selection has
/// gone since; with no answer, the node a question would be about.
fn about(app: &App) -> String {
    match &app.asked {
        Some((u, at)) if app.answer.is_some() || app.why.is_some() || app.reply.is_some() => {
            format!(
                "about {} #{u}{}",
                crate::text::visible(app.tree.description(*u)),
                at.as_ref()
                    .map_or(String::new(), |m| format!(" at moment {m}"))
            )
        }
        _ => format!(
            "about {} #{}",
            crate::text::visible(app.tree.description(app.asked_node())),
            app.asked_node()
        ),
    }
}

/// "from #13 #18": the nodes an answer used.
fn used(nodes: &[crate::model::Uid]) -> Line<'static> {
    let used: Vec<String> = nodes.iter().map(|u| format!("#{u}")).collect();
    Line::from(Span::styled(
        format!("from {}", used.join(" ")),
        Style::default().fg(Color::Cyan),
    ))
}

/// A why-answer: the question, the causes re-runs found, the
/// explanations (the picked one reversed) and the pane's keys.
fn why_lines(app: &App, w: &crate::tui::app::WhyView, lines: &mut Vec<Line<'static>>) {
    let q = &w.why;
    lines.push(Line::from(Span::styled(
        crate::causal::english::question(&q.model, &q.query),
        Style::default().add_modifier(Modifier::BOLD),
    )));
    // Causes found by running the tree again at calls the model does
    // not hold come first, as in `btx why`.
    for c in q.call_sentences() {
        lines.push(Line::from(format!("• {c}")));
    }
    let sentences = q.sentences();
    if sentences.is_empty() && q.answer.stopped.is_some() {
        let text = crate::causal::english::stopped_text(&q.answer);
        lines.push(Line::from(text.trim_end().to_string()));
    } else if sentences.is_empty() {
        // The CLI's words, word for word (the reason nothing explains
        // it, and what re-running said).
        let text = q.text();
        lines.extend(text.lines().skip(1).map(|l| Line::from(l.to_string())));
    }
    let limit = q.shown.unwrap_or(usize::MAX);
    for (i, s) in sentences.iter().enumerate().take(limit) {
        let st = if i == w.selected {
            Style::default().add_modifier(Modifier::REVERSED)
        } else {
            Style::default()
        };
        lines.push(Line::from(Span::styled(format!("{}. {s}", i + 1), st)));
    }
    if sentences.len() > limit {
        lines.push(Line::from(Span::styled(
            format!("… and {} more (+ shows more)", sentences.len() - limit),
            Style::default().fg(Color::DarkGray),
        )));
    }
    // The focus stays where the question was asked: the keys below
    // are this pane's once Tab brings it here.
    let keys = "↑↓ pick · Enter: why that reason? · m: causal model · x: DOT file · y: copy";
    lines.push(Line::from(Span::styled(
        match app.focus == Pane::Ask {
            true => keys.to_string(),
            false => format!("Tab here, then {keys}"),
        },
        Style::default().fg(Color::DarkGray),
    )));
}

/// A question typed in words: what btx read when it was not sure, the
/// question as it read it, the answer and the nodes it used.
fn reply_lines(r: &Reply, lines: &mut Vec<Line<'static>>) {
    if r.unsure() {
        lines.push(Line::from(Span::styled(
            crate::text::visible(&r.read_as()).into_owned(),
            Style::default().fg(Color::Yellow),
        )));
    }
    lines.push(Line::from(Span::styled(
        if r.understood.is_empty() {
            r.question.clone()
        } else {
            r.understood.clone()
        },
        Style::default().add_modifier(Modifier::BOLD),
    )));
    let body = Reply::body(r);
    lines.extend(
        body.lines()
            .map(|l| Line::from(crate::text::visible(l).into_owned())),
    );
    if !r.nodes.is_empty() {
        lines.push(used(&r.nodes));
    }
}
