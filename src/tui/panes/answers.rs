//! The answers pane: Han's questions, why-answers with their explanations
//! to pick and follow up, the earlier answers, and copying.

use super::overlays::Overlay;
use super::{Component, Handled, Hints, KeyHelp, Lines};
use crate::ask::Reply;
use crate::tui::keymap::Action;
use crate::tui::shared::{shown, Shared, WhyView};
use crate::tui::view::*;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::Frame;

/// The answers pane's own state (the answers are the conversation, in
/// [`Shared`]).
#[derive(Debug, Clone, Default)]
pub struct Answers {
    /// Scrolled in the answer on screen.
    lines: Lines,
}

impl Answers {
    /// Up, Down, a page, Home and End within the pane.
    pub fn scroll(&mut self, a: Action, sh: &Shared) -> bool {
        self.lines.key(a, sh.answered)
    }

    /// How far the pane is scrolled in the answer on screen.
    pub fn scrolled(&self, sh: &Shared) -> usize {
        self.lines.get(sh.answered)
    }

    /// Keys while the answers pane has the focus: ↑↓ pick a why-answer's
    /// explanation and Enter asks why its reason holds; otherwise the pane
    /// scrolls.
    fn focused_key(&mut self, a: Action, sh: &mut Shared) -> Handled {
        // + and - say more or less of the answer on screen.
        if matches!(a, Action::Faster | Action::Slower) && (sh.why.is_some() || sh.reply.is_some())
        {
            return change_detail(sh, a == Action::Faster);
        }
        if let Some(w) = &mut sh.why {
            let n = w.why.groups().len().min(w.why.shown.unwrap_or(usize::MAX));
            match a {
                Action::Up => w.selected = w.selected.saturating_sub(1),
                Action::Down => w.selected = (w.selected + 1).min(n.saturating_sub(1)),
                Action::Toggle => sh.follow_up(),
                _ => return Handled::taken(self.scroll(a, sh)),
            }
            return Handled::Taken;
        }
        Handled::taken(self.scroll(a, sh))
    }
}

impl Component for Answers {
    fn key(&mut self, a: Action, sh: &mut Shared, focused: bool) -> Handled {
        if focused {
            let h = self.focused_key(a, sh);
            if h != Handled::Ignored {
                return h;
            }
        }
        answers_key(a, sh)
    }

    fn hints(&self, sh: &Shared) -> Hints {
        match sh.why {
            Some(_) => Hints::Keys(&[
                (Action::Down, "next explanation"),
                (Action::Toggle, "why that?"),
                (Action::Graph, "model"),
                (Action::ExportGraph, "export"),
            ]),
            None => Hints::Keys(&[(Action::NextPane, "next pane")]),
        }
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "answers",
            anywhere: &[
                (Action::Ask, ""),
                (Action::AskWords, ""),
                (Action::Why, ""),
                (Action::Graph, ""),
                (Action::ExportGraph, ""),
                (Action::Running, ""),
                (Action::Faults, ""),
                (Action::Copy, ""),
                (Action::Back, "clear the answer"),
            ],
            focused: &[
                (Action::Up, "a why-answer's previous reason, or scroll up"),
                (Action::Down, "a why-answer's next reason, or scroll down"),
                (Action::Toggle, "why that? (of the reason picked)"),
                (Action::Start, "the answer's first line"),
                (Action::End, "the answer's last line"),
                (Action::PageUp, "a page of the answer up"),
                (Action::PageDown, "a page of the answer down"),
                (Action::Faster, "say more of the answer"),
                (Action::Slower, "say less of the answer"),
            ],
        }
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, focused: bool) {
        let mut lines = vec![Line::from(Span::styled(
            about(sh),
            Style::default().fg(Color::DarkGray),
        ))];
        let title = match (&sh.why, &sh.reply, &sh.answer) {
            (Some(w), ..) => {
                why_lines(w, focused, &mut lines);
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
        push_history(sh, &mut lines);
        let p = self.lines.paragraph(lines, sh.answered, area);
        f.render_widget(p.block(block(title.into(), focused)), area);
    }
}

/// More (`+`) or less (`-`) detail: a why-answer shows one
/// explanation, three, or every one; a question typed in words is
/// asked again at the new level.
fn change_detail(sh: &mut Shared, more: bool) -> Handled {
    use crate::ask::Detail;
    sh.detail = match (sh.detail, more) {
        (Detail::Brief, true) | (Detail::Full, false) => Detail::Normal,
        (Detail::Normal, true) | (Detail::Full, true) => Detail::Full,
        (Detail::Normal, false) | (Detail::Brief, false) => Detail::Brief,
    };
    if let Some(w) = &mut sh.why {
        w.why.shown = shown(sh.detail);
        w.selected = w
            .selected
            .min(w.why.shown.unwrap_or(usize::MAX).saturating_sub(1));
    }
    let offer = match sh.reply.as_ref().map(|r| r.question.clone()) {
        Some(q) => sh.ask_words(&q),
        None => false,
    };
    sh.message = Some(format!("detail: {:?}", sh.detail).to_lowercase());
    match offer {
        true => Handled::Open(Overlay::words()),
        false => Handled::Taken,
    }
}

/// Asking, whichever pane has the focus.
fn answers_key(a: Action, sh: &mut Shared) -> Handled {
    match a {
        // One prompt: the questions about the node are its first
        // completions, and any question can be typed.
        Action::Ask | Action::AskWords => return Handled::Open(Overlay::words()),
        Action::Why => {
            let targets = sh.why_targets();
            if !targets.is_empty() {
                return Handled::Open(Overlay::why(targets));
            }
        }
        Action::Graph => match &mut sh.why {
            Some(w) => w.graph = !w.graph,
            None => sh.message = Some("ask why first (w): the causal graph is the answer's".into()),
        },
        Action::ExportGraph => match &sh.why {
            Some(w) => {
                let path = format!("btx-model-tick-{}.dot", w.why.model.facts.tick);
                return Handled::Open(Overlay::export(path));
            }
            None => sh.message = Some("ask why first (w): the model is the answer's".into()),
        },
        Action::Back => {
            sh.answer = None;
            sh.why = None;
            sh.reply = None;
        }
        Action::Running => {
            if sh.running_nodes().is_empty() {
                sh.message = Some("nothing is RUNNING at this moment".into());
            } else {
                return Handled::Open(Overlay::running());
            }
        }
        Action::Faults => match &sh.session {
            None => sh.message = Some("a tree alone has no faults: open a run".into()),
            Some(_) => {
                let lines = sh.fault_lines();
                if lines.is_empty() {
                    sh.message = Some("no fault in this run".into());
                } else {
                    return Handled::Open(Overlay::faults(lines));
                }
            }
        },
        Action::Copy => sh.copy_answer(),
        _ => return Handled::Ignored,
    }
    Handled::Taken
}

/// Earlier answers under the one on screen (scroll down to read them).
fn push_history(sh: &Shared, lines: &mut Vec<Line<'static>>) {
    if sh.history.is_empty() {
        return;
    }
    lines.push(Line::from(Span::styled(
        format!("── {} earlier (PageDown) ──", sh.history.len()),
        Style::default().fg(Color::DarkGray),
    )));
    for h in &sh.history {
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

/// What the answer on screen was asked about, wherever the selection has
/// gone since; with no answer, the node a question would be about.
fn about(sh: &Shared) -> String {
    match &sh.asked {
        Some((u, at)) if sh.answer.is_some() || sh.why.is_some() || sh.reply.is_some() => {
            format!(
                "about {} #{u}{}",
                crate::text::visible(sh.tree.description(*u)),
                at.as_ref()
                    .map_or(String::new(), |m| format!(" at moment {m}"))
            )
        }
        _ => format!(
            "about {} #{}",
            crate::text::visible(sh.tree.description(sh.asked_node())),
            sh.asked_node()
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
fn why_lines(w: &WhyView, focused: bool, lines: &mut Vec<Line<'static>>) {
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
        match focused {
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
