//! Explanations: the questions people ask, and their answers.

pub mod han;

use crate::model::Uid;

/// A question about the node the robot is executing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Question {
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

impl Question {
    pub const ALL: [Question; 6] = [
        Question::Doing,
        Question::Why,
        Question::Subgoal,
        Question::Goal,
        Question::HowSubgoal,
        Question::HowGoal,
    ];

    /// The paper's wording.
    pub fn wording(self) -> &'static str {
        match self {
            Question::Doing => "What are you doing?",
            Question::Why => "Why are you doing this?",
            Question::Subgoal => "What is your subgoal?",
            Question::Goal => "What is your goal?",
            Question::HowSubgoal => "How do you achieve your subgoal?",
            Question::HowGoal => "How do you achieve your goal?",
        }
    }

    /// The short form accepted on the command line.
    pub fn short(self) -> &'static str {
        match self {
            Question::Doing => "q1",
            Question::Why => "q2",
            Question::Subgoal => "q3",
            Question::Goal => "q4",
            Question::HowSubgoal => "q5-subgoal",
            Question::HowGoal => "q5-goal",
        }
    }

    /// Reads a question: its short form, or its wording (any case, with or
    /// without the question mark).
    pub fn parse(s: &str) -> Option<Question> {
        let norm = normalize(s);
        Question::ALL
            .into_iter()
            .find(|q| norm == q.short() || norm == normalize(q.wording()))
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
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Answer {
    pub question: Question,
    pub text: String,
    pub nodes: Vec<Uid>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn questions_parse_from_wording_and_short_forms() {
        assert_eq!(
            Question::parse("What are you doing?"),
            Some(Question::Doing)
        );
        assert_eq!(
            Question::parse("  why are you doing this "),
            Some(Question::Why)
        );
        assert_eq!(Question::parse("q5-goal"), Some(Question::HowGoal));
        assert_eq!(Question::parse("Q3"), Some(Question::Subgoal));
        assert_eq!(Question::parse("what?"), None);
        for q in Question::ALL {
            assert_eq!(Question::parse(q.wording()), Some(q));
            assert_eq!(Question::parse(q.short()), Some(q));
        }
    }
}
