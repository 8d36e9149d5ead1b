//! What the explorer's components share: the run, the moment, the
//! selection and the conversation (the answers asked for and their
//! history). The components read it to draw and change it through these
//! methods; every answer comes from the library.

use crate::explain::fault::is_fault;
use crate::explain::{answer, Answer, Question, RunQuestion, TreeQuestion};
use crate::frame::Framed;
use crate::model::{Builtin, Kind, Tree, Uid};
use crate::run::Status;
use crate::session::{At, Session};
use fuzzy_matcher::skim::SkimMatcherV2;
use fuzzy_matcher::FuzzyMatcher;
use std::collections::HashSet;

/// A why-answer on screen: the library's answer, the explanation picked,
/// and whether its causal model is shown.
pub struct WhyView {
    pub why: crate::causal::Why,
    pub selected: usize,
    pub graph: bool,
    /// The variable the graph view is centred on (None: the one asked about).
    pub centre: Option<crate::causal::model::VarId>,
    /// The cause or effect picked in the graph view (parents, then children).
    pub pick: Option<usize>,
}

/// Earlier answers kept for the ask pane.
pub const HISTORY_MAX: usize = 50;

/// A visible row of the tree pane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Row {
    pub uid: Uid,
    pub depth: usize,
    pub has_children: bool,
}

/// What writing the causal model to a file did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Exported {
    Written,
    /// A file is there: Enter again replaces it.
    Exists,
    Failed,
}

pub struct Shared {
    pub tree: Tree,
    pub session: Option<Session>,
    pub title: String,
    pub framed: Framed,
    pub framed_view: bool,
    pub collapsed: HashSet<Uid>,
    pub selected: Uid,
    /// The moment, as a position in the session (transitions applied).
    pub pos: u32,
    /// The tick stepped to with N/P when it ends where an earlier one did.
    pub at_tick: Option<u32>,
    /// Bumped each time the moment is set, even to where it was: the panes
    /// that scroll go back to their top for the new moment.
    pub moved: u64,
    /// Whether stepping selects the current node. On until the person
    /// selects a node themselves; `o` turns it on and off.
    pub follow_node: bool,
    pub answer: Option<Answer>,
    /// The answer to a question typed in the user's own words.
    pub reply: Option<crate::ask::Reply>,
    /// Other readings of the last question, when btx was not sure of its
    /// own: the ask prompt offers them to pick from.
    pub did_you_mean: Vec<String>,
    /// How much answers say (`+`/`-` on the answers pane).
    pub detail: crate::ask::Detail,
    pub why: Option<WhyView>,
    /// The node and moment the answer or why-answer on screen is about:
    /// the pane keeps saying so when the selection or the moment moves.
    pub asked: Option<(Uid, Option<String>)>,
    /// Earlier answers, most recent first, each with what it was about.
    pub history: Vec<String>,
    /// Bumped each time an answer is put on screen: the answers pane goes
    /// back to its top.
    pub answered: u64,
    /// Text waiting to be put on the clipboard by the terminal loop.
    pub clipboard: Option<String>,
    /// The finder's lines, made when it first opens (the tree is fixed).
    pub(crate) finder_labels: std::cell::OnceCell<Vec<String>>,
    /// A one-line message for the status bar (an error, a file written).
    pub message: Option<String>,
    pub playing: bool,
    /// Milliseconds between steps while playing.
    pub play_ms: u64,
    /// The key bindings in force (the help and the hints show these).
    pub keymap: super::keymap::Keymap,
    /// A log still being written, read again as it grows (`--follow`).
    pub follow: Option<crate::input::Follow>,
    /// A long log read whole while its first part is shown: moving
    /// through that part goes on, every other key waits for the whole.
    pub reading: Option<crate::input::Reading>,
    /// A robot running now (`btx open --live`): the run grows from it.
    pub live: Option<crate::live::Feed>,
    /// A live run's faults in numbers, for the timeline's title.
    pub live_faults: crate::explain::alerts::Tally,
    /// The other runs of the log, or the other robots watched (`R`).
    pub choices: Option<super::choices::Choices>,
    pub(crate) rows: Vec<Row>,
}

impl Shared {
    pub fn new(tree: Tree, session: Option<Session>, title: String) -> Shared {
        let framed = Framed::new(&tree);
        let pos = session.as_ref().map_or(0, |s| {
            s.index
                .position(crate::session::Moment {
                    tick: 1,
                    step: None,
                })
                .unwrap_or(0)
        });
        let mut shared = Shared {
            live_faults: Default::default(),
            tree,
            session,
            title,
            framed,
            framed_view: false,
            collapsed: HashSet::new(),
            selected: Tree::ROOT,
            pos,
            at_tick: None,
            moved: 0,
            answer: None,
            why: None,
            asked: None,
            history: Vec::new(),
            answered: 0,
            follow_node: true,
            reply: None,
            did_you_mean: Vec::new(),
            detail: crate::ask::Detail::Normal,
            finder_labels: std::cell::OnceCell::new(),
            clipboard: None,
            message: None,
            playing: false,
            play_ms: 200,
            keymap: super::keymap::Keymap::default(),
            follow: None,
            reading: None,
            live: None,
            choices: None,
            rows: Vec::new(),
        };
        shared.follow_current();
        shared.rebuild_rows();
        shared
    }

    /// The run's faults as a watch told them (the library's
    /// `explain::alerts`), newest first, each with where it happened (a
    /// position of the run) and the node to select there.
    pub fn fault_lines(&self) -> Vec<(String, u32, Uid)> {
        let Some(s) = &self.session else {
            return Vec::new();
        };
        crate::explain::alerts::of_run(s)
            .into_iter()
            .rev()
            .filter_map(|a| {
                let m = crate::session::Moment {
                    tick: a.tick,
                    step: Some(a.step),
                };
                let p = s.index.position(m).ok()?;
                let u = a
                    .root_cause
                    .filter(|_| a.what == crate::explain::alerts::What::Fault);
                Some((a.text, p, u.unwrap_or(a.node)))
            })
            .collect()
    }

    /// The why-questions about the selected node at this moment, as
    /// (target, question); none, with the reason said, where there are none.
    pub fn why_targets(&mut self) -> Vec<(String, String)> {
        let (Some(s), Some(m)) = (&self.session, self.moment()) else {
            self.message = Some("why-questions are about a run: open a session or a log".into());
            return Vec::new();
        };
        let targets = crate::causal::session_domain(s, None)
            .and_then(|d| crate::causal::why_targets(s, d, self.selected, m));
        match targets {
            Ok(targets) if !targets.is_empty() => return targets,
            Ok(_) => self.message = Some("nothing to ask why about here".into()),
            Err(e) => self.message = Some(e.to_string()),
        }
        Vec::new()
    }

    /// Writes the why-answer's causal model (DOT) to `path`, replacing a
    /// file there only if `replace`.
    pub fn export_to(&mut self, path: &str, replace: bool) -> Exported {
        let Some(w) = &self.why else {
            return Exported::Failed;
        };
        let dot = crate::causal::graph::dot(&w.why.model);
        match crate::export::write_file(std::path::Path::new(path), dot.as_bytes(), replace) {
            Ok(crate::export::Written::Done) => {
                self.message = Some(format!("wrote {path}"));
                Exported::Written
            }
            Ok(crate::export::Written::Exists) => Exported::Exists,
            Err(e) => {
                self.message = Some(format!("{path}: {e}"));
                Exported::Failed
            }
        }
    }

    /// Selects `u`, shown (its ancestors unfolded), as the person's choice.
    pub fn select(&mut self, u: Uid) {
        self.reveal(u);
        self.selected = self.visible_for(u);
        self.follow_node = false;
    }

    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// The run at the current moment, if there is a run.
    pub fn at(&self) -> Option<At<'_>> {
        self.session.as_ref().map(|s| s.index.at(self.pos))
    }

    pub fn status(&self, uid: Uid) -> Status {
        self.at().map_or(Status::Idle, |a| a.status(uid))
    }

    /// Rebuilds the visible rows after expanding, collapsing or switching view.
    pub fn rebuild_rows(&mut self) {
        let mut rows = Vec::new();
        if self.framed_view {
            let mut stack = vec![(0usize, 0usize)];
            while let Some((i, depth)) = stack.pop() {
                let f = &self.framed.nodes[i];
                rows.push(Row {
                    uid: f.uid,
                    depth,
                    has_children: !f.children.is_empty(),
                });
                if !self.collapsed.contains(&f.uid) {
                    stack.extend(f.children.iter().rev().map(|&c| (c, depth + 1)));
                }
            }
        } else {
            let mut stack = vec![(Tree::ROOT, 0usize)];
            while let Some((u, depth)) = stack.pop() {
                let n = self.tree.node(u);
                rows.push(Row {
                    uid: u,
                    depth,
                    has_children: !n.children.is_empty(),
                });
                if !self.collapsed.contains(&u) {
                    stack.extend(n.children.iter().rev().map(|&c| (c, depth + 1)));
                }
            }
        }
        self.rows = rows;
        if self.row_of(self.selected).is_none() {
            // The selection was folded away (or is not in the framed view):
            // select its nearest visible ancestor.
            let visible: HashSet<Uid> = self.rows.iter().map(|r| r.uid).collect();
            self.selected = self
                .tree
                .ancestors(self.selected)
                .find(|a| visible.contains(a))
                .unwrap_or(Tree::ROOT);
        }
    }

    pub fn row_of(&self, uid: Uid) -> Option<usize> {
        self.rows.iter().position(|r| r.uid == uid)
    }

    /// Makes a node visible: expands its ancestors.
    pub(crate) fn reveal(&mut self, uid: Uid) {
        let anc: Vec<Uid> = self.tree.ancestors(uid).collect();
        for a in anc {
            self.collapsed.remove(&a);
        }
        self.rebuild_rows();
    }

    /// Selects the current node of the moment, as Groot keeps it in view.
    pub(crate) fn follow_current(&mut self) {
        if !self.follow_node {
            return;
        }
        if let Some(cur) = self.at().and_then(|a| a.current()) {
            self.selected = self.visible_for(cur);
            self.reveal(cur);
        }
    }

    /// In the framed view, a folded node is shown by its framed ancestor.
    pub(crate) fn visible_for(&self, uid: Uid) -> Uid {
        if !self.framed_view || self.framed.nodes.iter().any(|f| f.uid == uid) {
            return uid;
        }
        self.tree
            .ancestors(uid)
            .find(|a| self.framed.nodes.iter().any(|f| f.uid == *a))
            .unwrap_or(Tree::ROOT)
    }

    pub(crate) fn positions(&self) -> u32 {
        self.session
            .as_ref()
            .map_or(0, |s| s.index.transitions.len() as u32)
    }

    pub(crate) fn goto(&mut self, pos: u32) {
        self.pos = pos.min(self.positions());
        self.at_tick = None;
        // An answer about the moment left goes to the history, said with
        // its moment (a why-answer stays: it names its own).
        if self.answer.is_some() {
            self.remember_answer();
        }
        self.answer = None;
        self.moved += 1;
        self.follow_current();
    }

    /// Goes to the end of tick `t`, which may have no transition of its
    /// own (a leaf kept RUNNING): several ticks then end at one position,
    /// and the tick is kept apart from it.
    pub(crate) fn goto_tick(&mut self, t: u32) {
        if let Some(p) = self.tick_end(t) {
            self.goto(p);
            self.at_tick = Some(t);
        }
    }

    /// The moment shown: the tick stepped to, or the position's moment.
    pub fn shown_moment(&self) -> Option<crate::session::Moment> {
        match self.at_tick {
            Some(tick) => Some(crate::session::Moment { tick, step: None }),
            None => self.at().map(|a| a.moment()),
        }
    }

    pub(crate) fn tick_end(&self, tick: u32) -> Option<u32> {
        let s = self.session.as_ref()?;
        s.index
            .position(crate::session::Moment { tick, step: None })
            .ok()
    }

    pub(crate) fn current_tick(&self) -> u32 {
        self.shown_moment().map_or(0, |m| m.tick)
    }

    /// The nodes RUNNING at this moment, in tree order.
    pub fn running_nodes(&self) -> Vec<Uid> {
        let Some(at) = self.at() else {
            return Vec::new();
        };
        self.tree
            .preorder()
            .into_iter()
            .filter(|&u| at.status(u) == Status::Running)
            .collect()
    }

    /// Asks a question typed in the user's own words, as `btx ask` does:
    /// the library reads it and answers; the explorer shows the reply.
    /// Whether btx, not sure of its reading, offers others to pick from
    /// (the ask prompt then opens with them).
    pub fn ask_words(&mut self, text: &str) -> bool {
        self.remember_answer();
        self.why = None;
        self.answer = None;
        let node = self.asked_node();
        let at = self.at();
        let cx = crate::ask::Context {
            tree: &self.tree,
            session: self.session.as_ref(),
            at,
            tick: self.moment().map(|m| m.tick),
            node: Some(node),
            detail: self.detail,
            last: std::cell::Cell::new(self.reply.as_ref().and_then(|r| r.about)),
        };
        let r = crate::ask::ask(&cx, text);
        self.asked = Some((node, self.moment().map(|m| m.to_string())));
        self.answered += 1;
        for &u in &r.nodes {
            self.reveal(u);
        }
        // Not sure of its reading: the other readings, to pick from.
        self.did_you_mean = if r.unsure() {
            r.alternatives.clone()
        } else {
            Vec::new()
        };
        self.reply = Some(r);
        if self.did_you_mean.is_empty() {
            return false;
        }
        self.message =
            Some("did you mean one of these? Enter asks it, Esc keeps this answer".into());
        true
    }

    /// The answer on screen as plain text (what `y` copies).
    pub fn answer_text(&self) -> Option<String> {
        if let Some(w) = &self.why {
            return Some(w.why.text());
        }
        if let Some(r) = &self.reply {
            // The question once: the reply restates it first when btx read it.
            let text = r.text();
            return Some(match text.lines().next() == Some(r.understood.as_str()) {
                true => format!("{text}\n"),
                false => format!("{}\n{text}\n", r.understood),
            });
        }
        let a = self.answer.as_ref()?;
        Some(format!("{}\n{}\n", a.question.wording(), a.text))
    }

    /// Keeps the answer on screen in the history before another replaces it.
    pub(crate) fn remember_answer(&mut self) {
        let (Some(text), Some((u, at))) = (self.answer_text(), &self.asked) else {
            return;
        };
        let about = format!(
            "about {} #{u}{}",
            self.tree.description(*u),
            at.as_ref()
                .map_or(String::new(), |m| format!(" at moment {m}"))
        );
        self.history
            .insert(0, format!("{about}\n{}", text.trim_end()));
        self.history.truncate(HISTORY_MAX);
    }

    /// Copies the answer through the terminal (OSC 52), which works over
    /// SSH; the sequence is queued for the next draw.
    pub(crate) fn copy_answer(&mut self) {
        match self.answer_text() {
            Some(t) => {
                self.clipboard = Some(t);
                self.message = Some("copied the answer (OSC 52)".into());
            }
            None => self.message = Some("no answer to copy: ask first (a or w)".into()),
        }
    }

    /// The leaf whose fault came last in tick `t` (a check that answered
    /// no as designed is a branch taken, not a fault).
    pub(crate) fn failed_leaf(&self, t: u32) -> Option<Uid> {
        let s = self.session.as_ref()?;
        let range = s.index.tick_range(t);
        (range.start as u32 + 1..=range.end as u32)
            .rev()
            .find(|&p| {
                let x = s.index.transitions[p as usize - 1];
                s.tree.node(x.uid).kind.is_leaf() && is_fault(&s.tree, &s.index, p)
            })
            .map(|p| s.index.transitions[p as usize - 1].uid)
    }

    /// The ticks with a fault of a leaf in them.
    pub(crate) fn failure_ticks(&self) -> Vec<u32> {
        let Some(s) = &self.session else {
            return Vec::new();
        };
        // Leaves only: a control node's fault is its leaf's, and costs a
        // scan of its call.
        let mut ticks: Vec<u32> = (1..=s.index.transitions.len() as u32)
            .filter(|&p| {
                let t = s.index.transitions[p as usize - 1];
                t.status == Status::Failure
                    && s.tree.node(t.uid).kind.is_leaf()
                    && is_fault(&s.tree, &s.index, p)
            })
            .map(|p| s.index.transitions[p as usize - 1].tick)
            .collect();
        ticks.dedup();
        ticks
    }

    /// The questions that apply to the selected node at this moment.
    pub fn questions(&self) -> Vec<Question> {
        let mut qs: Vec<Question> = TreeQuestion::ALL.into_iter().map(Question::Tree).collect();
        if self.session.is_some() {
            qs.extend(RunQuestion::ALL.into_iter().map(Question::Run));
        }
        // "Can you X?" for the sequences and subtrees of the current subgoal.
        let me = self.asked_node();
        if let Some(sg) = crate::explain::han::subgoal(&self.tree, me) {
            let mut seen = HashSet::new();
            for u in self.tree.descendants(sg) {
                let n = self.tree.node(u);
                let seq = n.kind == Kind::SubTree
                    || matches!(
                        n.builtin,
                        Some(
                            Builtin::Sequence
                                | Builtin::SequenceWithMemory
                                | Builtin::ReactiveSequence
                        )
                    );
                if seq && self.tree.has_name(u) && seen.insert(self.tree.description(u).to_string())
                {
                    qs.push(Question::CanYou(self.tree.description(u).to_string()));
                }
            }
        }
        // Last: any subgoal or step, typed (an empty X opens the prompt).
        qs.push(Question::CanYou(String::new()));
        qs
    }

    /// What "Can you X?" can name: every sequence, subtree and step of the
    /// whole tree, by description, once each, fuzzy-matched to `typed`.
    pub fn can_you_candidates(&self, typed: &str) -> Vec<String> {
        let mut seen = HashSet::new();
        let names: Vec<String> = self
            .tree
            .preorder()
            .into_iter()
            .filter(|&u| {
                let n = self.tree.node(u);
                self.tree.has_name(u) && matches!(n.kind, Kind::SubTree | Kind::Control)
            })
            .map(|u| self.tree.description(u).to_string())
            .filter(|d| seen.insert(d.clone()))
            .collect();
        if typed.is_empty() {
            return names;
        }
        let m = SkimMatcherV2::default().ignore_case();
        let mut scored: Vec<(i64, usize, String)> = names
            .into_iter()
            .enumerate()
            .filter_map(|(i, d)| m.fuzzy_match(&d, typed).map(|s| (s, i, d)))
            .collect();
        scored.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        scored.into_iter().map(|(_, _, d)| d).collect()
    }

    /// The node questions are about: the selected one.
    pub fn asked_node(&self) -> Uid {
        self.selected
    }

    /// The finder's line for a node (made for every node on first use).
    pub fn finder_label(&self, u: Uid) -> &str {
        let all = self.finder_labels.get_or_init(|| finder_labels(&self.tree));
        all.get(u as usize - 1).map_or("", String::as_str)
    }

    /// Finder results: (uid, matched character positions in the label).
    /// A match in the node's own `#uid`, description or ID comes first;
    /// then one within one segment of its path; one whose letters are
    /// spread over several segments last (`/chuck` found "back to approach
    /// pose" by letters of "build a gearbox kit/…").
    pub fn finder_results(&self, query: &str) -> Vec<(Uid, Vec<usize>)> {
        let m = SkimMatcherV2::default().ignore_case();
        let mut scored: Vec<(u8, i64, Uid, Vec<usize>)> = (1..=self.tree.len() as Uid)
            .filter_map(|u| {
                let label = self.finder_label(u);
                if query.is_empty() {
                    return Some((0, 0, u, Vec::new()));
                }
                // The label is `#uid description  [ID]  path`.
                let own = label.find("]  ").map_or(label.len(), |i| i + 1);
                if let Some((s, idx)) = m.fuzzy_indices(&label[..own], query) {
                    return Some((0, s, u, idx));
                }
                let (s, idx) = m.fuzzy_indices(label, query)?;
                let own_chars = label[..own].chars().count();
                let segment = |i: usize| {
                    label
                        .chars()
                        .take(i)
                        .skip(own_chars)
                        .filter(|&c| c == '/')
                        .count()
                };
                let first = idx.first().map_or(0, |&i| segment(i));
                let one = idx.iter().all(|&i| i >= own_chars && segment(i) == first);
                Some((if one { 1 } else { 2 }, s, u, idx))
            })
            .collect();
        scored.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.cmp(&a.1)).then(a.2.cmp(&b.2)));
        scored
            .into_iter()
            .take(200)
            .map(|(_, _, u, i)| (u, i))
            .collect()
    }

    /// Asks the library; the answer and its nodes are shown.
    pub fn ask(&mut self, q: &Question) {
        self.remember_answer();
        self.why = None;
        self.reply = None;
        let at = self.at();
        let node = self.asked_node();
        self.answer = answer(&self.tree, at.as_ref(), node, q).ok();
        self.asked = Some((node, self.moment().map(|m| m.to_string())));
        self.answered += 1;
        if let Some(a) = &self.answer {
            let nodes = a.nodes.clone();
            for u in nodes {
                self.reveal(u);
            }
        }
    }

    pub(crate) fn moment(&self) -> Option<crate::session::Moment> {
        let s = self.session.as_ref()?;
        if let Some(tick) = self.at_tick {
            return Some(crate::session::Moment { tick, step: None });
        }
        (s.index.ticks() > 0).then(|| s.index.moment(self.pos.max(1)))
    }

    /// Asks the library why; the answer, its reasons' nodes and the moment
    /// are shown.
    pub fn ask_why(&mut self, target: String, foils: Vec<String>, at: crate::session::Moment) {
        let Some(s) = &self.session else { return };
        let r = crate::causal::session_domain(s, None)
            .and_then(|d| crate::causal::why(s, d, &target, &foils, Some(at), 2));
        match r {
            Ok(mut w) => {
                w.shown = shown(self.detail);
                self.remember_answer();
                let s = self.session.as_ref().expect("a why-answer is about a run");
                if let Ok(p) = s.index.position(at) {
                    if p != self.pos {
                        let keep = self.selected;
                        self.goto(p);
                        self.selected = keep;
                    }
                }
                for u in w.reason_nodes(0) {
                    self.reveal(u);
                }
                self.asked = Some((self.selected, Some(w.moment.clone())));
                self.answered += 1;
                self.reply = None;
                self.why = Some(WhyView {
                    why: w,
                    selected: 0,
                    graph: false,
                    centre: None,
                    pick: None,
                });
            }
            Err(e) => self.message = Some(e.to_string()),
        }
    }

    /// Why does the picked explanation's first reason hold?
    pub(crate) fn follow_up(&mut self) {
        let Some(w) = &self.why else { return };
        match w.why.follow_up(w.selected) {
            Some((t, foils, at)) => self.ask_why(t, foils, at),
            None => self.message = Some("no reason to follow up".into()),
        }
    }

    /// Nodes shown as used by the answer on screen.
    pub fn highlighted(&self) -> Vec<Uid> {
        match (&self.why, &self.answer, &self.reply) {
            (Some(w), _, _) => w.why.reason_nodes(w.selected),
            (None, Some(a), _) => a.nodes.clone(),
            (None, None, Some(r)) => r.nodes.clone(),
            _ => Vec::new(),
        }
    }

    /// A mouse click on tree row `row` (counted from the pane's first row).
    pub fn click_row(&mut self, row: usize, first: usize) {
        if let Some(r) = self.rows.get(first + row) {
            self.selected = r.uid;
            self.follow_node = false;
        }
    }

    /// Takes a newer reading of the same run: whether it did (a log whose
    /// tree changed is not followed further).
    pub fn grow(&mut self, s: Session) -> bool {
        let at_end = self.pos >= self.positions();
        if s.tree.len() != self.tree.len() {
            self.message = Some(format!(
                "{}: the log's tree changed ({} nodes, was {}); not followed further",
                s.path.display(),
                s.tree.len(),
                self.tree.len()
            ));
            self.follow = None;
            return false;
        }
        if self.live.is_some() {
            self.live_faults = crate::explain::alerts::Tally::of_run(&s.tree, &s.index);
        }
        self.session = Some(s);
        let end = self.positions();
        if at_end {
            self.pos = end;
            self.at_tick = None;
            self.follow_current();
        } else {
            self.pos = self.pos.min(end);
            self.at_tick = None;
        }
        true
    }

    /// One step of autoplay; stops at the end.
    pub fn play_step(&mut self) {
        if self.pos >= self.positions() {
            self.playing = false;
        } else {
            self.goto(self.pos + 1);
        }
    }
}

/// How many explanations a why-answer shows at a level of detail, as
/// `btx why --detail` does.
pub fn shown(d: crate::ask::Detail) -> Option<usize> {
    match d {
        crate::ask::Detail::Brief => Some(1),
        crate::ask::Detail::Normal => Some(3),
        crate::ask::Detail::Full => None,
    }
}

/// The finder's line for each node, by uid − 1: uid, description, ID and
/// path, the path built top-down and cut to its last `FINDER_PATH_MAX`
/// characters, so a 10,000-level tree costs its size, once.
pub fn finder_labels(tree: &Tree) -> Vec<String> {
    tree.display_paths()
        .into_iter()
        .enumerate()
        .map(|(i, path)| {
            let uid = i as Uid + 1;
            let n = path.chars().count();
            let path = if n > FINDER_PATH_MAX {
                let tail: String = path.chars().skip(n - FINDER_PATH_MAX).collect();
                format!("…{tail}")
            } else {
                path
            };
            format!(
                "#{:<4} {}  [{}]  {}",
                uid,
                tree.description(uid),
                tree.node(uid).id,
                path
            )
        })
        .collect()
}

/// The most of a path the finder matches and shows.
pub const FINDER_PATH_MAX: usize = 120;
