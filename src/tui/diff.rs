//! The side-by-side view of `btx open --diff A B` (Han et al. Fig. 14): two
//! trees aligned row by row and scrolled together, divergent leaves and
//! their parents highlighted, an edit summary per subgoal, and for two runs
//! timelines that move together. The comparison and the answer to "why did
//! they diverge?" come from the library (`diff`, `causal::compare`).

use super::keymap::{Action, Keymap};
use crate::diff::{Diff, Op, Side};
use crate::model::{Tree, Uid};
use crate::session::{Moment, Session};
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

pub struct DiffApp {
    pub a: Pane,
    pub b: Pane,
    pub diff: Diff,
    pub rows: Vec<Row>,
    pub selected: usize,
    /// Which divergence the last jump went to (index into `diff.divergences()`).
    pub divergence: Option<usize>,
    /// The answer to "why did they diverge?", as text.
    pub answer: Option<String>,
    pub help: bool,
    pub message: Option<String>,
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
        let rows = Self::align(&a, &b, &diff);
        DiffApp {
            a,
            b,
            diff,
            rows,
            selected: 0,
            divergence: None,
            answer: None,
            help: false,
            message: None,
            quit: false,
            keymap: Keymap::default(),
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

    pub fn update(&mut self, act: Action) {
        self.message = None;
        if self.help {
            self.help = matches!(act, Action::Up | Action::Down);
            if matches!(act, Action::Quit) {
                self.quit = true;
            }
            return;
        }
        let last = self.rows.len().saturating_sub(1);
        match act {
            Action::Quit => self.quit = true,
            Action::Help => self.help = true,
            Action::Back => self.answer = None,
            Action::Up => self.selected = self.selected.saturating_sub(1),
            Action::Down => self.selected = (self.selected + 1).min(last),
            Action::NextDivergence => self.jump(true),
            Action::PrevDivergence => self.jump(false),
            Action::Why => self.ask_why(),
            Action::StepForward => self.step(1),
            Action::StepBack => self.step(-1),
            Action::TickForward | Action::TickBack => {
                if let Some(m) = self.a.moment().or(self.b.moment()) {
                    let t = if act == Action::TickForward {
                        m.tick + 1
                    } else {
                        m.tick.saturating_sub(1)
                    };
                    self.a.go_to_tick(t);
                    self.b.go_to_tick(t);
                }
            }
            Action::Start => {
                self.a.go_to_tick(1);
                self.b.go_to_tick(1);
                self.selected = 0;
            }
            Action::End => {
                self.a.go_to_pos(self.a.len());
                self.b.go_to_pos(self.b.len());
            }
            // No key is silent (#27 item 2): what the diff does instead.
            other => {
                self.message = Some(format!(
                    "{} is not in the side-by-side diff: d/D divergences, n/p step, w why, ? keys",
                    super::keymap::Action::name(other).replace('_', " ")
                ))
            }
        }
    }

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

    /// The hints for the status bar, with the keys in force.
    pub fn hints(&self) -> String {
        let mut out = Vec::new();
        // Stepping and "why" are about runs; two trees have neither.
        let runs = self.a.session.is_some() && self.b.session.is_some();
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
