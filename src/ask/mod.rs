//! Questions in the user's own words: text → query (`parse`, `nodes`) →
//! composed answer (`compose`, `fixed`, `why`), calling `explain` and
//! `causal`. The CLI and the explorer both ask here, and never each other.

pub mod complete;
pub mod compose;
pub mod detail;
pub mod fixed;
pub mod nodes;
pub mod parse;
pub mod why;

pub use compose::Context;
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
            answered: true,
        }
    }

    /// The answer as printed: the restatement first when btx read the
    /// question, then the answer, then what came before.
    pub fn text(&self) -> String {
        let body = self.body();
        if self.restate && !self.understood.is_empty() {
            format!("{}\n{body}", self.understood)
        } else {
            body
        }
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
            "nodes": self.nodes.iter().map(|&u| node(u)).collect::<Vec<_>>(),
            "insert": self.insertion.as_ref().map(|i| json!({"copy_of": node(i.copy_of), "after": node(i.after)})),
        })
    }
}

/// Answers a question typed in the user's words.
pub fn ask(cx: &Context, question: &str) -> Reply {
    match parse::parse(question) {
        Some(intent) => {
            let mut r = compose::compose(cx, question, &intent);
            r.restate = Question::parse(question).is_none();
            // A why is put at its level of detail by the search's own
            // rendering (`detail::why_text`); the others here.
            if r.target.is_none() && r.answered {
                at_detail(cx, &mut r);
            }
            r
        }
        None => {
            let mut r = Reply::new(question, None);
            r.answered = false;
            r.answer = "I don't know how to answer that.".into();
            r.suggestions = suggestions(cx, question);
            r
        }
    }
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
        }
    }
}

/// Up to three questions btx can answer here that come closest to what
/// was typed, with this run's names in them.
fn suggestions(cx: &Context, question: &str) -> Vec<String> {
    let tree = cx.tree;
    let node = cx
        .node
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
    let keyed: Vec<(String, String)> = items.iter().map(|s| (s.clone(), s.clone())).collect();
    crate::rank::rank(question, &keyed, 3)
}
