//! Drawing the fleet view: the failures as bars, the selected action's
//! RUNNING spells as a sparkline, the runs on a time axis by outcome, the
//! runs' list and the selected run's ending.

use super::fleet::{FleetApp, Focus};
use super::view::{block, centered, first_shown as first, fit, status_color};
use crate::run::Status;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph, Wrap};
use ratatui::Frame;

pub fn view(app: &FleetApp, f: &mut Frame) {
    if let Some(run) = &app.opened {
        return run.draw(f);
    }
    let v = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Percentage(45),
            Constraint::Min(6),
            Constraint::Length(1),
        ])
        .split(f.area());
    let top = halves(v[0]);
    let middle = halves(v[1]);
    failures(app, f, top[0]);
    spells(app, f, top[1]);
    runs(app, f, middle[0]);
    run_detail(app, f, middle[1]);
    let status = match &app.message {
        Some(m) => Span::styled(fit(m, v[2].width as usize), Style::default().fg(Color::Yellow)),
        None => Span::styled(
            super::view::first_fitting(
                &[
                    "↑↓ choose  Tab nodes/runs  Enter the runs it failed in / open the run  Esc every run  q quit  ? help",
                    "↑↓ choose  Tab nodes/runs  Enter its runs / open  Esc every run  q quit  ? help",
                    "↑↓  Tab  Enter  Esc  q quit  ? help",
                ],
                v[2].width as usize,
            ),
            Style::default().fg(Color::DarkGray),
        ),
    };
    f.render_widget(Paragraph::new(status), v[2]);
    if app.help {
        help(f);
    }
}

fn halves(area: Rect) -> std::rc::Rc<[Rect]> {
    Layout::default()
        .direction(Direction::Horizontal)
        .constraints([Constraint::Percentage(60), Constraint::Percentage(40)])
        .split(area)
}

/// Each failing action's runs failed in, as a bar out of every run.
fn failures(app: &FleetApp, f: &mut Frame, area: Rect) {
    let runs = app.fleet.runs.len().max(1);
    let b = block(
        format!(
            " actions that failed, by the runs they failed in (of {}) ",
            crate::text::counted(app.fleet.runs.len(), "run")
        ),
        app.focus == Focus::Nodes,
    );
    let inner = b.inner(area);
    f.render_widget(b, area);
    if app.nodes.is_empty() {
        f.render_widget(Paragraph::new("no action failed in any run"), inner);
        return;
    }
    let w = inner.width as usize;
    let name_w = app
        .nodes
        .iter()
        .map(|n| n.name.chars().count())
        .max()
        .unwrap_or(0)
        .min(w / 2);
    let bar_w = w.saturating_sub(name_w + 12).max(1);
    let h = inner.height as usize;
    let mut lines = Vec::new();
    for (i, n) in app
        .nodes
        .iter()
        .enumerate()
        .skip(first(app.node, app.nodes.len(), h))
        .take(h)
    {
        let filled = (n.faulted_in * bar_w).div_ceil(runs);
        let mut name = Style::default();
        if i == app.node {
            name = name.add_modifier(Modifier::REVERSED);
        }
        lines.push(Line::from(vec![
            Span::styled(format!("{:<name_w$}", fit(&n.name, name_w)), name),
            Span::raw(" "),
            Span::styled("█".repeat(filled), Style::default().fg(Color::Red)),
            Span::styled(
                "░".repeat(bar_w - filled.min(bar_w)),
                Style::default().fg(Color::DarkGray),
            ),
            Span::raw(format!(" {:>4}/{}", n.faulted_in, n.ran_in)),
        ]));
    }
    f.render_widget(Paragraph::new(lines), inner);
}

/// The selected action: its RUNNING spells and what recovered it.
fn spells(app: &FleetApp, f: &mut Frame, area: Rect) {
    let b = block(" the action chosen ".into(), false);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let Some(n) = app.nodes.get(app.node) else {
        return;
    };
    let q = |p| n.running_quantile(p).unwrap_or(0);
    let mut lines = vec![
        Line::from(Span::styled(
            n.name.clone(),
            Style::default().add_modifier(Modifier::BOLD),
        )),
        Line::from(format!(
            "failed in {} of the {} runs it ran in ({})",
            n.faulted_in,
            n.ran_in,
            crate::text::counted(n.faults as usize, "failure")
        )),
    ];
    for (by, k) in &n.recovered {
        lines.push(Line::from(format!("{k} recovered by {by}")));
    }
    if n.unrecovered > 0 {
        lines.push(Line::from(format!("{} not recovered", n.unrecovered)));
    }
    lines.push(Line::from(""));
    lines.push(Line::from(format!(
        "ticks RUNNING: median {}, 95th percentile {}, longest {}",
        q(0.5),
        q(0.95),
        n.running.max().unwrap_or(0)
    )));
    lines.push(Line::from(vec![
        Span::raw("spells by length "),
        Span::styled(
            crate::fleet::sparkline(&n.running),
            Style::default().fg(Color::Yellow),
        ),
    ]));
    f.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), inner);
}

fn outcome_mark(o: Option<Status>) -> (&'static str, Color) {
    match o {
        Some(Status::Success) => ("S", status_color(Status::Success)),
        Some(Status::Failure) => ("F", status_color(Status::Failure)),
        _ => ("·", Color::DarkGray),
    }
}

fn runs(app: &FleetApp, f: &mut Frame, area: Rect) {
    let title = match app.only.and_then(|i| app.nodes.get(i)) {
        Some(n) => format!(" the runs {} failed in (Esc: every run) ", n.name),
        None => format!(" {} ", crate::text::counted(app.fleet.runs.len(), "run")),
    };
    let b = block(title, app.focus == Focus::Runs);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let h = inner.height as usize;
    let w = inner.width as usize;
    let mut lines = Vec::new();
    for (row, &i) in app
        .shown
        .iter()
        .enumerate()
        .skip(first(app.run, app.shown.len(), h))
        .take(h)
    {
        let r = &app.fleet.runs[i];
        let (mark, colour) = outcome_mark(r.outcome);
        let mut name = Style::default();
        if row == app.run {
            name = name.add_modifier(Modifier::REVERSED);
        }
        let ticks = format!("  {} ticks", r.ticks);
        lines.push(Line::from(vec![
            Span::styled(format!("{mark} "), Style::default().fg(colour)),
            Span::styled(fit(&r.name, w.saturating_sub(2 + ticks.len())), name),
            Span::styled(ticks, Style::default().fg(Color::DarkGray)),
        ]));
    }
    f.render_widget(Paragraph::new(lines), inner);
}

/// The runs on a time axis by outcome, then the selected run's ending.
fn run_detail(app: &FleetApp, f: &mut Frame, area: Rect) {
    let b = block(" when, and how it ended ".into(), false);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let w = inner.width as usize;
    let mut lines = Vec::new();
    match app.timeline() {
        Some((marks, (lo, hi))) if w > 2 => {
            let timed = marks.len();
            // One cell a slice of time; a failure shows over a success.
            let mut cells: Vec<Option<Option<Status>>> = vec![None; w];
            for (p, o) in marks {
                let c = &mut cells[((p * (w - 1) as f64).round() as usize).min(w - 1)];
                let worse = match (*c, o) {
                    (None, _) => true,
                    (Some(Some(Status::Failure)), _) => false,
                    (_, Some(Status::Failure)) => true,
                    (Some(Some(Status::Success)), None) => true,
                    _ => false,
                };
                if worse {
                    *c = Some(o);
                }
            }
            lines.push(Line::from(
                cells
                    .into_iter()
                    .map(|c| match c {
                        None => Span::styled("─", Style::default().fg(Color::DarkGray)),
                        Some(o) => {
                            let (m, colour) = outcome_mark(o);
                            Span::styled(m, Style::default().fg(colour))
                        }
                    })
                    .collect::<Vec<_>>(),
            ));
            // The axis's ends, dated (UTC, the robots' clocks).
            let (first, last) = (crate::clock::utc(lo), crate::clock::utc(hi));
            let last = if first[..10] == last[..10] {
                format!("{} UTC", &last[11..16])
            } else {
                format!("{} UTC", &last[..16])
            };
            let first = &first[..16];
            let pad = w.saturating_sub(first.chars().count() + last.chars().count());
            let ends = if pad > 0 {
                format!("{first}{}{last}", " ".repeat(pad))
            } else {
                format!("from {first}")
            };
            lines.push(Line::from(Span::styled(
                ends,
                Style::default().fg(Color::DarkGray),
            )));
            lines.push(Line::from(Span::styled(
                format!(
                    "{} by start time: S succeeded, F failed, · unfinished",
                    if timed == app.fleet.runs.len() {
                        "the runs".to_string()
                    } else {
                        format!("the {timed} of {} runs that say when", app.fleet.runs.len())
                    }
                ),
                Style::default().fg(Color::DarkGray),
            )));
        }
        _ => lines.push(Line::from(Span::styled(
            "no run says when it happened (a session keeps no times; a robot's log does)",
            Style::default().fg(Color::DarkGray),
        ))),
    }
    if let Some(r) = app.selected_run() {
        lines.push(Line::from(""));
        lines.push(Line::from(Span::styled(
            r.name.clone(),
            Style::default().add_modifier(Modifier::BOLD),
        )));
        if let Some((first, _)) = r.span_us {
            lines.push(Line::from(format!(
                "started {} UTC",
                &crate::clock::utc(first)[..19]
            )));
        }
        lines.push(Line::from(format!(
            "{}.",
            crate::causal::english::capitalised(&r.ending)
        )));
        if let Some(w) = &r.wrong {
            lines.push(Line::from(w.clone()));
        }
    }
    f.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), inner);
}

fn help(f: &mut Frame) {
    let r = centered(f.area(), 66, 12);
    f.render_widget(Clear, r);
    let text = [
        "↑↓ k j     choose in the list focused",
        "PgUp PgDn  a page; g G the first, the last",
        "Tab        the actions, or the runs",
        "Enter      on an action: the runs it failed in",
        "           on a run: open it in the explorer (q comes back)",
        "Esc        every run again",
        "q          quit",
    ];
    f.render_widget(
        Paragraph::new(text.iter().map(|l| Line::from(*l)).collect::<Vec<_>>()).block(block(
            " the fleet view's keys (Esc or ? closes) ".into(),
            true,
        )),
        r,
    );
}
