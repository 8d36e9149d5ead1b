//! What a question asks, once read: its intent, the event and the subject
//! it names. The reader (`ask::read`) makes them from a person's words;
//! `compose` answers them.

use crate::explain::Question;

/// What happened to a node that a question asks about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    Fail,
    Succeed,
    /// Started: left IDLE (or a completed status) for another.
    Run,
    NotRun,
    /// Skipped by a pre-condition (`_skipIf`): ticked, and not run.
    Skipped,
    Halted,
    KeepRunning,
    /// Completed, either way.
    Finish,
}

/// Which occurrences a "when" asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    First,
    Last,
    Every,
}

/// The node a question names: the task itself ("you", "the robot"), or a
/// phrase to find among the tree's names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Subject {
    Task,
    Named(String),
    /// The nodes a question's words name, found by the reader (several
    /// when they share the words), with the words.
    Nodes(Vec<crate::model::Uid>, String),
    /// "it", "that": the node of the previous question, else the
    /// selected one, else the task.
    It,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Intent {
    /// Han's questions, the failure questions and "Can you X?".
    Fixed(Question),
    Why {
        node: Subject,
        event: Event,
        /// "instead of succeeding": the outcome the person expected.
        foil: Option<Event>,
    },
    /// "Why did you do X instead of Y?": why Y did not run.
    WhyNot {
        done: Subject,
        instead: Subject,
    },
    When {
        node: Subject,
        event: Event,
        which: Which,
    },
    HowOften {
        node: Subject,
        event: Event,
    },
    Tick(u32),
    Next,
    WhatIf {
        node: Subject,
        event: Event,
    },
    Recovered,
}

impl Intent {
    /// The query's short name, as `btx ask` prints it in JSON.
    pub fn short(&self) -> &'static str {
        match self {
            Intent::Fixed(q) => q.short(),
            Intent::Why { .. } | Intent::WhyNot { .. } => "why",
            Intent::When { .. } => "when",
            Intent::HowOften { .. } => "how-often",
            Intent::Tick(_) => "tick",
            Intent::Next | Intent::WhatIf { .. } => "next",
            Intent::Recovered => "recovered",
        }
    }
}
