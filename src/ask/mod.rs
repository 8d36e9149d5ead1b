//! Questions in the user's own words: text → query (`parse`, `nodes`) →
//! composed answer (`compose`, `fixed`, `why`), calling `explain` and
//! `causal`. The CLI and the explorer both ask here, and never each other.

pub mod complete;
pub mod compose;
pub mod context;
pub mod detail;
pub mod fixed;
pub mod nodes;
pub mod parse;
pub mod read;
mod say;
pub mod why;

pub use context::Context;
pub use detail::Detail;

use crate::explain::insert::Insertion;
use crate::explain::Question;
use crate::model::{Tree, Uid};
use serde_json::{json, Value};

/// One question's answer, with what btx understood it to ask.
#[derive(Debug, Clone)]
pub struct Reply {
    /// As typed.
    pub question: String,
    /// The query's short name; `None` when not understood.
    pub short: Option<&'static str>,
    /// The question restated in btx's words.
    pub understood: String,
    /// Whether btx read the question (rather than the person typing one
    /// of its own wordings), so that the restatement is printed first.
    pub restate: bool,
    pub about: Option<Uid>,
    /// For a why: `btx why`'s target and foils.
    pub target: Option<String>,
    pub not: Vec<String>,
    /// The moment the answer is about.
    pub moment: Option<String>,
    pub answer: String,
    /// What happened to the node before (a failure that came again).
    pub history: Option<String>,
    pub suggestions: Vec<String>,
    /// For a why: the event asked about, to check the search answered it.
    pub short_event: Option<parse::Event>,
    /// For a why: whether the foil came from the words' tense ("why did X
    /// fail?" → rather than succeed), not from the question.
    pub foil_implied: bool,
    pub nodes: Vec<Uid>,
    pub insertion: Option<Insertion>,
    /// How sure btx is of its reading (1 for a question in its own words).
    pub confidence: f32,
    /// Other readings, said back, when btx was not sure of this one.
    pub alternatives: Vec<String>,
    /// The moment the question itself named ("at tick 9"), as it says it.
    pub named_moment: Option<String>,
    /// False when btx could not answer (not understood, no such node, a
    /// run question about a tree): the CLI then exits with 1.
    pub answered: bool,
}

impl Reply {
    fn new(question: &str, short: Option<&'static str>) -> Reply {
        Reply {
            question: question.to_string(),
            short,
            understood: String::new(),
            restate: true,
            about: None,
            target: None,
            not: Vec::new(),
            moment: None,
            answer: String::new(),
            history: None,
            suggestions: Vec::new(),
            short_event: None,
            foil_implied: false,
            nodes: Vec::new(),
            insertion: None,
            confidence: 1.0,
            alternatives: Vec::new(),
            named_moment: None,
            answered: true,
        }
    }

    /// The answer as printed: the restatement first when btx read the
    /// question, then the answer, then what came before.
    pub fn text(&self) -> String {
        let body = self.body();
        if self.unsure() {
            return format!("{}\n{body}", self.read_as());
        }
        if self.restate && !self.understood.is_empty() {
            format!("{}\n{body}", self.understood)
        } else {
            body
        }
    }

    /// Whether btx says what it read and offers other readings.
    pub fn unsure(&self) -> bool {
        self.confidence < read::SURE && !self.understood.is_empty()
    }

    /// "I read this as "…". Did you mean: "…" or "…"?"
    pub fn read_as(&self) -> String {
        let mut s = format!("I read this as \"{}\".", self.understood);
        if !self.alternatives.is_empty() {
            let quoted: Vec<String> = self
                .alternatives
                .iter()
                .map(|a| format!("\"{a}\""))
                .collect();
            s.push_str(&format!(" Did you mean: {}?", or_list(&quoted)));
        }
        s
    }

    /// The answer without its restatement: the answer, what came before,
    /// and suggestions.
    pub fn body(&self) -> String {
        let mut out = vec![self.answer.clone()];
        if let Some(h) = &self.history {
            out.push(h.clone());
        }
        if !self.suggestions.is_empty() {
            out.push("Questions I can answer that come closest:".into());
            out.extend(self.suggestions.iter().map(|s| format!("  {s}")));
        }
        out.join("\n")
    }

    pub fn json(&self, tree: &Tree) -> Value {
        let node = |u: Uid| json!({"uid": u, "description": tree.description(u)});
        json!({
            "question": self.question,
            "short": self.short,
            "understood": (!self.understood.is_empty()).then_some(&self.understood),
            "about": self.about.map(node),
            "target": self.target,
            "not": self.not,
            "moment": self.moment,
            "answer": self.answer,
            "history": self.history,
            "suggestions": self.suggestions,
            "answered": self.answered,
            "confidence": (f64::from(self.confidence) * 100.0).round() / 100.0,
            "alternatives": self.alternatives,
            "named_moment": self.named_moment,
            "nodes": self.nodes.iter().map(|&u| node(u)).collect::<Vec<_>>(),
            "insert": self.insertion.as_ref().map(|i| json!({"copy_of": node(i.copy_of), "after": node(i.after)})),
        })
    }
}

fn or_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// Answers a question typed in the user's words: read (nodes, then what
/// is asked, then when), then answered at the moment it names, if any.
pub fn ask(cx: &Context, question: &str) -> Reply {
    let (reading, restate) = reading_of(cx, question);
    // "How often did CPTP run?" of a tree with no such node: said, not
    // answered of the whole task; "why did RA S?" where RA could be
    // retreat arm or reset arm: which, rather than not understood.
    let naming_nothing = match &reading {
        Some(r) if read::asks_of_the_task_unnamed(&r.intent) => {
            read::initials_naming_nothing(cx.tree, question).map(|u| u.told)
        }
        None => read::initials_naming_nothing(cx.tree, question)
            .filter(|u| u.several)
            .map(|u| u.told),
        Some(_) => None,
    };
    let (Some(reading), None) = (reading, &naming_nothing) else {
        let mut r = Reply::new(question, None);
        r.answered = false;
        r.answer = naming_nothing.unwrap_or_else(|| "I don't know how to answer that.".into());
        r.suggestions = suggestions(cx, question);
        r.confidence = 0.0;
        return r;
    };
    let failure = failure_said(cx, &reading);
    let moved = match (reading.when, cx.at.as_ref()) {
        (Some(_), Some(at)) if failure.is_some() => failure.filter(|&p| p > at.pos).map(|_| {
            let end = at.index.transitions.len() as u32;
            moved_to(cx, Some(at.index.at(end)), cx.node)
        }),
        (Some(w), Some(at)) => match moment_of(cx.tree, at, w) {
            Ok(pos) => {
                let pos = past_the_clause(at, &reading, pos);
                Some(moved_to(cx, Some(at.index.at(pos)), cx.node))
            }
            Err(e) => return not_in_the_run(cx, question, &reading, e),
        },
        _ => None,
    };
    let cx = moved.as_ref().unwrap_or(cx);
    // Han's questions asked of a node named: the one of them running at
    // the moment, if one is.
    let named = reading.about.as_ref().map(|us| {
        // The deepest of them running (a node's uid is past its parent's):
        // the action a RecoveryNode of the same name runs.
        let running = cx.at.as_ref().and_then(|at| {
            us.iter()
                .copied()
                .filter(|&u| at.status(u) == crate::run::Status::Running)
                .max()
        });
        moved_to(cx, cx.at, running.or(us.first().copied()))
    });
    let cx = named.as_ref().unwrap_or(cx);
    let mut r = compose::compose(cx, question, &reading.intent, failure);
    said_as_read(cx, &reading, restate, &mut r);
    r
}

/// "After look at chuck failed, did it still manage to insert the large
/// gear?": the failure a question of recovery names is the one asked
/// about, seen from the moment asked (seen from just after it, nothing
/// had recovered yet). Its position in the run, where it is one. "Did it
/// recover after it failed at tick 10?": the tick's failure, of the node
/// named where it failed then, else the tick's first.
fn failure_said(cx: &Context, reading: &read::Reading) -> Option<u32> {
    let handled = parse::Intent::Fixed(Question::Run(crate::explain::RunQuestion::Handled));
    let (Some(w), Some(at)) = (reading.when, &cx.at) else {
        return None;
    };
    if reading.intent != parse::Intent::Recovered && reading.intent != handled {
        return None;
    }
    let failed =
        |p: u32| at.index.transitions[p as usize - 1].status == crate::run::Status::Failure;
    let p = moment_of(cx.tree, at, w).ok().filter(|&p| p > 0)?;
    // "How was FollowPath's second failure handled?", "did it recover
    // after it?" asked before it happened: of the run as far as it was
    // recorded (`ask` moves there).
    if p > at.pos {
        return failed(p).then_some(p);
    }
    if failed(p) {
        return Some(p);
    }
    let tick = at.index.moment(p).tick;
    let in_tick: Vec<u32> = at
        .index
        .tick_range(tick)
        .map(|i| i as u32 + 1)
        .filter(|&q| q <= at.pos && failed(q))
        .collect();
    let named = reading.about.as_deref().unwrap_or_default();
    in_tick
        .iter()
        .rev()
        .find(|&&q| named.contains(&at.index.transitions[q as usize - 1].uid))
        .or(in_tick.first())
        .copied()
}

/// The question as read: one of the paper's fixed wordings (not restated)
/// or the user's own words (restated). "Can you justify the move you're
/// making?", "can you explain …": a question put politely is read as what
/// it asks, not as "Can you X?".
fn reading_of(cx: &Context, question: &str) -> (Option<read::Reading>, bool) {
    let polite = |x: &str| {
        let words: Vec<String> = x.split_whitespace().map(str::to_lowercase).collect();
        let words: Vec<&str> = words.iter().map(String::as_str).collect();
        let first = words.first().copied().unwrap_or("");
        [
            "justify", "explain", "tell", "show", "describe", "say", "give", "list",
        ]
        .contains(&first)
            || words.starts_with(&["break", "down"])
            || read::wraps_a_question(&words)
            || words.iter().any(|w| read::ADVICE.contains(w))
    };
    let vocabulary = read::Vocabulary::new(cx.tree);
    let meant = read::as_meant(&vocabulary, cx.tree, question);
    let parsed = Question::parse(&meant).filter(|q| !matches!(q, Question::CanYou(x) if polite(x)));
    let parsed = parsed.map(|q| found_by_the_reader(cx, &vocabulary, question, q));
    match parsed {
        Some(q) => (
            Some(read::Reading {
                intent: parse::Intent::Fixed(q),
                confidence: 1.0,
                alternatives: Vec::new(),
                when: None,
                about: None,
            }),
            false,
        ),
        None => (read::read(&vocabulary, cx.tree, question), true),
    }
}

/// "Can you check if the screw is grasped?": the behaviour as the reader
/// finds it among the tree's names (check if grasped), where every word
/// of its name is said, not the words as said.
fn found_by_the_reader(
    cx: &Context,
    vocabulary: &read::Vocabulary,
    question: &str,
    q: Question,
) -> Question {
    let Question::CanYou(said) = &q else {
        return q;
    };
    match read::read(vocabulary, cx.tree, question) {
        Some(read::Reading {
            intent: parse::Intent::Fixed(Question::CanYou(found)),
            confidence,
            ..
        }) if confidence >= read::SURE
            && read::said_by(&found, said)
            && cx
                .tree
                .nodes
                .iter()
                .any(|n| n.name == found || n.id == found) =>
        {
            Question::CanYou(found)
        }
        _ => q,
    }
}

/// "After look at chuck failed, why did it reset the arm?": a moment said
/// as "after" something starts the search for the deed asked about; it
/// does not end it. Where the deed came after that moment, the question
/// is asked at the end of the tick of its first time after it (asked at
/// the moment itself, the answer was that reset arm "had not run by
/// moment 10:1"). "When X failed for the second time" is that moment
/// itself, not a start; "after the first X failure" is a start.
fn past_the_clause(at: &crate::session::At, reading: &read::Reading, pos: u32) -> u32 {
    use parse::{Event, Intent, Subject};
    let after = matches!(
        reading.when,
        Some(
            read::When::AfterFailure
                | read::When::AfterFailureOf(_)
                | read::When::AfterStartOf(_)
                | read::When::AfterRecovery
                | read::When::Ended {
                    side: read::Side::After,
                    ..
                }
        )
    );
    if !after {
        return pos;
    }
    let (uids, event) = match &reading.intent {
        Intent::Why {
            node: Subject::Nodes(us, _),
            event,
            ..
        } => (us, *event),
        Intent::WhyNot {
            done: Subject::Nodes(us, _),
            ..
        } => (us, Event::Run),
        _ => return pos,
    };
    let end = at.index.at(at.index.transitions.len() as u32);
    let first_after = uids
        .iter()
        .filter_map(|&u| {
            context::events(&end, u, event)
                .into_iter()
                .find(|&p| p > pos)
        })
        .min();
    let Some(p) = first_after else {
        return pos;
    };
    let tick = at.index.transitions[p as usize - 1].tick;
    at.index
        .position(crate::session::Moment { tick, step: None })
        .unwrap_or(p)
}

/// The context asked of, at another moment or about another node.
fn moved_to<'a>(
    cx: &Context<'a>,
    at: Option<crate::session::At<'a>>,
    node: Option<Uid>,
) -> Context<'a> {
    Context {
        tree: cx.tree,
        session: cx.session,
        at,
        tick: None,
        node,
        detail: cx.detail,
        last: std::cell::Cell::new(cx.last.get()),
    }
}

/// A moment the question names that the run does not hold ("the fifth
/// time" of a node that failed twice): said, not answered at another. A
/// reading not sure of itself says so all the same.
fn not_in_the_run(cx: &Context, question: &str, reading: &read::Reading, e: String) -> Reply {
    let mut r = Reply::new(question, Some(reading.intent.short()));
    r.answered = false;
    r.answer = e;
    if reading.confidence < read::SURE {
        r.understood = read::wording(cx.tree, &reading.intent);
        r.confidence = reading.confidence;
        r.alternatives = reading
            .alternatives
            .iter()
            .map(|i| read::wording(cx.tree, i))
            .collect();
    }
    r
}

/// The reply told as read: how sure, the moment named (Han's questions
/// are asked of a moment, said back with it: "What are you doing at tick
/// 9?"), the other readings, the level of detail, and the node "it" means
/// next.
fn said_as_read(cx: &Context, reading: &read::Reading, restate: bool, r: &mut Reply) {
    r.restate = restate;
    r.confidence = reading.confidence;
    r.named_moment = reading.when.map(|w| w.told(cx.tree));
    // "Did it recover in the end?", asked mid-run: of the run's end.
    if reading.intent == parse::Intent::Recovered && reading.when == Some(read::When::LastTick) {
        r.understood = "Did the recovery work by the end of the run?".into();
    }
    if let (Some(w), parse::Intent::Fixed(Question::Tree(_) | Question::Run(_))) =
        (reading.when, &reading.intent)
    {
        if let Some(q) = r.understood.strip_suffix('?') {
            let past =
                q.replacen(" are you ", " were you ", 1)
                    .replacen(" is your ", " was your ", 1);
            r.understood = format!("{past} {}?", w.told(cx.tree));
        }
    }
    r.alternatives = reading
        .alternatives
        .iter()
        .map(|i| read::wording(cx.tree, i))
        .collect();
    // A why is put at its level of detail by the search's own
    // rendering (`detail::why_text`); the others here.
    if r.target.is_none() && r.answered {
        at_detail(cx, r);
    }
    if r.answered {
        if let Some(u) = r.about {
            cx.last.set(Some(u));
        }
    }
}

/// The position a moment said in words stands for in the run.
pub fn moment_of(tree: &Tree, at: &crate::session::At, w: read::When) -> Result<u32, String> {
    use crate::run::Status;
    use crate::session::Moment;
    use read::When;
    let index = at.index;
    let ticks = index.ticks();
    let first_failure = || {
        index
            .transitions
            .iter()
            .position(|t| t.status == Status::Failure)
            .map(|i| i as u32)
            .ok_or_else(|| {
                "Nothing failed in this run, so there is no moment of a failure.".to_string()
            })
    };
    match w {
        When::Tick(n) | When::Step(n, _) if n > ticks => Err(format!(
            "The run has {ticks} tick{}; there is no tick {n}.",
            if ticks == 1 { "" } else { "s" }
        )),
        When::Tick(n) => index.position(Moment {
            tick: n,
            step: None,
        }),
        When::Step(n, s) => index.position(Moment {
            tick: n,
            step: Some(s),
        }),
        When::FirstTick => index.position(Moment {
            tick: 1,
            step: None,
        }),
        When::LastTick => index.position(Moment {
            tick: ticks.max(1),
            step: None,
        }),
        When::BeforeFailureOf(u) | When::AfterFailureOf(u) => {
            // The position right after the failure.
            let p = failure_of(tree, at, u)?;
            Ok(if matches!(w, When::BeforeFailureOf(_)) {
                p - 1
            } else {
                p
            })
        }
        When::BeforeStartOf(u) => start_of(tree, at, u).map(|p| p - 1),
        When::AfterStartOf(u) => start_of(tree, at, u),
        When::Ended {
            uid,
            n,
            failed,
            side,
        } => {
            let p = nth_end(tree, at, uid, n, failed)?;
            Ok(if side == read::Side::Before { p - 1 } else { p })
        }
        When::NthFailure(n) => nth_failure(tree, at, n),
        When::BeforeFailure => first_failure(),
        When::AfterFailure => first_failure().map(|i| i + 1),
        When::AfterRecovery => {
            let i = first_failure()?;
            let leaf = index.transitions[i as usize].uid;
            let end = index.at(index.transitions.len() as u32);
            crate::explain::failure::recovery(tree, &end, leaf, i + 1)
                .map(|(_, pos)| pos)
                .ok_or_else(|| {
                    "Nothing recovered from the first failure, so there is no moment after a recovery."
                        .to_string()
                })
        }
    }
}

/// The position right after the run's N-th failure of an action or
/// condition.
fn nth_failure(tree: &Tree, at: &crate::session::At, n: u32) -> Result<u32, String> {
    at.index
        .transitions
        .iter()
        .enumerate()
        .filter(|(_, t)| t.status == crate::run::Status::Failure && tree.node(t.uid).kind.is_leaf())
        .nth(n as usize - 1)
        .map(|(i, _)| i as u32 + 1)
        .ok_or_else(|| match n {
            1 => "No action failed in this run: there is no first time.".to_string(),
            n => format!(
                "No action failed a {} time in this run.",
                read::ordinal_word(n)
            ),
        })
}

/// The position right after `u`'s last failure by the moment, else its
/// first.
fn failure_of(tree: &Tree, at: &crate::session::At, u: Uid) -> Result<u32, String> {
    let index = at.index;
    let failures: Vec<u32> = index
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&p| index.transitions[p as usize - 1].status == crate::run::Status::Failure)
        .collect();
    nearest(&failures, at.pos).ok_or_else(|| format!("{} never failed in this run.", tree.told(u)))
}

/// Of positions in order, the last at or before `pos`, else the first.
fn nearest(positions: &[u32], pos: u32) -> Option<u32> {
    positions
        .iter()
        .rev()
        .find(|&&p| p <= pos)
        .or(positions.first())
        .copied()
}

/// The position right after `u` started (left IDLE): its last start by
/// the moment asked, else its first. Of the same behaviour in several
/// places ("ask" in three subtrees, `read::alike`), the run says which:
/// the start of any of them.
fn start_of(tree: &Tree, at: &crate::session::At, u: Uid) -> Result<u32, String> {
    use crate::run::Status;
    let index = at.index;
    let mut starts: Vec<u32> = read::alike(tree, u)
        .into_iter()
        .flat_map(|v| index.changes_of(v).iter().copied())
        .filter(|&p| {
            let t = index.transitions[p as usize - 1];
            t.prev == Status::Idle && t.status != Status::Idle
        })
        .collect();
    starts.sort_unstable();
    nearest(&starts, at.pos).ok_or_else(|| format!("{} never started in this run.", tree.told(u)))
}

/// The position right after `uid`'s `n`-th end (its `n`-th failure, if
/// `failed`).
fn nth_end(
    tree: &Tree,
    at: &crate::session::At,
    uid: Uid,
    n: u32,
    failed: bool,
) -> Result<u32, String> {
    use crate::run::Status;
    let index = at.index;
    let ends: Vec<u32> = index
        .changes_of(uid)
        .iter()
        .copied()
        .filter(|&p| match index.transitions[p as usize - 1].status {
            Status::Failure => true,
            Status::Success => !failed,
            _ => false,
        })
        .collect();
    ends.get(n as usize - 1).copied().ok_or_else(|| {
        let verb = if failed { "failed" } else { "ended" };
        let node = say::upper(&tree.told(uid));
        let nth = read::ordinal_word(n);
        match ends.len() {
            0 => format!("{node} never {verb} in this run: there is no {nth} time."),
            k => format!(
                "{node} {verb} {} in this run: there is no {nth} time.",
                crate::causal::calls::times(k)
            ),
        }
    })
}

fn at_detail(cx: &Context, r: &mut Reply) {
    match cx.detail {
        // Q5's steps are its answer, not detail.
        Detail::Brief if !matches!(r.short, Some("q5-subgoal" | "q5-goal")) => {
            r.answer = detail::first_sentence(&r.answer);
            r.history = None;
        }
        Detail::Brief => {}
        Detail::Normal => {}
        Detail::Full => {
            if let (Some(at), false) = (&cx.at, r.nodes.is_empty()) {
                let facts = detail::facts(cx.tree, at, &r.nodes);
                r.answer.push_str("\nWhat the run shows of these nodes:");
                for f in facts {
                    r.answer.push_str(&format!("\n  {f}"));
                }
            }
            if let Some(s) = cx.session {
                if let Some(times) = detail::times_of(&r.answer, s) {
                    r.answer.push('\n');
                    r.answer.push_str(&times);
                }
            }
        }
    }
}

/// Up to three questions btx can answer here that come closest to what
/// was typed, with this run's names in them.
fn suggestions(cx: &Context, question: &str) -> Vec<String> {
    let tree = cx.tree;
    // About the node the question named, if it named one ("chuk"), else
    // the selected or current one.
    let words = read::words::words(question);
    let named = read::Vocabulary::new(tree)
        .mentions(tree, &words, &|_| false)
        .into_iter()
        .find(|m| !m.uids.is_empty())
        .map(|m| m.uids[0]);
    let node = named
        .or(cx.node)
        .or_else(|| cx.at.as_ref().and_then(|a| a.current()))
        .unwrap_or(tree.root().uid);
    let x = tree.spoken(node);
    let mut items: Vec<String> = Question::fixed().iter().map(|q| q.wording()).collect();
    items.extend([
        format!("Why did {x} fail?"),
        format!("Why did {x} succeed?"),
        format!("Why did {x} not run?"),
        format!("When did {x} fail?"),
        format!("How often did {x} fail?"),
        format!("What if {x} fails?"),
        "Why did the task fail?".to_string(),
        "What will you do next?".to_string(),
        "Did the recovery work?".to_string(),
        format!("Can you {x}?"),
    ]);
    if let Some(a) = &cx.at {
        items.push(format!("What happened at tick {}?", a.moment().tick));
    }
    // A node named: the questions about it, best first.
    if named.is_some() {
        items.retain(|q| q.contains(&x));
    }
    let keyed: Vec<(String, String)> = items.iter().map(|s| (s.clone(), s.clone())).collect();
    let mut out = crate::rank::rank(question, &keyed, 3);
    if out.is_empty() {
        out = items.into_iter().take(3).collect();
    }
    out
}
