//! Drawing the side-by-side diff: two aligned tree panes, the edit summary
//! (or the answer to "why did they diverge?"), the two timelines.

use super::diff::{DiffApp, Pane};
use super::view::{block, status_color, tree_glyph};
use crate::run::Status;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph, Wrap};
use ratatui::Frame;

/// Fig. 14's colours: divergent leaves dark blue, their parents blue-grey.
pub const DIVERGENT: Color = Color::Rgb(0, 0, 139);
pub const PARENT: Color = Color::Rgb(96, 125, 139);

/// The first row shown so that the selection stays in view.
fn first_row(app: &DiffApp, height: usize) -> usize {
    super::view::first_shown(app.selected, app.rows.len(), height)
}

fn tree_pane(app: &DiffApp, side: usize, f: &mut Frame, area: Rect) {
    let p: &Pane = if side == 0 { &app.a } else { &app.b };
    let letter = if side == 0 { "A" } else { "B" };
    let title = match p.moment() {
        Some(m) => format!(" {letter} · {} · moment {m} ", p.name),
        None => format!(" {letter} · {} ", p.name),
    };
    let b = block(title, false);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let h = inner.height as usize;
    let first = first_row(app, h);
    let at = p.session.as_ref().map(|s| s.index.at(p.pos));
    let mut lines = Vec::with_capacity(h);
    for (i, r) in app.rows.iter().enumerate().skip(first).take(h) {
        let cell = if side == 0 { r.a } else { r.b };
        let selected = i == app.selected;
        let Some((uid, depth)) = cell else {
            let style = if selected {
                Style::default().add_modifier(Modifier::REVERSED)
            } else {
                Style::default()
            };
            lines.push(Line::from(Span::styled(" ", style)));
            continue;
        };
        let status = at.as_ref().map_or(Status::Idle, |a| a.status(uid));
        let marker = match status {
            Status::Idle => " ".to_string(),
            s => s.as_str()[..1].to_string(),
        };
        let mut name = Style::default();
        // The mark says it without colour too (NO_COLOR, monochrome terminals).
        let mark = if p.divergent.contains(&uid) {
            "≠ "
        } else if p.parents.contains(&uid) {
            "› "
        } else if p.following.contains(&uid) {
            "· "
        } else {
            "  "
        };
        if p.divergent.contains(&uid) {
            name = name
                .bg(DIVERGENT)
                .fg(Color::White)
                .add_modifier(Modifier::BOLD);
        } else if p.parents.contains(&uid) {
            name = name.bg(PARENT).fg(Color::White);
        } else if p.following.contains(&uid) {
            name = name.add_modifier(Modifier::ITALIC);
        }
        if selected {
            name = name.add_modifier(Modifier::REVERSED);
        }
        lines.push(Line::from(vec![
            Span::styled(
                format!("{marker} "),
                Style::default()
                    .fg(status_color(status))
                    .add_modifier(Modifier::BOLD),
            ),
            Span::styled(mark, Style::default().add_modifier(Modifier::BOLD)),
            Span::raw("  ".repeat(depth)),
            Span::styled(
                format!("{} ", tree_glyph(&p.tree, uid)),
                Style::default().fg(Color::Blue),
            ),
            // A long name ends in `…` and keeps its whole `#uid`.
            Span::styled(
                crate::tui::view::fit(
                    &crate::text::visible(p.tree.description(uid)),
                    (inner.width as usize)
                        .saturating_sub(6 + 2 * depth + format!(" #{uid}").chars().count()),
                ),
                name,
            ),
            Span::styled(format!(" #{uid}"), Style::default().fg(Color::DarkGray)),
        ]));
    }
    f.render_widget(Paragraph::new(lines), inner);
}

/// Per subgoal: edit distance, LCS and what changed; or the why-answer.
fn summary_pane(app: &DiffApp, f: &mut Frame, area: Rect) {
    if let Some(text) = &app.answer {
        let b = block(" why did they diverge? (Esc to close) ".into(), true);
        f.render_widget(
            Paragraph::new(text.clone())
                .block(b)
                .wrap(Wrap { trim: false }),
            area,
        );
        return;
    }
    let d = &app.diff;
    let title = if d.is_empty() {
        " edits · no divergence ".to_string()
    } else {
        format!(
            " edits · edit distance {}, LCS {} in all ",
            d.distance(),
            d.lcs()
        )
    };
    let current = app
        .divergence
        .and_then(|i| d.divergences().get(i).copied())
        .map(|(s, _)| s);
    let mut lines = Vec::new();
    for (i, sec) in d.sections.iter().enumerate() {
        if sec.a.is_empty() && sec.b.is_empty() {
            continue;
        }
        let mut style = if sec.diverges() {
            Style::default().fg(Color::LightBlue)
        } else {
            Style::default().fg(Color::DarkGray)
        };
        if current == Some(i) {
            style = style.add_modifier(Modifier::BOLD | Modifier::REVERSED);
        }
        lines.push(Line::from(Span::styled(
            format!(
                "{}: distance {}, LCS {} (A {}, B {}): {}",
                sec.name,
                sec.distance(),
                sec.lcs(),
                sec.a.len(),
                sec.b.len(),
                sec.summary()
            ),
            style,
        )));
    }
    f.render_widget(
        Paragraph::new(lines)
            .block(block(title, false))
            .wrap(Wrap { trim: false }),
        area,
    );
}

fn timeline_line(p: &Pane, letter: &str) -> Line<'static> {
    let Some(s) = &p.session else {
        return Line::from(Span::styled(
            format!("{letter}: a tree (no run)"),
            Style::default().fg(Color::DarkGray),
        ));
    };
    let m = s.index.moment(p.pos);
    let mut spans = vec![Span::raw(format!(
        "{letter}: moment {m} · tick {} of {} · transition {} of {}",
        m.tick,
        s.index.ticks(),
        p.pos,
        s.index.transitions.len()
    ))];
    if p.pos > 0 {
        let t = s.index.transitions[p.pos as usize - 1];
        spans.push(Span::raw(format!(
            "  #{} {} → ",
            t.uid,
            crate::text::visible(s.tree.description(t.uid))
        )));
        spans.push(Span::styled(
            t.status.as_str(),
            Style::default().fg(status_color(t.status)),
        ));
    }
    Line::from(spans)
}

fn help(app: &DiffApp, f: &mut Frame, area: Rect) {
    let mut lines = vec![Line::from(Span::styled(
        "Side-by-side diff (Han et al. Fig. 14)",
        Style::default().add_modifier(Modifier::BOLD),
    ))];
    lines.push(Line::from(vec![
        Span::styled("≠ leaf ", Style::default().bg(DIVERGENT).fg(Color::White)),
        Span::raw(" a divergent action   "),
        Span::styled("› parent ", Style::default().bg(PARENT).fg(Color::White)),
        Span::raw(" its parent   "),
        Span::styled("· leaf", Style::default().add_modifier(Modifier::ITALIC)),
        Span::raw(" ran (or not) only because the runs had parted"),
    ]));
    lines.push(Line::from(""));
    for (keys, action, help, _) in &app.keymap.keys {
        use super::keymap::Action as A;
        if matches!(
            action,
            A::Up
                | A::Down
                | A::NextDivergence
                | A::PrevDivergence
                | A::StepForward
                | A::StepBack
                | A::TickForward
                | A::TickBack
                | A::Start
                | A::End
                | A::Why
                | A::Back
                | A::Help
                | A::Quit
        ) {
            let text = match action {
                A::Why => "why did the runs diverge? (first divergence)",
                A::Up | A::Down => "scroll both trees",
                _ => help,
            };
            lines.push(Line::from(format!("{:<14} {text}", keys.join(", "))));
        }
    }
    let w = 64.min(area.width);
    let h = (lines.len() as u16 + 2).min(area.height);
    let r = Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    );
    f.render_widget(Clear, r);
    f.render_widget(Paragraph::new(lines).block(block(" help ".into(), true)), r);
}

pub fn view(app: &DiffApp, f: &mut Frame) {
    let runs = app.a.session.is_some() || app.b.session.is_some();
    // A message (a divergence described) wraps onto up to three rows.
    let width = usize::from(f.area().width).max(1);
    let said: Vec<String> = app
        .message
        .as_deref()
        .map(|m| {
            textwrap::wrap(m, width)
                .into_iter()
                .map(|r| r.into_owned())
                .collect()
        })
        .unwrap_or_default();
    let rows = said.len().clamp(1, 3) as u16;
    let v = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Min(6),
            Constraint::Length(if app.answer.is_some() { 10 } else { 6 }),
            Constraint::Length(if runs { 2 } else { 0 }),
            Constraint::Length(rows),
        ])
        .split(f.area());
    let top = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Percentage(50), Constraint::Percentage(50)])
        .split(v[0]);
    tree_pane(app, 0, f, top[0]);
    tree_pane(app, 1, f, top[1]);
    summary_pane(app, f, v[1]);
    if runs {
        f.render_widget(
            Paragraph::new(vec![timeline_line(&app.a, "A"), timeline_line(&app.b, "B")]),
            v[2],
        );
    }
    let status: Vec<Line> = match app.message {
        Some(_) => {
            let last = said.len().min(3);
            said[..last]
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    // A fourth row and on is cut, and says so.
                    let r = match i + 1 == last && said.len() > 3 {
                        true => super::view::fit(&format!("{r} …"), width),
                        false => r.clone(),
                    };
                    Line::from(Span::styled(r, Style::default().fg(Color::Yellow)))
                })
                .collect()
        }
        None => vec![Line::from(Span::styled(
            app.hints(),
            Style::default().fg(Color::DarkGray),
        ))],
    };
    f.render_widget(Paragraph::new(status), v[3]);
    if app.help {
        help(app, f, f.area());
    }
}
