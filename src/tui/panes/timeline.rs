//! The timeline: where the run is (stepping, ticks, failures, playing) and
//! the list of transitions, which scrolls and filters.

use super::overlays::Overlay;
use super::{Component, Handled, Hints, KeyHelp, Scrolled, PAGE};
use crate::run::Status;
use crate::tui::keymap::Action;
use crate::tui::shared::Shared;
use crate::tui::view::*;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

/// The timeline: its own state is the transition list's.
#[derive(Debug, Clone, Default)]
pub struct Timeline {
    /// Transitions the list is moved from the moment.
    scroll: Scrolled<i64>,
    /// Which transitions the list shows.
    pub filter: crate::export::LogFilter,
}

impl Timeline {
    /// Up, Down and a page scroll the list.
    pub fn scroll(&mut self, a: Action, sh: &Shared) -> bool {
        *self.scroll.get_mut(sh.moved) += match a {
            Action::Up => -1,
            Action::Down => 1,
            Action::PageUp => -(PAGE as i64),
            Action::PageDown => PAGE as i64,
            _ => return false,
        };
        true
    }
}

/// Keys that mean nothing without a run.
pub fn needs_run(a: Action) -> bool {
    matches!(
        a,
        Action::StepForward
            | Action::StepBack
            | Action::TickForward
            | Action::TickBack
            | Action::Start
            | Action::End
            | Action::NextFailure
            | Action::PrevFailure
            | Action::NextChange
            | Action::PrevChange
            | Action::Why
            | Action::Play
            | Action::HideResets
            | Action::OnlyBelow
            | Action::OnlyStatus
    )
}

impl Timeline {
    /// How far the list is moved from the moment.
    pub fn scrolled(&self, sh: &Shared) -> i64 {
        self.scroll.get(sh.moved)
    }

    /// Shows only the transitions of nodes named `text` (all: empty).
    pub fn set_filter(&mut self, text: String, sh: &Shared) {
        self.filter.text = text;
        *self.scroll.get_mut(sh.moved) = 0;
    }

    /// Keys while the timeline has the focus: the list scrolls, and `/`
    /// filters it by text.
    fn focused_key(&mut self, a: Action, sh: &Shared) -> Handled {
        if a == Action::Find {
            return Handled::Open(Overlay::filter(&self.filter.text));
        }
        Handled::taken(self.scroll(a, sh))
    }

    /// Time, whichever pane has the focus: steps, ticks, failures, changes
    /// of the selected node, playing, and the list's filters.
    fn time_key(&mut self, a: Action, sh: &mut Shared) -> bool {
        match a {
            Action::StepForward => sh.goto(sh.pos + 1),
            Action::StepBack => sh.goto(sh.pos.saturating_sub(1)),
            Action::TickForward | Action::TickBack => {
                let t = sh.current_tick();
                let at_end = sh.tick_end(t) == Some(sh.pos);
                let target = match a {
                    Action::TickForward if at_end => t + 1,
                    Action::TickForward => t,
                    _ => t.saturating_sub(1),
                };
                sh.goto_tick(target.max(1));
            }
            Action::Start => sh.goto_tick(1),
            Action::End => sh.goto(sh.positions()),
            Action::NextFailure | Action::PrevFailure => {
                Self::goto_failure(sh, a == Action::NextFailure)
            }
            Action::Follow => {
                sh.follow_node = !sh.follow_node;
                sh.follow_current();
                sh.message = Some(if sh.follow_node {
                    "following the current node as the run moves".into()
                } else {
                    "the selection stays where it is as the run moves".into()
                });
            }
            Action::NextChange | Action::PrevChange => {
                Self::goto_change(sh, a == Action::NextChange)
            }
            Action::Play => sh.playing = !sh.playing && sh.session.is_some(),
            Action::Faster | Action::Slower => {
                sh.play_ms = if a == Action::Faster {
                    (sh.play_ms / 2).max(10)
                } else {
                    (sh.play_ms * 2).min(5000)
                };
                // While paused the speed is shown nowhere else (#27 item 2).
                if !sh.playing {
                    sh.message = Some(format!(
                        "play speed: a step every {} ms (s plays)",
                        sh.play_ms
                    ));
                }
            }
            Action::HideResets => self.filter.no_idle = !self.filter.no_idle,
            Action::OnlyBelow => {
                self.filter.below = match self.filter.below {
                    Some(_) => None,
                    None => Some(sh.selected),
                }
            }
            Action::OnlyStatus => {
                self.filter.status = match self.filter.status {
                    None => Some(Status::Running),
                    Some(Status::Running) => Some(Status::Success),
                    Some(Status::Success) => Some(Status::Failure),
                    _ => None,
                }
            }
            _ => return false,
        }
        true
    }

    /// To the end of the next (previous) tick in which a leaf's failure was
    /// a fault (not a branch taken), with that leaf selected.
    fn goto_failure(sh: &mut Shared, next: bool) {
        let t = sh.current_tick();
        let at_end = sh.tick_end(t) == Some(sh.pos);
        let ticks = sh.failure_ticks();
        let target = if next {
            ticks.into_iter().find(|&x| x > t || (x == t && !at_end))
        } else {
            ticks.into_iter().rev().find(|&x| x < t)
        };
        if let Some((x, p)) = target.and_then(|x| Some((x, sh.tick_end(x)?))) {
            sh.goto(p);
            // Land on the leaf that failed (the tick's last failure).
            if let Some(u) = sh.failed_leaf(x) {
                sh.reveal(u);
                sh.selected = sh.visible_for(u);
            }
        } else {
            sh.message = Some(format!(
                "no fault {} tick {t}",
                if next { "after" } else { "before" }
            ));
        }
    }

    /// To the next (previous) moment the selected node changes status.
    fn goto_change(sh: &mut Shared, next: bool) {
        let Some(s) = &sh.session else { return };
        let changes = s.index.changes_of(sh.selected);
        let target = if next {
            changes.iter().copied().find(|&p| p > sh.pos)
        } else {
            changes.iter().copied().rev().find(|&p| p < sh.pos)
        };
        if let Some(p) = target {
            let keep = sh.selected;
            sh.goto(p);
            sh.selected = keep;
        } else {
            sh.message = Some(format!(
                "{} does not change {} this moment",
                crate::text::visible(sh.tree.description(sh.selected)),
                if next { "after" } else { "before" }
            ));
        }
    }
}

/// The indices of the transitions the list shows: `rows` of those the
/// filters keep, the moment's (or the last kept before it) in the middle,
/// moved by the pane's scroll. Only as far from the moment as it must look.
impl Timeline {
    fn shown_transitions(
        &self,
        sh: &Shared,
        s: &crate::session::Session,
        rows: usize,
    ) -> Vec<usize> {
        let scroll = self.scrolled(sh);
        let total = s.index.transitions.len();
        let f = &self.filter;
        let keeps = |i: usize| f.keeps(&s.tree, &s.index.transitions[i]);
        let pos = sh.pos as usize;
        // Kept transitions at or before the moment, nearest first, and after it.
        let before: Vec<usize> = (0..pos.min(total))
            .rev()
            .filter(|&i| keeps(i))
            .take(rows + 1 + scroll.unsigned_abs() as usize)
            .collect();
        let after: Vec<usize> = (pos.min(total)..total)
            .filter(|&i| keeps(i))
            .take(rows + scroll.max(0) as usize)
            .collect();
        let mut all: Vec<usize> = before.into_iter().rev().collect();
        let here = all.len();
        all.extend(after);
        let start = (here as i64 - (rows / 2) as i64 + scroll)
            .clamp(0, all.len().saturating_sub(rows) as i64) as usize;
        all.into_iter().skip(start).take(rows).collect()
    }
}

impl Component for Timeline {
    fn key(&mut self, a: Action, sh: &mut Shared, focused: bool) -> Handled {
        if focused {
            let h = self.focused_key(a, sh);
            if h != Handled::Ignored {
                return h;
            }
        }
        Handled::taken(self.time_key(a, sh))
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Keys(&[(Action::NextPane, "next pane")])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "timeline",
            anywhere: &[
                (Action::StepForward, ""),
                (Action::StepBack, ""),
                (Action::TickForward, ""),
                (Action::TickBack, ""),
                (Action::Start, ""),
                (Action::End, ""),
                (Action::NextFailure, ""),
                (Action::PrevFailure, ""),
                (Action::NextChange, ""),
                (Action::PrevChange, ""),
                (Action::Follow, ""),
                (Action::Play, ""),
                (Action::Faster, ""),
                (Action::Slower, ""),
                (Action::HideResets, ""),
                (Action::OnlyBelow, ""),
                (Action::OnlyStatus, ""),
            ],
            focused: &[
                (Action::Up, "scroll the transitions up"),
                (Action::Down, "scroll the transitions down"),
                (Action::PageUp, "a page of transitions up"),
                (Action::PageDown, "a page of transitions down"),
                (Action::Find, "show only the transitions of nodes named so"),
            ],
        }
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, focused: bool) {
        let b = block(self.title(sh), focused);
        let inner = b.inner(area);
        f.render_widget(b, area);
        let Some(s) = &sh.session else {
            f.render_widget(
                Paragraph::new("no run: open a session to step through it"),
                inner,
            );
            return;
        };
        let m = sh
            .shown_moment()
            .unwrap_or_else(|| s.index.at(sh.pos).moment());
        let mut lines = vec![head(sh, s, m, inner.width as usize)];
        // A strip of what the selected node did in each tick around now, and
        // its tick axis.
        let width = inner.width.saturating_sub(10) as u32;
        let start = m.tick.saturating_sub(width / 2).max(1);
        let end = (start + width).min(s.index.ticks());
        lines.push(strip(sh, s, m, start..=end));
        lines.push(axis(start..=end));
        // The transitions around the moment (those the filters keep).
        let around = (inner.height as usize).saturating_sub(3);
        for i in self.shown_transitions(sh, s, around) {
            lines.push(transition_row(s, i, i + 1 == sh.pos as usize));
        }
        f.render_widget(Paragraph::new(lines), inner);
    }
}

impl Timeline {
    /// The pane's title: how the run ended (a live robot's status and faults),
    /// and the filters that hide transitions.
    fn title(&self, sh: &Shared) -> String {
        let mut title = match (&sh.live, &sh.session) {
            (Some(l), Some(s)) => {
                // How far behind goes first: the status line is long.
                let behind = s.index.transitions.len().saturating_sub(sh.pos as usize);
                let mut title = format!(
                    " timeline · {}{} ",
                    if behind > 0 {
                        format!("{behind} transitions behind live · ")
                    } else {
                        String::new()
                    },
                    crate::text::visible(&l.status.line()),
                );
                let t = &sh.live_faults;
                if t.faults > 0 {
                    title.push_str(&format!(
                        "· faults: {} open, {} recovered, {} not ",
                        t.open, t.recovered, t.not_recovered
                    ));
                }
                title
            }
            (_, Some(s)) => format!(" timeline · run {} ", crate::text::visible(&s.ending())),
            _ => " timeline ".into(),
        };
        let lf = &self.filter;
        if !lf.is_empty() {
            let mut parts = Vec::new();
            if lf.no_idle {
                parts.push("no resets".to_string());
            }
            if let Some(u) = lf.below {
                parts.push(format!("#{u} and below"));
            }
            if let Some(st) = lf.status {
                parts.push(format!("to {}", st.as_str()));
            }
            if !lf.text.is_empty() {
                parts.push(format!("\"{}\"", crate::text::visible(&lf.text)));
            }
            title.push_str(&format!("· showing {} ", parts.join(", ")));
        }
        title
    }
}

/// The moment, its tick and transition of the run's, and the strip's
/// legend as far as it fits in `width`.
fn head(
    sh: &Shared,
    s: &crate::session::Session,
    m: crate::session::Moment,
    width: usize,
) -> Line<'static> {
    let ticks = s.index.ticks();
    let total = s.index.transitions.len();
    let mut play = if sh.playing {
        format!("  ▶ playing every {} ms", sh.play_ms)
    } else {
        String::new()
    };
    if sh.follow.is_some() {
        play.push_str("  · following the log");
    }
    // The first part of a long log, while the rest is read: more to come.
    let more = if sh.reading.is_some() {
        play.push_str("  · reading the rest of the log");
        "+"
    } else {
        ""
    };
    let head = match &sh.live {
        // A robot watched before its first tick is numbered: "tick 1 of 0"
        // says nothing true.
        Some(l) if ticks == 0 => match &l.status.finished {
            Some(f) => format!("no tick came: {f}"),
            None if l.status.transitions > 0 => {
                format!(
                    "{} transitions came; their first tick is not over yet",
                    l.status.transitions
                )
            }
            None => "waiting for the robot's first tick".to_string(),
        },
        _ => format!(
            "moment {m}  ·  tick {} of {ticks}{more}  ·  transition {} of {total}{more}{play}",
            m.tick, sh.pos
        ),
    };
    let room = width.saturating_sub(head.chars().count() + 4);
    // The strip's legend, shorter where the long one does not fit.
    let legend = first_fitting(
        &[
            "strip: ▆ running ▃ failed ▂ succeeded ⊘ halted · not ticked",
            "▆ running ▃ failed ▂ succeeded ⊘ halted · not run",
            "▆ run ▃ fail ▂ ok ⊘ halt · not run",
        ],
        room,
    );
    Line::from(vec![
        Span::raw(head),
        Span::styled(
            if legend.is_empty() {
                String::new()
            } else {
                format!("    {legend}")
            },
            Style::default().fg(Color::DarkGray),
        ),
    ])
}

/// What the selected node did in each of the ticks: a status only where
/// it ran, `·` where it did not, blank before it first ran; the moment's
/// tick reversed.
fn strip(
    sh: &Shared,
    s: &crate::session::Session,
    m: crate::session::Moment,
    ticks: std::ops::RangeInclusive<u32>,
) -> Line<'static> {
    use crate::session::TickMark;
    let mut strip = vec![Span::raw(format!("#{:<4} ", sh.selected))];
    for t in ticks {
        let (c, color) = match s.index.tick_mark(sh.selected, t) {
            TickMark::Running => ('▆', status_color(Status::Running)),
            TickMark::Done(Status::Failure) => ('▃', status_color(Status::Failure)),
            TickMark::Done(_) => ('▂', status_color(Status::Success)),
            TickMark::Halted => ('⊘', status_color(Status::Idle)),
            TickMark::NotTicked => ('·', status_color(Status::Idle)),
            TickMark::NotYet => (' ', status_color(Status::Idle)),
        };
        let mut style = Style::default().fg(color);
        if t == m.tick {
            style = style.add_modifier(Modifier::REVERSED);
        }
        strip.push(Span::styled(c.to_string(), style));
    }
    Line::from(strip)
}

/// The strip's tick axis: a mark and the number every ten ticks.
fn axis(ticks: std::ops::RangeInclusive<u32>) -> Line<'static> {
    let mut axis = String::from("tick  ");
    let mut t = *ticks.start();
    while t <= *ticks.end() {
        if t.is_multiple_of(10) || t == 1 {
            let label = format!("╵{t}");
            axis.push_str(&label);
            let skip = label.chars().count() as u32;
            t += skip;
        } else {
            axis.push(' ');
            t += 1;
        }
    }
    Line::from(Span::styled(axis, Style::default().fg(Color::DarkGray)))
}

/// Transition `i` as a row: its tick, node, and the statuses it changed
/// between; reversed `here`; a live run's gap before it said.
fn transition_row(s: &crate::session::Session, i: usize, here: bool) -> Line<'static> {
    let t = s.index.transitions[i];
    let style = if here {
        Style::default().add_modifier(Modifier::REVERSED)
    } else {
        Style::default()
    };
    Line::from(vec![
        Span::styled(
            format!(
                "{:>5} #{:<4} {:<32} ",
                t.tick,
                t.uid,
                truncate(&crate::text::visible(s.tree.description(t.uid)), 32)
            ),
            style,
        ),
        Span::styled(
            format!("{:<8}", t.prev.as_str()),
            Style::default().fg(status_color(t.prev)),
        ),
        Span::raw(" → "),
        Span::styled(
            t.status.as_str(),
            Style::default().fg(status_color(t.status)),
        ),
        // A live run's gap just before this transition.
        Span::styled(
            if s.index.gaps.iter().any(|g| g.0 as usize == i) {
                "  ⋯ gap before: transitions may be missing"
            } else {
                ""
            },
            Style::default().fg(Color::Yellow),
        ),
    ])
}
