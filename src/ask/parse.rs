//! Text → query: a small grammar of what people ask about a run, in
//! several phrasings each. Deterministic: a sentence it does not know is
//! not understood, never guessed.

use crate::explain::{Question, RunQuestion, TreeQuestion};

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

/// Reads a question. `None`: not understood.
pub fn parse(text: &str) -> Option<Intent> {
    if let Some(q) = Question::parse(text) {
        return Some(Intent::Fixed(q));
    }
    let s = normalize(text);
    fixed(&s)
        .map(Intent::Fixed)
        .or_else(|| can_you(&s))
        .or_else(|| tick(&s))
        .or_else(|| recovered(&s))
        .or_else(|| next(&s))
        .or_else(|| what_if(&s))
        .or_else(|| why_instead(&s))
        .or_else(|| why(&s))
        .or_else(|| when(&s))
        .or_else(|| how_often(&s))
}

/// Lower case, contractions spelled out, fillers and the question mark
/// dropped, one space between words.
pub fn normalize(text: &str) -> String {
    let mut s = text
        .trim()
        .to_lowercase()
        .replace(['’', '‘'], "'")
        .replace(['?', '!', '"', '“', '”', ','], " ");
    for (from, to) in [
        ("can't", "cannot"),
        ("won't", "will not"),
        ("n't", " not"),
        ("what's", "what is"),
        ("where's", "where is"),
        ("how's", "how is"),
        ("it's", "it is"),
        ("'s ", " "),
    ] {
        s = s.replace(from, to);
    }
    let words: Vec<&str> = s.split_whitespace().collect();
    let mut w: &[&str] = &words;
    while let Some((first, rest)) = w.split_first() {
        if ["please", "btx", "hey", "so", "ok", "okay", "robot"].contains(first) {
            w = rest;
        } else {
            break;
        }
    }
    while let Some((last, rest)) = w.split_last() {
        if ["please", "then"].contains(last) {
            w = rest;
        } else {
            break;
        }
    }
    w.join(" ").trim_end_matches('.').trim().to_string()
}

/// Han's questions and the failure questions in other words.
fn fixed(s: &str) -> Option<Question> {
    // The robot, the tree and "it" are "you"; "current" adds nothing.
    let mut t = format!(" {s} ");
    for (from, to) in [
        (" is the robot ", " are you "),
        (" is the tree ", " are you "),
        (" is it ", " are you "),
        (" the robot's ", " your "),
        (" the robot ", " you "),
        (" current ", " "),
        (" right now ", " now "),
    ] {
        t = t.replace(from, to);
    }
    let t = t.trim();
    FIXED
        .iter()
        .find(|(w, _)| *w == s || *w == t)
        .map(|(_, q)| q.clone())
}

const FIXED: &[(&str, Question)] = &[
    ("what are you doing", Question::Tree(TreeQuestion::Doing)),
    (
        "what are you doing now",
        Question::Tree(TreeQuestion::Doing),
    ),
    (
        "what are you doing right now",
        Question::Tree(TreeQuestion::Doing),
    ),
    (
        "what is the robot doing",
        Question::Tree(TreeQuestion::Doing),
    ),
    ("what is it doing", Question::Tree(TreeQuestion::Doing)),
    ("what is happening", Question::Tree(TreeQuestion::Doing)),
    ("what is running", Question::Tree(TreeQuestion::Doing)),
    ("what is running now", Question::Tree(TreeQuestion::Doing)),
    (
        "what is the tree doing",
        Question::Tree(TreeQuestion::Doing),
    ),
    ("what are you up to", Question::Tree(TreeQuestion::Doing)),
    ("doing", Question::Tree(TreeQuestion::Doing)),
    ("why are you doing this", Question::Tree(TreeQuestion::Why)),
    ("why are you doing that", Question::Tree(TreeQuestion::Why)),
    ("why are you doing it", Question::Tree(TreeQuestion::Why)),
    ("why do you do this", Question::Tree(TreeQuestion::Why)),
    ("why this", Question::Tree(TreeQuestion::Why)),
    ("what for", Question::Tree(TreeQuestion::Why)),
    (
        "what is your subgoal",
        Question::Tree(TreeQuestion::Subgoal),
    ),
    ("what is the subgoal", Question::Tree(TreeQuestion::Subgoal)),
    (
        "what is your current subgoal",
        Question::Tree(TreeQuestion::Subgoal),
    ),
    (
        "which subgoal are you on",
        Question::Tree(TreeQuestion::Subgoal),
    ),
    ("subgoal", Question::Tree(TreeQuestion::Subgoal)),
    ("what is your goal", Question::Tree(TreeQuestion::Goal)),
    ("what is the goal", Question::Tree(TreeQuestion::Goal)),
    ("what is the task", Question::Tree(TreeQuestion::Goal)),
    ("what is your task", Question::Tree(TreeQuestion::Goal)),
    ("what is the mission", Question::Tree(TreeQuestion::Goal)),
    (
        "what are you trying to do",
        Question::Tree(TreeQuestion::Goal),
    ),
    ("goal", Question::Tree(TreeQuestion::Goal)),
    ("q5", Question::Tree(TreeQuestion::HowSubgoal)),
    (
        "how do you achieve your subgoal",
        Question::Tree(TreeQuestion::HowSubgoal),
    ),
    (
        "how do you achieve the subgoal",
        Question::Tree(TreeQuestion::HowSubgoal),
    ),
    (
        "how do you achieve this subgoal",
        Question::Tree(TreeQuestion::HowSubgoal),
    ),
    (
        "what are the steps of your subgoal",
        Question::Tree(TreeQuestion::HowSubgoal),
    ),
    (
        "what are the steps",
        Question::Tree(TreeQuestion::HowSubgoal),
    ),
    (
        "how do you do that",
        Question::Tree(TreeQuestion::HowSubgoal),
    ),
    (
        "how do you achieve your goal",
        Question::Tree(TreeQuestion::HowGoal),
    ),
    (
        "how do you achieve the goal",
        Question::Tree(TreeQuestion::HowGoal),
    ),
    (
        "what are the steps of your goal",
        Question::Tree(TreeQuestion::HowGoal),
    ),
    (
        "how do you do the task",
        Question::Tree(TreeQuestion::HowGoal),
    ),
    ("what went wrong", Question::Run(RunQuestion::WhatWentWrong)),
    ("what is wrong", Question::Run(RunQuestion::WhatWentWrong)),
    ("what failed", Question::Run(RunQuestion::WhatWentWrong)),
    ("what broke", Question::Run(RunQuestion::WhatWentWrong)),
    (
        "what is the problem",
        Question::Run(RunQuestion::WhatWentWrong),
    ),
    (
        "what was the problem",
        Question::Run(RunQuestion::WhatWentWrong),
    ),
    (
        "was there anything wrong",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "was anything wrong",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "is anything wrong",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "is something wrong",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "did anything go wrong",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "did something go wrong",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "did anything fail",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    ("any problems", Question::Run(RunQuestion::AnythingWrong)),
    ("any errors", Question::Run(RunQuestion::AnythingWrong)),
    (
        "is everything ok",
        Question::Run(RunQuestion::AnythingWrong),
    ),
    (
        "how was the failure handled",
        Question::Run(RunQuestion::Handled),
    ),
    ("how was it handled", Question::Run(RunQuestion::Handled)),
    (
        "how did you handle the failure",
        Question::Run(RunQuestion::Handled),
    ),
    ("how did you handle it", Question::Run(RunQuestion::Handled)),
    ("how did you recover", Question::Run(RunQuestion::Handled)),
    (
        "how did you deal with it",
        Question::Run(RunQuestion::Handled),
    ),
    (
        "what did you do about it",
        Question::Run(RunQuestion::Handled),
    ),
    (
        "what did you do about the failure",
        Question::Run(RunQuestion::Handled),
    ),
];

fn can_you(s: &str) -> Option<Intent> {
    for p in [
        "can you ",
        "could you ",
        "are you able to ",
        "can the robot ",
    ] {
        if let Some(x) = s.strip_prefix(p) {
            let x = x.trim();
            if !x.is_empty() {
                return Some(Intent::Fixed(Question::CanYou(x.to_string())));
            }
        }
    }
    None
}

fn tick(s: &str) -> Option<Intent> {
    let words: Vec<&str> = s.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "tick")?;
    let n: u32 = words.get(at + 1)?.parse().ok()?;
    let before = words[..at].join(" ");
    let asks = [
        "",
        "what happened at",
        "what happened in",
        "what happened on",
        "what happened during",
        "what did you do at",
        "what did you do in",
        "what changed at",
        "what changed in",
        "show",
    ];
    (at + 2 == words.len() && asks.contains(&before.as_str()) && n > 0).then_some(Intent::Tick(n))
}

fn recovered(s: &str) -> Option<Intent> {
    const ASKS: &[&str] = &[
        "did the recovery work",
        "did the recovery succeed",
        "did the recovery help",
        "was the recovery successful",
        "did recovery work",
        "did it recover",
        "did you recover",
        "did the robot recover",
        "did the retry work",
        "did the retry succeed",
        "did the fallback work",
        "did the fallback succeed",
        "were you able to recover",
        "recovered",
    ];
    ASKS.contains(&s).then_some(Intent::Recovered)
}

fn next(s: &str) -> Option<Intent> {
    const ASKS: &[&str] = &[
        "what will you do next",
        "what are you going to do next",
        "what do you do next",
        "what is next",
        "what next",
        "what comes next",
        "what happens next",
        "what will happen next",
        "next",
    ];
    ASKS.contains(&s).then_some(Intent::Next)
}

fn what_if(s: &str) -> Option<Intent> {
    let rest = ["what if ", "what happens if ", "what would happen if "]
        .iter()
        .find_map(|p| s.strip_prefix(p))?;
    let (node, event) = subject_event(rest)?;
    matches!(event, Event::Fail | Event::Succeed).then_some(Intent::WhatIf { node, event })
}

/// "why did you do X instead of Y", "why X and not Y", "why X rather
/// than Y", where X and Y are nodes, not outcomes.
fn why_instead(s: &str) -> Option<Intent> {
    let rest = [
        "why did you do ",
        "why did you run ",
        "why did you choose ",
        "why ",
    ]
    .iter()
    .find_map(|p| s.strip_prefix(p))?;
    for sep in [" instead of ", " and not ", " rather than "] {
        if let Some((done, instead)) = rest.split_once(sep) {
            if event_word(instead).is_some() || done.starts_with("did ") {
                return None;
            }
            return Some(Intent::WhyNot {
                done: subject(done),
                instead: subject(instead),
            });
        }
    }
    None
}

fn why(s: &str) -> Option<Intent> {
    let rest = s.strip_prefix("why ")?;
    let (clause, foil) = split_foil(rest);
    let clause = ["did ", "does ", "was ", "is ", "has ", "had "]
        .iter()
        .find_map(|p| clause.strip_prefix(p))
        .unwrap_or(clause);
    // "why did not X run" (from "why didn't X run").
    let (clause, negated) = match clause.strip_prefix("not ") {
        Some(rest) => (rest, true),
        None => (clause, false),
    };
    let (node, event) = subject_event(clause)?;
    let event = match (negated, event) {
        (false, e) => e,
        (true, Event::Run) => Event::NotRun,
        (true, _) => return None,
    };
    Some(Intent::Why { node, event, foil })
}

/// "X failed instead of succeeding" → ("X failed", Succeed).
fn split_foil(s: &str) -> (&str, Option<Event>) {
    for sep in [" instead of ", " rather than ", " and not ", " but not "] {
        if let Some((a, b)) = s.split_once(sep) {
            if let Some(e) = event_word(b) {
                return (a, Some(e));
            }
        }
    }
    (s, None)
}

fn when(s: &str) -> Option<Intent> {
    let rest = ["when did ", "when was ", "when does ", "when is "]
        .iter()
        .find_map(|p| s.strip_prefix(p))?;
    let (rest, which) = which_of(rest);
    let (node, event) = subject_event(&rest)?;
    (!matches!(event, Event::NotRun | Event::Skipped)).then_some(Intent::When {
        node,
        event,
        which,
    })
}

/// Takes "first", "last", "every time" out of a "when" clause.
fn which_of(s: &str) -> (String, Which) {
    let mut which = Which::Every;
    let mut out = s.to_string();
    for (w, k) in [
        (" for the first time", Which::First),
        (" the first time", Which::First),
        (" for the last time", Which::Last),
        (" the last time", Which::Last),
        (" every time", Which::Every),
        (" each time", Which::Every),
    ] {
        if let Some(p) = out.strip_suffix(w) {
            out = p.to_string();
            which = k;
        }
    }
    let words: Vec<&str> = out.split_whitespace().collect();
    let mut kept = Vec::new();
    for (i, word) in words.iter().enumerate() {
        // "when did X first fail": the adverb sits before the verb.
        let before_verb = i + 1 < words.len() && event_word(&words[i + 1..].join(" ")).is_some();
        match *word {
            "first" if before_verb => which = Which::First,
            "last" | "finally" if before_verb => which = Which::Last,
            _ => kept.push(*word),
        }
    }
    (kept.join(" "), which)
}

fn how_often(s: &str) -> Option<Intent> {
    let rest = [
        "how often did ",
        "how often was ",
        "how often has ",
        "how many times did ",
        "how many times was ",
        "how many times has ",
    ]
    .iter()
    .find_map(|p| s.strip_prefix(p))?;
    let (node, event) = subject_event(rest)?;
    (!matches!(event, Event::NotRun | Event::Skipped)).then_some(Intent::HowOften { node, event })
}

/// "look at chuck fail" → (look at chuck, Fail): the longest verb phrase
/// that ends the clause.
fn subject_event(clause: &str) -> Option<(Subject, Event)> {
    let words: Vec<&str> = clause.split_whitespace().collect();
    for cut in 1..words.len() {
        let verb = words[cut..].join(" ");
        if let Some(e) = event_word(&verb) {
            let who = words[..cut].join(" ");
            return Some((subject(&who), e));
        }
    }
    None
}

/// The verb phrases of each event.
const EVENTS: &[(&[&str], Event)] = &[
    (
        &[
            "fail",
            "failed",
            "fails",
            "failing",
            "keep failing",
            "kept failing",
            "abort",
            "aborted",
        ],
        Event::Fail,
    ),
    (
        &[
            "succeed",
            "succeeded",
            "succeeds",
            "succeeding",
            "success",
            "work",
            "worked",
            "pass",
            "passed",
        ],
        Event::Succeed,
    ),
    (
        &[
            "run",
            "ran",
            "runs",
            "start",
            "started",
            "starts",
            "execute",
            "executed",
            "ticked",
            "tick",
            "called",
            "triggered",
            "begin",
            "began",
        ],
        Event::Run,
    ),
    (
        &[
            "not run",
            "not start",
            "not execute",
            "not executed",
            "not ticked",
            "not tick",
            "not called",
            "never run",
            "never ran",
            "not get ticked",
            "not triggered",
        ],
        Event::NotRun,
    ),
    (&["skipped", "skip"], Event::Skipped),
    (
        &[
            "halted",
            "halt",
            "stopped",
            "stop",
            "interrupted",
            "cancelled",
            "canceled",
            "preempted",
        ],
        Event::Halted,
    ),
    (
        &[
            "keep running",
            "kept running",
            "still running",
            "running",
            "take so long",
            "take long",
            "taking so long",
        ],
        Event::KeepRunning,
    ),
    (
        &[
            "finish",
            "finished",
            "end",
            "ended",
            "complete",
            "completed",
            "done",
        ],
        Event::Finish,
    ),
];

/// A verb phrase as an event: "fail", "not run", "get halted", "keep
/// running", "succeeding", …
fn event_word(verb: &str) -> Option<Event> {
    let v = verb.trim();
    let v = v
        .strip_prefix("get ")
        .or_else(|| v.strip_prefix("be "))
        .or_else(|| v.strip_prefix("been "))
        .unwrap_or(v);
    let v = v
        .strip_suffix(" at all")
        .or_else(|| v.strip_suffix(" so often"))
        .or_else(|| v.strip_suffix(" again"))
        .unwrap_or(v);
    EVENTS
        .iter()
        .find(|(words, _)| words.contains(&v))
        .map(|(_, e)| *e)
}

/// "you", "the robot", "the task", "it" are the task itself (the root).
fn subject(who: &str) -> Subject {
    let w = who.trim();
    let task = [
        "you",
        "it",
        "the robot",
        "the task",
        "the tree",
        "the mission",
        "the run",
        "the whole task",
        "the behavior tree",
        "the behaviour tree",
        "the root",
        "root",
    ];
    if task.contains(&w) {
        Subject::Task
    } else {
        Subject::Named(w.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(s: &str) -> Subject {
        Subject::Named(s.into())
    }

    #[test]
    fn why_questions_name_the_node_the_event_and_the_foil() {
        assert_eq!(
            parse("Why did look at chuck fail?"),
            Some(Intent::Why {
                node: named("look at chuck"),
                event: Event::Fail,
                foil: None
            })
        );
        assert_eq!(
            parse("why didn't ask run"),
            Some(Intent::Why {
                node: named("ask"),
                event: Event::NotRun,
                foil: None
            })
        );
        assert_eq!(
            parse("Why did FollowPath fail instead of succeeding?"),
            Some(Intent::Why {
                node: named("followpath"),
                event: Event::Fail,
                foil: Some(Event::Succeed)
            })
        );
        assert_eq!(
            parse("why was lift arm skipped"),
            Some(Intent::Why {
                node: named("lift arm"),
                event: Event::Skipped,
                foil: None
            })
        );
        assert_eq!(
            parse("Why did the task fail?"),
            Some(Intent::Why {
                node: Subject::Task,
                event: Event::Fail,
                foil: None
            })
        );
        assert_eq!(
            parse("why did you do reset arm instead of approach door"),
            Some(Intent::WhyNot {
                done: named("reset arm"),
                instead: named("approach door")
            })
        );
    }

    #[test]
    fn other_intents_in_several_phrasings() {
        assert_eq!(
            parse("q5"),
            Some(Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)))
        );
        assert_eq!(
            parse("What's wrong?"),
            Some(Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)))
        );
        assert_eq!(parse("what happened at tick 10"), Some(Intent::Tick(10)));
        assert_eq!(
            parse("when did look at chuck first fail"),
            Some(Intent::When {
                node: named("look at chuck"),
                event: Event::Fail,
                which: Which::First
            })
        );
        assert_eq!(
            parse("How many times did detect chuck fail?"),
            Some(Intent::HowOften {
                node: named("detect chuck"),
                event: Event::Fail
            })
        );
        assert_eq!(parse("did the recovery work?"), Some(Intent::Recovered));
        assert_eq!(parse("What will you do next?"), Some(Intent::Next));
        assert_eq!(
            parse("what if retreat arm fails"),
            Some(Intent::WhatIf {
                node: named("retreat arm"),
                event: Event::Fail
            })
        );
        assert_eq!(
            parse("Could you back up?"),
            Some(Intent::Fixed(Question::CanYou("back up".into())))
        );
        assert_eq!(parse("make me a sandwich"), None);
        assert_eq!(parse("why"), None);
    }
}
