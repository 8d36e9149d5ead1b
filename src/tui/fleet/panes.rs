//! The fleet view's components: the actions that failed as bars (a list),
//! the chosen action's RUNNING spells as a sparkline, the runs (a list),
//! the runs on a time axis by outcome with the chosen run's ending, and
//! the help.

use super::FleetShared;
use crate::run::Status;
use crate::tui::keymap::{Action, Keymap};
use crate::tui::panes::{help_lines, help_window, Component, Handled, Hints, KeyHelp, Lines, PAGE};
use crate::tui::view::{block, first_shown as first, fit, status_color};
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};
use ratatui::Frame;

/// Each failing action's runs failed in, as a bar out of every run.
fn failures(sh: &FleetShared, f: &mut Frame, area: Rect, focused: bool) {
    let runs = sh.fleet.runs.len().max(1);
    let b = block(
        format!(
            " actions that failed, by the runs they failed in (of {}) ",
            crate::text::counted(sh.fleet.runs.len(), "run")
        ),
        focused,
    );
    let inner = b.inner(area);
    f.render_widget(b, area);
    if sh.nodes.is_empty() {
        f.render_widget(Paragraph::new("no action failed in any run"), inner);
        return;
    }
    let w = inner.width as usize;
    let name_w = sh
        .nodes
        .iter()
        .map(|n| n.name.chars().count())
        .max()
        .unwrap_or(0)
        .min(w / 2);
    let bar_w = w.saturating_sub(name_w + 12).max(1);
    let h = inner.height as usize;
    let mut lines = Vec::new();
    for (i, n) in sh
        .nodes
        .iter()
        .enumerate()
        .skip(first(sh.node, sh.nodes.len(), h))
        .take(h)
    {
        let filled = (n.faulted_in * bar_w).div_ceil(runs);
        let mut name = Style::default();
        if i == sh.node {
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
fn spells(sh: &FleetShared, f: &mut Frame, area: Rect) {
    let b = block(" the action chosen ".into(), false);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let Some(n) = sh.nodes.get(sh.node) else {
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

fn runs(sh: &FleetShared, f: &mut Frame, area: Rect, focused: bool) {
    let title = match sh.only.and_then(|i| sh.nodes.get(i)) {
        Some(n) => format!(" the runs {} failed in (Esc: every run) ", n.name),
        None => format!(" {} ", crate::text::counted(sh.fleet.runs.len(), "run")),
    };
    let b = block(title, focused);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let h = inner.height as usize;
    let w = inner.width as usize;
    let mut lines = Vec::new();
    for (row, &i) in sh
        .shown
        .iter()
        .enumerate()
        .skip(first(sh.run, sh.shown.len(), h))
        .take(h)
    {
        let r = &sh.fleet.runs[i];
        let (mark, colour) = outcome_mark(r.outcome);
        let mut name = Style::default();
        if row == sh.run {
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
fn run_detail(sh: &FleetShared, f: &mut Frame, area: Rect) {
    let b = block(" when, and how it ended ".into(), false);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let w = inner.width as usize;
    let grey = Style::default().fg(Color::DarkGray);
    let mut lines = Vec::new();
    match sh.timeline() {
        Some((marks, (lo, hi))) if w > 2 => {
            lines.push(strip(&marks, w));
            lines.push(Line::from(Span::styled(axis_ends(lo, hi, w), grey)));
            let which = if marks.len() == sh.fleet.runs.len() {
                "the runs".to_string()
            } else {
                format!(
                    "the {} of {} runs that say when",
                    marks.len(),
                    sh.fleet.runs.len()
                )
            };
            lines.push(Line::from(Span::styled(
                format!("{which} by start time: S succeeded, F failed, · unfinished"),
                grey,
            )));
        }
        _ => lines.push(Line::from(Span::styled(
            "no run says when it happened (a session keeps no times; a robot's log does)",
            grey,
        ))),
    }
    if let Some(r) = sh.selected_run() {
        lines.extend(how_it_ended(r));
    }
    f.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), inner);
}

/// The runs by start time, one cell a slice of time; a failure shows over
/// a success.
fn strip(marks: &[(f64, Option<Status>)], w: usize) -> Line<'static> {
    let mut cells: Vec<Option<Option<Status>>> = vec![None; w];
    for &(p, o) in marks {
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
    Line::from(
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
    )
}

/// The axis's ends, dated (UTC, the robots' clocks), `w` cells apart.
fn axis_ends(lo: i64, hi: i64, w: usize) -> String {
    let (first, last) = (crate::clock::utc(lo), crate::clock::utc(hi));
    let last = if first[..10] == last[..10] {
        format!("{} UTC", &last[11..16])
    } else {
        format!("{} UTC", &last[..16])
    };
    let first = &first[..16];
    let pad = w.saturating_sub(first.chars().count() + last.chars().count());
    if pad > 0 {
        format!("{first}{}{last}", " ".repeat(pad))
    } else {
        format!("from {first}")
    }
}

/// The selected run: its name, when it started, how it ended, what went
/// wrong.
fn how_it_ended(r: &crate::fleet::summary::RunSummary) -> Vec<Line<'static>> {
    let mut lines = vec![
        Line::from(""),
        Line::from(Span::styled(
            r.name.clone(),
            Style::default().add_modifier(Modifier::BOLD),
        )),
    ];
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
    lines
}

/// Up, Down, a page, Home and End over a list of `len` rows; at an end,
/// the status line says so.
fn list_key(at: &mut usize, len: usize, a: Action, message: &mut Option<String>) -> bool {
    match a {
        Action::Up | Action::PageUp | Action::Start if *at == 0 => {
            *message = Some("at the top of the list".into())
        }
        Action::Down | Action::PageDown | Action::End if *at + 1 >= len => {
            *message = Some("at the end of the list".into())
        }
        Action::Up => *at -= 1,
        Action::Down => *at += 1,
        Action::PageUp => *at = at.saturating_sub(PAGE),
        Action::PageDown => *at = (*at + PAGE).min(len - 1),
        Action::Start => *at = 0,
        Action::End => *at = len - 1,
        _ => return false,
    }
    true
}

/// The actions that failed, by the runs they failed in: Enter lists
/// those runs alone (and says it picked them).
pub struct Failures;

impl Component<FleetShared> for Failures {
    fn key(&mut self, a: Action, sh: &mut FleetShared, focused: bool) -> Handled {
        if !focused {
            return Handled::Ignored;
        }
        let len = sh.nodes.len();
        if list_key(&mut sh.node, len, a, &mut sh.message) {
            return Handled::Taken;
        }
        if !matches!(a, Action::Toggle | Action::Expand) {
            return Handled::Ignored;
        }
        let Some(n) = sh.nodes.get(sh.node) else {
            return Handled::Taken;
        };
        sh.shown = sh
            .fleet
            .runs
            .iter()
            .enumerate()
            .filter(|(_, r)| r.tree_key == n.tree_key && r.faulted.contains(&n.uid))
            .map(|(i, _)| i)
            .collect();
        sh.message = Some(format!(
            "the {} runs {} failed in (Esc: every run)",
            sh.shown.len(),
            n.name
        ));
        sh.only = Some(sh.node);
        sh.run = 0;
        Handled::Pick(sh.node)
    }

    fn hints(&self, _: &FleetShared) -> Hints {
        Hints::Keys(&[(Action::Toggle, "the runs it failed in")])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "the actions that failed",
            anywhere: &[],
            focused: &[
                (Action::Up, "the action above"),
                (Action::Down, "the action below"),
                (Action::PageUp, "a page up"),
                (Action::PageDown, "a page down"),
                (Action::Start, "the first action"),
                (Action::End, "the last action"),
                (Action::Toggle, "the runs it failed in"),
                (Action::Expand, "the runs it failed in"),
            ],
        }
    }

    fn draw(&self, sh: &FleetShared, f: &mut Frame, area: Rect, focused: bool) {
        failures(sh, f, area, focused)
    }
}

/// The action chosen: its failures, what recovered it, its RUNNING spells.
pub struct Spells;

impl Component<FleetShared> for Spells {
    fn key(&mut self, _: Action, _: &mut FleetShared, _: bool) -> Handled {
        Handled::Ignored
    }

    fn hints(&self, _: &FleetShared) -> Hints {
        Hints::Keys(&[])
    }

    fn draw(&self, sh: &FleetShared, f: &mut Frame, area: Rect, _: bool) {
        spells(sh, f, area)
    }
}

/// The runs listed: Enter picks one to open; Esc lists every run again,
/// wherever the focus is.
pub struct Runs;

impl Component<FleetShared> for Runs {
    fn key(&mut self, a: Action, sh: &mut FleetShared, focused: bool) -> Handled {
        if a == Action::Back && sh.only.is_some() {
            sh.only = None;
            sh.shown = (0..sh.fleet.runs.len()).collect();
            sh.run = 0;
            return Handled::Taken;
        }
        if !focused {
            return Handled::Ignored;
        }
        let len = sh.shown.len();
        if list_key(&mut sh.run, len, a, &mut sh.message) {
            return Handled::Taken;
        }
        match a {
            Action::Toggle | Action::Expand => Handled::Pick(sh.run),
            _ => Handled::Ignored,
        }
    }

    fn hints(&self, _: &FleetShared) -> Hints {
        Hints::Keys(&[
            (Action::Toggle, "open the run"),
            (Action::Back, "every run"),
        ])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "the runs",
            anywhere: &[(Action::Back, "every run again")],
            focused: &[
                (Action::Up, "the run above"),
                (Action::Down, "the run below"),
                (Action::PageUp, "a page up"),
                (Action::PageDown, "a page down"),
                (Action::Start, "the first run"),
                (Action::End, "the last run"),
                (
                    Action::Toggle,
                    "open the run in the explorer (q comes back)",
                ),
                (
                    Action::Expand,
                    "open the run in the explorer (q comes back)",
                ),
            ],
        }
    }

    fn draw(&self, sh: &FleetShared, f: &mut Frame, area: Rect, focused: bool) {
        runs(sh, f, area, focused)
    }
}

/// The runs on a time axis by outcome, and how the chosen run ended.
pub struct RunDetail;

impl Component<FleetShared> for RunDetail {
    fn key(&mut self, _: Action, _: &mut FleetShared, _: bool) -> Handled {
        Handled::Ignored
    }

    fn hints(&self, _: &FleetShared) -> Hints {
        Hints::Keys(&[])
    }

    fn draw(&self, sh: &FleetShared, f: &mut Frame, area: Rect, _: bool) {
        run_detail(sh, f, area)
    }
}

/// The fleet view's keys, over the panes: Esc, ?, q or Enter closes it.
pub struct FleetHelp {
    /// The keys in force, as the help lists them.
    pub keymap: Keymap,
    /// The view's own keys and each list's.
    pub parts: Vec<KeyHelp>,
    /// How far it is scrolled.
    pub scroll: Lines,
}

/// The fleet view's own keys, for the help.
pub const FLEET_KEYS: KeyHelp = KeyHelp {
    name: "the fleet view",
    anywhere: &[
        (Action::Help, ""),
        (Action::Quit, ""),
        (Action::NextPane, "the actions, or the runs"),
    ],
    focused: &[],
};

impl Component<FleetShared> for FleetHelp {
    fn key(&mut self, a: Action, sh: &mut FleetShared, _: bool) -> Handled {
        if matches!(
            a,
            Action::Help | Action::Back | Action::Quit | Action::Toggle
        ) {
            return Handled::Close;
        }
        if !self.scroll.key(a, 0) {
            sh.message = Some("the help is open: Esc or ? closes it".into());
        }
        Handled::Taken
    }

    fn hints(&self, _: &FleetShared) -> Hints {
        Hints::Text("↑↓ scroll  Esc or ? closes the help")
    }

    fn draw(&self, _: &FleetShared, f: &mut Frame, area: Rect, _: bool) {
        let lines = help_lines(&self.keymap, &self.parts);
        let title = " the fleet view's keys (↑↓ scroll, Esc or ? closes) ";
        help_window(f, area, 66, title, lines, &self.scroll);
    }
}
