//! The side-by-side view of `btx open --diff A B` (Han et al. Fig. 14): two
//! trees aligned row by row and scrolled together, divergent leaves and
//! their parents highlighted, an edit summary per subgoal, and for two runs
//! timelines that move together. The comparison and the answer to "why did
//! they diverge?" come from the library (`diff`, `causal::compare`).
//!
//! Its panes are components as the explorer's are (`panes::Component`,
//! over [`DiffShared`]): the two trees scrolled together, the edit summary
//! (divergences and the why), the two timelines, and the help window. The
//! app routes keys and draws them in their places.

pub mod panes;

pub use panes::{DIVERGENT, PARENT};

use super::keymap::{Action, Keymap};
use super::panes::{Component, Handled};
use crate::diff::{Diff, Op, Side};
use crate::model::{Tree, Uid};
use crate::session::{Moment, Session};
use panes::{DiffHelp, Summary, Timelines, Trees};
use ratatui::layout::{Constraint, Direction, Layout};
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;
use std::collections::HashSet;

/// One compared input.
pub struct Pane {
    pub name: String,
    pub tree: Tree,
    pub session: Option<Session>,
    /// The moment shown, as a position in the session.
    pub pos: u32,
    /// The tick last moved to: a tick without transitions ends where the
    /// one before did, so the position alone cannot tell them apart.
    tick: u32,
    /// Leaves that diverge, and their parents (Fig. 14's two colours).
    pub divergent: HashSet<Uid>,
    pub parents: HashSet<Uid>,
    /// Leaves that only ran (or did not) because the runs had parted.
    pub following: HashSet<Uid>,
}

impl Pane {
    fn side(&self) -> Side<'_> {
        match &self.session {
            Some(s) => Side::session(self.name.clone(), s),
            None => Side::tree(self.name.clone(), &self.tree),
        }
    }

    fn len(&self) -> u32 {
        self.session
            .as_ref()
            .map_or(0, |s| s.index.transitions.len() as u32)
    }

    /// The moment shown, if this is a run.
    pub fn moment(&self) -> Option<Moment> {
        let s = self.session.as_ref()?;
        let end = Moment {
            tick: self.tick,
            step: None,
        };
        Some(if s.index.position(end) == Ok(self.pos) {
            end
        } else {
            s.index.moment(self.pos)
        })
    }

    fn go_to_tick(&mut self, tick: u32) {
        if let Some(s) = &self.session {
            let t = tick.clamp(1, s.index.ticks().max(1));
            self.pos = s
                .index
                .position(Moment {
                    tick: t,
                    step: None,
                })
                .unwrap_or(0);
            self.tick = t;
        }
    }

    fn go_to_pos(&mut self, pos: u32) {
        if let Some(s) = &self.session {
            self.pos = pos.min(s.index.transitions.len() as u32);
            self.tick = s.index.moment(self.pos).tick;
        }
    }
}

/// A row of the aligned trees: a node of A, of B, or of both, with depths.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Row {
    pub a: Option<(Uid, usize)>,
    pub b: Option<(Uid, usize)>,
}

/// What the diff's panes share: the two sides, their comparison and
/// aligned rows, the selection, the divergence last jumped to, and the
/// answer and message shown.
pub struct DiffShared {
    pub a: Pane,
    pub b: Pane,
    pub diff: Diff,
    pub rows: Vec<Row>,
    pub selected: usize,
    /// Which divergence the last jump went to (index into `diff.divergences()`).
    pub divergence: Option<usize>,
    /// The answer to "why did they diverge?", as text.
    pub answer: Option<String>,
    pub message: Option<String>,
}

pub struct DiffApp {
    pub shared: DiffShared,
    trees: Trees,
    summary: Summary,
    timelines: Timelines,
    /// The help window, when open.
    pub help: Option<DiffHelp>,
    pub quit: bool,
    pub keymap: Keymap,
}

/// Every node with its depth, in tree order.
fn rows_of(tree: &Tree) -> Vec<(Uid, usize)> {
    tree.descendants(Tree::ROOT)
        .map(|u| (u, tree.ancestors(u).count()))
        .collect()
}

impl DiffApp {
    pub fn new(a: (String, Tree, Option<Session>), b: (String, Tree, Option<Session>)) -> DiffApp {
        let pane = |(name, tree, session): (String, Tree, Option<Session>)| {
            let pos = session.as_ref().map_or(0, |s| {
                s.index
                    .position(Moment {
                        tick: 1,
                        step: None,
                    })
                    .unwrap_or(0)
            });
            Pane {
                name,
                tree,
                session,
                pos,
                tick: 1,
                divergent: HashSet::new(),
                parents: HashSet::new(),
                following: HashSet::new(),
            }
        };
        let (mut a, mut b) = (pane(a), pane(b));
        let diff = Diff::new(&a.side(), &b.side());
        let (da, db) = diff.divergent_nodes();
        for (p, nodes) in [(&mut a, da), (&mut b, db)] {
            for u in nodes {
                p.divergent.insert(u);
                if let Some(parent) = p.tree.parent(u) {
                    p.parents.insert(parent);
                }
            }
        }
        let (fa, fb) = diff.following_nodes();
        for (p, nodes) in [(&mut a, fa), (&mut b, fb)] {
            let only = nodes.into_iter().filter(|u| !p.divergent.contains(u));
            p.following.extend(only.collect::<Vec<_>>());
        }
        let rows = align(&a, &b, &diff);
        DiffApp {
            shared: DiffShared {
                a,
                b,
                diff,
                rows,
                selected: 0,
                divergence: None,
                answer: None,
                message: None,
            },
            trees: Trees,
            summary: Summary,
            timelines: Timelines,
            help: None,
            quit: false,
            keymap: Keymap::default(),
        }
    }

    /// A key: to the help when it is open, else quit and help, else each
    /// pane in turn (the diff has no focus: its keys are each one pane's).
    pub fn update(&mut self, act: Action) {
        let sh = &mut self.shared;
        sh.message = None;
        if let Some(help) = &mut self.help {
            if matches!(act, Action::Quit) {
                self.quit = true;
            }
            if help.key(act, sh, true) == Handled::Close {
                self.help = None;
            }
            return;
        }
        match act {
            Action::Quit => self.quit = true,
            Action::Help => {
                let parts = [
                    panes::DIFF_KEYS,
                    self.trees.help(),
                    self.summary.help(),
                    self.timelines.help(),
                ];
                self.help = Some(DiffHelp {
                    keymap: self.keymap.clone(),
                    parts: parts.to_vec(),
                    scroll: Default::default(),
                })
            }
            _ => {
                let parts: [&mut dyn Component<DiffShared>; 3] =
                    [&mut self.trees, &mut self.summary, &mut self.timelines];
                let taken = parts
                    .into_iter()
                    .any(|p| p.key(act, sh, true) != Handled::Ignored);
                // No key is silent (#27 item 2): what the diff does instead.
                if !taken {
                    sh.message = Some(format!(
                        "{} is not in the side-by-side diff: d/D divergences, n/p step, w why, ? keys",
                        super::keymap::Action::name(act).replace('_', " ")
                    ))
                }
            }
        }
    }

    /// The two trees above, the summary, the timelines for runs, and the
    /// status line (a message wraps onto up to three rows); the help over
    /// them.
    pub fn view(&self, f: &mut Frame) {
        let sh = &self.shared;
        let runs = sh.a.session.is_some() || sh.b.session.is_some();
        let width = usize::from(f.area().width).max(1);
        let said: Vec<String> = sh
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
                Constraint::Length(if sh.answer.is_some() { 10 } else { 6 }),
                Constraint::Length(if runs { 2 } else { 0 }),
                Constraint::Length(rows),
            ])
            .split(f.area());
        self.trees.draw(sh, f, v[0], false);
        self.summary.draw(sh, f, v[1], false);
        if runs {
            self.timelines.draw(sh, f, v[2], false);
        }
        let status: Vec<Line> = match sh.message {
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
                self.hints(),
                Style::default().fg(Color::DarkGray),
            ))],
        };
        f.render_widget(Paragraph::new(status), v[3]);
        if let Some(help) = &self.help {
            help.draw(sh, f, f.area(), true);
        }
    }

    /// The hints for the status bar, with the keys in force.
    pub fn hints(&self) -> String {
        let mut out = Vec::new();
        // Stepping and "why" are about runs; two trees have neither.
        let runs = self.shared.a.session.is_some() && self.shared.b.session.is_some();
        for (a, what) in [
            (Action::NextDivergence, "next divergence"),
            (Action::StepForward, "step"),
            (Action::TickForward, "tick"),
            (Action::Why, "why did they diverge?"),
            (Action::Help, "help"),
            (Action::Quit, "quit"),
        ] {
            if !runs && matches!(a, Action::StepForward | Action::TickForward | Action::Why) {
                continue;
            }
            if let Some(k) = self.keymap.key_of(a) {
                out.push(format!("{k} {what}"));
            }
        }
        out.join("  ")
    }
}

/// The two trees' rows aligned by a shortest edit script. Inner nodes
/// match by depth, type and name; leaves of two trees match only where
/// the action diff keeps them (so a divergent leaf faces a gap, as in
/// Fig. 14); two runs of one tree show the tree once, row for row.
fn align(a: &Pane, b: &Pane, diff: &Diff) -> Vec<Row> {
    let (ra, rb) = (rows_of(&a.tree), rows_of(&b.tree));
    let by_pairs = !crate::diff::same_shape(&a.tree, &b.tree);
    let mut pairs = [
        std::collections::HashMap::new(),
        std::collections::HashMap::new(),
    ];
    if by_pairs {
        let mut k = 0usize;
        for sec in &diff.sections {
            for e in sec.edits.iter().filter(|e| e.op == Op::Same) {
                let (Some(i), Some(j)) = (e.a, e.b) else {
                    continue;
                };
                pairs[0].entry(sec.a[i].uid).or_insert(k);
                pairs[1].entry(sec.b[j].uid).or_insert(k);
                k += 1;
            }
        }
    }
    let key = |side: usize, t: &Tree, (u, d): (Uid, usize)| {
        if by_pairs && t.node(u).kind.is_leaf() {
            return match pairs[side].get(&u) {
                Some(k) => format!("=leaf {k}"),
                None => format!("{side}#{u}"),
            };
        }
        format!(
            "{d} {} {}",
            t.type_name(u),
            crate::text::visible(t.description(u))
        )
    };
    let ka: Vec<String> = ra.iter().map(|&r| key(0, &a.tree, r)).collect();
    let kb: Vec<String> = rb.iter().map(|&r| key(1, &b.tree, r)).collect();
    crate::diff::align::edits(&ka, &kb)
        .into_iter()
        .flat_map(|e| match e.op {
            Op::Changed => vec![
                Row {
                    a: e.a.map(|i| ra[i]),
                    b: None,
                },
                Row {
                    a: None,
                    b: e.b.map(|j| rb[j]),
                },
            ],
            _ => vec![Row {
                a: e.a.map(|i| ra[i]),
                b: e.b.map(|j| rb[j]),
            }],
        })
        .collect()
}
