//! Explanations: the questions people ask about a tree or a run, and their
//! answers.

pub mod alerts;
pub mod failure;
pub mod fault;
pub mod han;
pub mod insert;

use crate::model::{Tree, Uid};
use crate::session::At;

/// Han et al.'s hierarchical questions, about the node being executed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TreeQuestion {
    /// Q1 "What are you doing?"
    Doing,
    /// Q2 "Why are you doing this?"
    Why,
    /// Q3 "What is your subgoal?"
    Subgoal,
    /// Q4 "What is your goal?"
    Goal,
    /// Q5 "How do you achieve your subgoal?"
    HowSubgoal,
    /// Q5 "How do you achieve your goal?"
    HowGoal,
}

/// Han et al.'s failure questions (Algorithm 7), about a moment of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RunQuestion {
    AnythingWrong,
    WhatWentWrong,
    Handled,
}

/// Any question btx answers.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Question {
    Tree(TreeQuestion),
    Run(RunQuestion),
    /// "Can you X?" (Algorithms 8 and 9).
    CanYou(String),
}

impl TreeQuestion {
    pub const ALL: [TreeQuestion; 6] = [
        TreeQuestion::Doing,
        TreeQuestion::Why,
        TreeQuestion::Subgoal,
        TreeQuestion::Goal,
        TreeQuestion::HowSubgoal,
        TreeQuestion::HowGoal,
    ];

    pub fn wording(self) -> &'static str {
        match self {
            TreeQuestion::Doing => "What are you doing?",
            TreeQuestion::Why => "Why are you doing this?",
            TreeQuestion::Subgoal => "What is your subgoal?",
            TreeQuestion::Goal => "What is your goal?",
            TreeQuestion::HowSubgoal => "How do you achieve your subgoal?",
            TreeQuestion::HowGoal => "How do you achieve your goal?",
        }
    }

    pub fn short(self) -> &'static str {
        match self {
            TreeQuestion::Doing => "q1",
            TreeQuestion::Why => "q2",
            TreeQuestion::Subgoal => "q3",
            TreeQuestion::Goal => "q4",
            TreeQuestion::HowSubgoal => "q5-subgoal",
            TreeQuestion::HowGoal => "q5-goal",
        }
    }
}

impl RunQuestion {
    pub const ALL: [RunQuestion; 3] = [
        RunQuestion::AnythingWrong,
        RunQuestion::WhatWentWrong,
        RunQuestion::Handled,
    ];

    pub fn wording(self) -> &'static str {
        match self {
            RunQuestion::AnythingWrong => "Was there anything wrong?",
            RunQuestion::WhatWentWrong => "What went wrong?",
            RunQuestion::Handled => "How was the failure handled?",
        }
    }

    pub fn short(self) -> &'static str {
        match self {
            RunQuestion::AnythingWrong => "anything-wrong",
            RunQuestion::WhatWentWrong => "wrong",
            RunQuestion::Handled => "handled",
        }
    }
}

impl Question {
    /// Every question with a fixed wording.
    pub fn fixed() -> Vec<Question> {
        TreeQuestion::ALL
            .into_iter()
            .map(Question::Tree)
            .chain(RunQuestion::ALL.into_iter().map(Question::Run))
            .collect()
    }

    pub fn wording(&self) -> String {
        match self {
            Question::Tree(q) => q.wording().to_string(),
            Question::Run(q) => q.wording().to_string(),
            Question::CanYou(x) => format!("Can you {x}?"),
        }
    }

    pub fn short(&self) -> &'static str {
        match self {
            Question::Tree(q) => q.short(),
            Question::Run(q) => q.short(),
            Question::CanYou(_) => "can-you",
        }
    }

    /// Reads a question: its short form, or its wording (any case, with or
    /// without the question mark), or "Can you X?".
    pub fn parse(s: &str) -> Option<Question> {
        let norm = normalize(s);
        if norm == "can you" || norm.starts_with("can you ") {
            // Keep the person's own words for X (ASCII lowering keeps offsets).
            let start = s
                .to_ascii_lowercase()
                .find("can you")
                .map_or(0, |i| i + "can you".len());
            let x = s[start..].trim().trim_end_matches('?').trim();
            return (!x.is_empty()).then(|| Question::CanYou(x.to_string()));
        }
        Question::fixed()
            .into_iter()
            .find(|q| norm == q.short() || norm == normalize(&q.wording()))
    }
}

fn normalize(s: &str) -> String {
    s.trim()
        .trim_end_matches('?')
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase()
}

/// An answer, with the nodes it was built from (for highlighting).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Answer {
    pub question: Question,
    pub text: String,
    pub nodes: Vec<Uid>,
    /// For "Can you X?" answered yes: what to insert where.
    pub insertion: Option<insert::Insertion>,
}

/// Answers a question about node `n` (the current node, usually), at a
/// moment of a run when there is one. Failure questions need a run.
pub fn answer(tree: &Tree, run: Option<&At>, n: Uid, q: &Question) -> Result<Answer, String> {
    let (text, nodes, insertion) = match q {
        Question::Tree(TreeQuestion::Doing) if run.is_some() => {
            let (text, nodes) = han::doing_at(tree, run.expect("matched"));
            (text, nodes, None)
        }
        Question::Tree(t) => {
            let a = han::answer(tree, n, *t);
            (a.text, a.nodes, None)
        }
        Question::Run(r) => {
            let Some(run) = run else {
                return Err(format!(
                    "\"{}\" is about a run: ask it of a session, at a moment",
                    r.wording()
                ));
            };
            let (text, nodes) = match r {
                RunQuestion::AnythingWrong => failure::anything_wrong(tree, run, n),
                RunQuestion::WhatWentWrong => failure::what_went_wrong(tree, run, n),
                RunQuestion::Handled => failure::how_handled(tree, run, n),
            };
            (text, nodes, None)
        }
        Question::CanYou(x) => match insert::can_you(tree, n, x) {
            Ok(ins) => (
                ins.answer.clone(),
                vec![ins.named, ins.copy_of, ins.after],
                Some(ins),
            ),
            Err(refusal) => (refusal, vec![n], None),
        },
    };
    Ok(Answer {
        question: q.clone(),
        text,
        nodes,
        insertion,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn questions_parse_from_wording_and_short_forms() {
        assert_eq!(
            Question::parse("What are you doing?"),
            Some(Question::Tree(TreeQuestion::Doing))
        );
        assert_eq!(
            Question::parse("  why are you doing this "),
            Some(Question::Tree(TreeQuestion::Why))
        );
        assert_eq!(
            Question::parse("q5-goal"),
            Some(Question::Tree(TreeQuestion::HowGoal))
        );
        assert_eq!(
            Question::parse("Q3"),
            Some(Question::Tree(TreeQuestion::Subgoal))
        );
        assert_eq!(
            Question::parse("wrong"),
            Some(Question::Run(RunQuestion::WhatWentWrong))
        );
        assert_eq!(
            Question::parse("How was the failure handled?"),
            Some(Question::Run(RunQuestion::Handled))
        );
        assert_eq!(
            Question::parse("Can you insert large gear?"),
            Some(Question::CanYou("insert large gear".into()))
        );
        assert_eq!(
            Question::parse("can you  Go Pick Screw"),
            Some(Question::CanYou("Go Pick Screw".into()))
        );
        assert_eq!(Question::parse("can you?"), None);
        assert_eq!(Question::parse("what?"), None);
        for q in Question::fixed() {
            assert_eq!(Question::parse(&q.wording()), Some(q.clone()));
            assert_eq!(Question::parse(q.short()), Some(q));
        }
    }
}
