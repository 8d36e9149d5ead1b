//! The side-by-side diff's components: the two aligned trees scrolled
//! together, the edit summary (divergences, and the answer to "why did
//! they diverge?"), the two timelines moved together, and the help.

use super::{DiffShared, Pane};
use crate::run::Status;
use crate::tui::keymap::{Action, Keymap};
use crate::tui::panes::{help_lines, help_window, Component, Handled, Hints, KeyHelp, Lines};
use crate::tui::view::{block, status_color, tree_glyph};
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};
use ratatui::Frame;

/// Fig. 14's colours: divergent leaves dark blue, their parents blue-grey.
pub const DIVERGENT: Color = Color::Rgb(0, 0, 139);
pub const PARENT: Color = Color::Rgb(96, 125, 139);

/// The first row shown so that the selection stays in view.
fn first_row(sh: &DiffShared, height: usize) -> usize {
    crate::tui::view::first_shown(sh.selected, sh.rows.len(), height)
}

fn tree_pane(app: &DiffShared, side: usize, f: &mut Frame, area: Rect) {
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
        let (mark, mut name) = divergence_mark(p, uid);
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

/// How a node's row says where it stands to the divergence: a mark, which
/// says it without colour too (NO_COLOR, monochrome terminals), and the
/// name's style.
fn divergence_mark(p: &Pane, uid: crate::model::Uid) -> (&'static str, Style) {
    let name = Style::default();
    if p.divergent.contains(&uid) {
        let style = name
            .bg(DIVERGENT)
            .fg(Color::White)
            .add_modifier(Modifier::BOLD);
        ("≠ ", style)
    } else if p.parents.contains(&uid) {
        ("› ", name.bg(PARENT).fg(Color::White))
    } else if p.following.contains(&uid) {
        ("· ", name.add_modifier(Modifier::ITALIC))
    } else {
        ("  ", name)
    }
}

/// Per subgoal: edit distance, LCS and what changed; or the why-answer.
fn summary_pane(app: &DiffShared, f: &mut Frame, area: Rect) {
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

fn help(keymap: &Keymap, parts: &[KeyHelp], scroll: &Lines, f: &mut Frame, area: Rect) {
    let mut lines = vec![Line::from(Span::styled(
        "Side-by-side diff (Han et al. Fig. 14)",
        Style::default().add_modifier(Modifier::BOLD),
    ))];
    lines.push(Line::from(vec![
        Span::styled("≠ leaf ", Style::default().bg(DIVERGENT).fg(Color::White)),
        Span::raw(" a divergent action   "),
        Span::styled("› parent ", Style::default().bg(PARENT).fg(Color::White)),
        Span::raw(" its parent"),
    ]));
    // The third sign on a line of its own: the three do not fit the help's
    // width on one.
    lines.push(Line::from(vec![
        Span::styled("· leaf", Style::default().add_modifier(Modifier::ITALIC)),
        Span::raw(" ran (or not) only because the runs had parted"),
    ]));
    lines.push(Line::from(""));
    lines.extend(help_lines(keymap, parts));
    help_window(f, area, 64, " help (↑↓ scroll, Esc closes) ", lines, scroll);
}

impl DiffShared {
    fn step(&mut self, by: i64) {
        for p in [&mut self.a, &mut self.b] {
            p.go_to_pos((p.pos as i64 + by).clamp(0, p.len() as i64) as u32);
        }
        if self.a.session.is_none() && self.b.session.is_none() {
            self.message = Some("two trees: there is no run to step through".into());
        }
    }

    /// Moves the selection to the next (or previous) divergent edit, and
    /// for runs, both timelines to the tick where it started.
    fn jump(&mut self, forward: bool) {
        let all = self.diff.divergences();
        if all.is_empty() {
            self.message = Some("no divergence: A and B do the same".into());
            return;
        }
        let n = all.len();
        let next = match (self.divergence, forward) {
            (None, true) => 0,
            (None, false) => n - 1,
            (Some(i), true) => (i + 1) % n,
            (Some(i), false) => (i + n - 1) % n,
        };
        self.divergence = Some(next);
        let (s, i) = all[next];
        let sec = &self.diff.sections[s];
        let e = sec.edits[i];
        let (ua, ub) = (e.a.map(|k| &sec.a[k]), e.b.map(|k| &sec.b[k]));
        if let Some(r) = self.rows.iter().position(|r| {
            ub.is_some_and(|x| r.b.is_some_and(|(u, _)| u == x.uid))
                || ua.is_some_and(|x| r.a.is_some_and(|(u, _)| u == x.uid))
        }) {
            self.selected = r;
        }
        if let Some(t) = ub.and_then(|x| x.tick).or(ua.and_then(|x| x.tick)) {
            self.a.go_to_tick(t);
            self.b.go_to_tick(t);
        }
        let parting = if self.diff.parting_edit() == Some((s, i)) {
            let here = if self.diff.parting_held {
                "the runs part ways here"
            } else {
                "the first to differ after the runs part"
            };
            match self.diff.following().len() {
                0 => format!(" ({here})"),
                1 => format!(" ({here}; 1 step follows, ·)"),
                k => format!(" ({here}; {k} steps follow, ·)"),
            }
        } else {
            String::new()
        };
        self.message = Some(format!(
            "divergence {} of {n}{parting}: {}",
            next + 1,
            self.diff.describe(s, i)
        ));
    }

    /// "Why did they diverge?": the first transition where the runs differ,
    /// asked in B's model of that tick with A's value as the foil. Both
    /// timelines move to that transition.
    fn ask_why(&mut self) {
        let (Some(sa), Some(sb)) = (&self.a.session, &self.b.session) else {
            self.message = Some("why they diverged is a question about two runs".into());
            return;
        };
        if !crate::diff::same_shape(&sa.tree, &sb.tree) {
            self.message =
                Some("these runs are of different trees: no transition to compare".into());
            return;
        }
        let domain = match crate::causal::session_domain(sb, None) {
            Ok(d) => d,
            Err(e) => {
                self.message = Some(e.to_string());
                return;
            }
        };
        match crate::causal::compare::why_diverged(sa, sb, domain, 2) {
            Ok(None) => self.answer = Some(crate::causal::compare::Diverged::SAME.into()),
            Ok(Some(x)) => {
                let i = x.difference.index as u32 + 1;
                let text = x.text(&sb.tree, "");
                self.a.go_to_pos(i);
                self.b.go_to_pos(i);
                self.answer = Some(text);
            }
            Err(e) => self.message = Some(e.to_string()),
        }
    }
}

/// The two trees, scrolled together by ↑↓.
pub struct Trees;

impl Component<DiffShared> for Trees {
    fn key(&mut self, a: Action, sh: &mut DiffShared, _: bool) -> Handled {
        let last = sh.rows.len().saturating_sub(1);
        match a {
            Action::Up => sh.selected = sh.selected.saturating_sub(1),
            Action::Down => sh.selected = (sh.selected + 1).min(last),
            _ => return Handled::Ignored,
        }
        Handled::Taken
    }

    fn hints(&self, _: &DiffShared) -> Hints {
        Hints::Keys(&[(Action::Down, "scroll both trees")])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "the two trees",
            anywhere: &[
                (Action::Up, "scroll both trees up"),
                (Action::Down, "scroll both trees down"),
            ],
            focused: &[],
        }
    }

    fn draw(&self, sh: &DiffShared, f: &mut Frame, area: Rect, _: bool) {
        let top = Layout::default()
            .direction(Direction::Horizontal)
            .constraints([Constraint::Percentage(50), Constraint::Percentage(50)])
            .split(area);
        tree_pane(sh, 0, f, top[0]);
        tree_pane(sh, 1, f, top[1]);
    }
}

/// The edits by subgoal, or the answer to "why did they diverge?": d and
/// D jump between divergences, w asks why, Esc closes the answer.
pub struct Summary;

impl Component<DiffShared> for Summary {
    fn key(&mut self, a: Action, sh: &mut DiffShared, _: bool) -> Handled {
        match a {
            Action::Back => sh.answer = None,
            Action::NextDivergence => sh.jump(true),
            Action::PrevDivergence => sh.jump(false),
            Action::Why => sh.ask_why(),
            _ => return Handled::Ignored,
        }
        Handled::Taken
    }

    fn hints(&self, _: &DiffShared) -> Hints {
        Hints::Keys(&[
            (Action::NextDivergence, "next divergence"),
            (Action::Why, "why did they diverge?"),
        ])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "the divergences",
            anywhere: &[
                (Action::NextDivergence, "the next divergence"),
                (Action::PrevDivergence, "the previous divergence"),
                (Action::Why, "why did the runs diverge? (first divergence)"),
                (Action::Back, "close the answer"),
            ],
            focused: &[],
        }
    }

    fn draw(&self, sh: &DiffShared, f: &mut Frame, area: Rect, _: bool) {
        summary_pane(sh, f, area)
    }
}

/// The two timelines, moved together: a step, a tick, the start, the end.
pub struct Timelines;

impl Component<DiffShared> for Timelines {
    fn key(&mut self, a: Action, sh: &mut DiffShared, _: bool) -> Handled {
        match a {
            Action::StepForward => sh.step(1),
            Action::StepBack => sh.step(-1),
            Action::TickForward | Action::TickBack => {
                if let Some(m) = sh.a.moment().or(sh.b.moment()) {
                    let t = if a == Action::TickForward {
                        m.tick + 1
                    } else {
                        m.tick.saturating_sub(1)
                    };
                    sh.a.go_to_tick(t);
                    sh.b.go_to_tick(t);
                }
            }
            Action::Start => {
                sh.a.go_to_tick(1);
                sh.b.go_to_tick(1);
                sh.selected = 0;
            }
            Action::End => {
                sh.a.go_to_pos(sh.a.len());
                sh.b.go_to_pos(sh.b.len());
            }
            _ => return Handled::Ignored,
        }
        Handled::Taken
    }

    fn hints(&self, _: &DiffShared) -> Hints {
        Hints::Keys(&[(Action::StepForward, "step"), (Action::TickForward, "tick")])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "the two timelines, moved together",
            anywhere: &[
                (Action::StepForward, ""),
                (Action::StepBack, ""),
                (Action::TickForward, ""),
                (Action::TickBack, ""),
                (Action::Start, ""),
                (Action::End, ""),
            ],
            focused: &[],
        }
    }

    fn draw(&self, sh: &DiffShared, f: &mut Frame, area: Rect, _: bool) {
        f.render_widget(
            Paragraph::new(vec![timeline_line(&sh.a, "A"), timeline_line(&sh.b, "B")]),
            area,
        );
    }
}

/// The diff's own keys, for the help.
pub const DIFF_KEYS: KeyHelp = KeyHelp {
    name: "the diff",
    anywhere: &[(Action::Help, ""), (Action::Quit, "")],
    focused: &[],
};

/// The diff's keys, over the panes: ↑↓, a page, Home and End scroll it,
/// any other key closes it.
pub struct DiffHelp {
    /// The keys in force, as the help lists them.
    pub keymap: Keymap,
    /// The diff's own keys and each pane's.
    pub parts: Vec<KeyHelp>,
    /// How far it is scrolled.
    pub scroll: Lines,
}

impl Component<DiffShared> for DiffHelp {
    fn key(&mut self, a: Action, _: &mut DiffShared, _: bool) -> Handled {
        if self.scroll.key(a, 0) {
            Handled::Taken
        } else {
            Handled::Close
        }
    }

    fn hints(&self, _: &DiffShared) -> Hints {
        Hints::Text("↑↓ scroll  Esc or ? closes the help")
    }

    fn draw(&self, _: &DiffShared, f: &mut Frame, area: Rect, _: bool) {
        help(&self.keymap, &self.parts, &self.scroll, f, area)
    }
}
