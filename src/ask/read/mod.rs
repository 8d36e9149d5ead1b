//! A question → what it asks, read as an intent reader reads: its words
//! made standard (`words`), the moment it names taken out (`when`), the
//! nodes it names found as spans against this tree's vocabulary
//! (`mentions`), then what is asked, from the words that are left (cue
//! words, negation, "instead of"), with a confidence. The order of the
//! parts, imperatives ("explain", "tell me") and filler change nothing.

mod can_you;
mod classify;
mod clauses;
mod colours;
mod coursework;
mod cues;
mod event;
pub mod mentions;
mod naming;
mod one;
mod repair;
mod rewrite;
mod shorthand;
mod story;
pub use shorthand::initials_naming_nothing;
pub mod when;
pub mod words;

use super::parse::{Event, Intent, Subject};
use crate::explain::{Question, RunQuestion, TreeQuestion};
use crate::model::{Kind, Tree, Uid};
use can_you::can_you;
pub use can_you::{said_by, wraps_a_question};
use classify::classify;
use clauses::{
    children_by_place, counted_among_alike, deepest, elided_foil, failure_clause,
    governing_verbs_dropped, moment_of_an_event, scoped, tick_of_a_failure,
};
use event::{
    event, foil, gave_up, joined, loops_of, negated_first, progressive, subject, uids_of, verbless,
};
pub use mentions::{Mention, Vocabulary};
use naming::*;
use one::*;
use rewrite::{ids_as_uids, named_as_uids, paths_as_uids, ports_as_uids, states_as_outcomes};
use story::*;
pub use when::{alike, ordinal_word, Side, When};
use words::Word;

/// Below this, the answer says what it read and offers other readings.
pub const SURE: f32 = 0.7;

/// What a question was read as.
#[derive(Debug, Clone, PartialEq)]
pub struct Reading {
    pub intent: Intent,
    /// 0 to 1: how much of the question the reading accounts for, and how
    /// closely its node names match the tree's.
    pub confidence: f32,
    /// Other readings, best first (at most three).
    pub alternatives: Vec<Intent>,
    /// The moment the question names, if any.
    pub when: Option<When>,
    /// For Han's questions asked of a node named ("why is it looking at
    /// the chuck?"): that node, in place of the selected one.
    pub about: Option<Vec<Uid>>,
}

/// A question's words with the parts already read marked.
struct Sentence<'a> {
    q: &'a [Word],
    /// Stems of the tree's own words: a verb that names a node's deed
    /// ("cleared") is not an unexplained word.
    tree_words: &'a rustc_hash::FxHashSet<String>,
    /// Positions read as a moment or a node.
    used: Vec<bool>,
    nodes: Vec<Mention>,
}

impl<'a> Sentence<'a> {
    /// The same words (corrected as `q`), read with `nodes` as its node
    /// mentions: their words are read, the rest are left to ask.
    fn with_nodes(&self, q: &'a [Word], nodes: Vec<Mention>) -> Sentence<'a> {
        let mut used = self.used.clone();
        for m in &nodes {
            for u in &mut used[m.start..m.end] {
                *u = true;
            }
        }
        Sentence {
            q,
            tree_words: self.tree_words,
            used,
            nodes,
        }
    }

    fn free(&self) -> impl Iterator<Item = (usize, &Word)> + '_ {
        self.q.iter().enumerate().filter(|(i, _)| !self.used[*i])
    }
    fn has(&self, text: &str) -> bool {
        self.free().any(|(_, w)| w.text == text)
    }
    fn has_stem(&self, stems: &[&str]) -> bool {
        self.free().any(|(_, w)| stems.contains(&w.stem.as_str()))
    }
    fn has_prefix(&self, prefixes: &[&str]) -> bool {
        self.free()
            .any(|(_, w)| prefixes.iter().any(|p| w.text.starts_with(p)))
    }
    /// Words in a row among the free ones ("how often").
    fn phrase(&self, p: &[&str]) -> Option<usize> {
        let free: Vec<(usize, &Word)> = self.free().collect();
        free.windows(p.len())
            .find(|win| win.iter().zip(p).all(|((_, w), t)| w.text == *t))
            .map(|win| win[0].0)
    }
    /// The first word that may ask, past politeness and imperatives.
    fn first_free(&self) -> Option<&str> {
        self.free()
            .map(|(_, w)| w.text.as_str())
            .find(|w| !LEAD.contains(w) && !IMPERATIVE.contains(w))
    }

    /// Whether the question's last words are these ("… what now").
    fn ends_with(&self, words: &[&str]) -> bool {
        self.q.len() >= words.len()
            && self.q[self.q.len() - words.len()..]
                .iter()
                .map(|w| w.text.as_str())
                .eq(words.iter().copied())
    }

    /// Whether nothing but filler is left.
    fn empty(&self) -> bool {
        self.free().all(|(_, w)| {
            FILLER.contains(&w.text.as_str()) || IMPERATIVE.contains(&w.text.as_str())
        })
    }
}

/// Words after "why" that make it not a bare verb ("why look around?"):
/// auxiliaries, articles and the robot named.
const NOT_A_VERB: &[&str] = &[
    "did", "was", "is", "does", "do", "were", "has", "have", "had", "are", "not", "would", "could",
    "will", "can", "the", "it", "you", "so", "robot", "bot", "they", "he", "she", "we",
];

/// Words a question may open with that ask nothing.
const LEAD: &[&str] = &[
    "please", "btx", "hey", "hi", "so", "ok", "um", "uh", "umm", "hmm", "well", "just", "and",
    "but", "then", "also", "me", "quick", "question", "bro", "dude", "now", "i", "wonder", "want",
    "to", "know", "yo", "ngl", "bruh", "lowkey", "guys", "yall", "folks",
];

/// Words that ask nothing: politeness, imperatives, hedges.
const FILLER: &[&str] = &[
    "please",
    "btx",
    "hey",
    "hi",
    "so",
    "ok",
    "um",
    "uh",
    "umm",
    "hmm",
    "well",
    "just",
    "exactly",
    "actually",
    "really",
    "then",
    "like",
    "quick",
    "quickly",
    "question",
    "bro",
    "man",
    "dude",
    "lol",
    "again",
    "here",
    "there",
    "this",
    "one",
    "in",
    "with",
    "about",
    "on",
    "at",
    "of",
    "to",
    "for",
    "and",
    "or",
    "but",
    "the",
    "a",
    "an",
    "me",
    "i",
    "we",
    "us",
    "know",
    "want",
    "wonder",
    "wondering",
    "curious",
    "now",
    "moment",
    "thanks",
    "thank",
    "you",
    "it",
    "that",
    "is",
    "are",
    "was",
    "were",
    "be",
    "been",
    "do",
    "does",
    "did",
    "have",
    "has",
    "had",
    "can",
    "could",
    "would",
    "will",
    "should",
    "any",
    "some",
    "exact",
    "precisely",
    "briefly",
    "robot",
    "bot",
    "agent",
    "system",
    "today",
    "this",
    "these",
    "those",
    "time",
    "run",
    "log",
    "during",
    "by",
    "from",
    "guess",
    "mean",
    "means",
    "happen",
    "happened",
    "hell",
    "heck",
    "earth",
    "on",
    "up",
    "out",
    "all",
    "everything",
    "something",
    "anything",
    "go",
    "get",
    "got",
    "kind",
    "sort",
    "as",
    "my",
    "your",
    "its",
    "our",
    "their",
    "they",
    "he",
    "she",
    "him",
    "her",
    "again",
    "yet",
    "still",
    "even",
    "ever",
    "whole",
    "entire",
    "currently",
    "right",
    "real",
    "go",
    "going",
    "okay",
];

/// Imperatives that ask what the words after them ask.
const IMPERATIVE: &[&str] = &[
    "explain",
    "tell",
    "show",
    "describe",
    "list",
    "give",
    "say",
    "summarize",
    "summarise",
    "report",
    "display",
    "print",
    "find",
    "help",
    "let",
    "remind",
];

/// The words of the robot's world (`about_the_world`).
const WORLD: &[&str] = &[
    "cost",
    "costs",
    "price",
    "prices",
    "priced",
    "pricing",
    "buy",
    "bought",
    "purchase",
    "purchased",
    "warranty",
    "distro",
    "distribution",
    "install",
    "installed",
    "installing",
    "installation",
    "firmware",
    "license",
    "licence",
    "licensing",
    "maintenance",
    "weather",
    "windows",
    "ubuntu",
    "macos",
    "rmw",
    "recommend",
    "meters",
    "ram",
    "cpu",
    "raining",
    "rain",
    "snow",
    "metres",
    "kilometers",
    "miles",
    "recommendation",
    "tune",
    "tuning",
    "temperature",
    "humidity",
    "owner",
    "vendor",
    "vendors",
    "supplier",
    "sell",
    "sells",
    "sold",
    "sales",
    "revenue",
    "profit",
    "brand",
    "manufacturer",
    "month",
    "payload",
    "voltage",
    "speed",
    "velocity",
    "lighting",
    "algorithm",
    "launch",
    "hardware",
    "engine",
    "fence",
    "safe",
    "wrote",
    "author",
    "team",
    "calibrated",
    "calibration",
    "lidar",
    "trained",
    "training",
    "dataset",
    "resolution",
    "sender",
];

/// Words of questions about the robot's world, not its run (what it costs,
/// what software it runs, its upkeep): the run holds no answer, so no node
/// named, none is read.
fn about_the_world(word: &str) -> bool {
    WORLD.contains(&word)
}

/// Words that ask, by stem: a node named by one of them only is a weak
/// mention ("wait" in "wait, what failed?").
fn asks(stem: &str) -> bool {
    const CUES: &[&str] = &[
        "what",
        "whi",
        "why",
        "how",
        "when",
        "where",
        "which",
        "who",
        "fail",
        "succeed",
        "success",
        "run",
        "start",
        "go",
        "goal",
        "subgoal",
        "task",
        "mission",
        "do",
        "next",
        "wrong",
        "problem",
        "error",
        "recov",
        "recoveri",
        "handl",
        "can",
        "tick",
        "step",
        "happen",
        "be",
        "have",
        "it",
        "you",
        "robot",
        "now",
        "not",
        "if",
        "step",
        "work",
        "help",
        "objective",
        "doing",
    ];
    CUES.contains(&stem)
}

/// The question the text asks, as its asker meant it: an exercise's
/// task as the question it sets, the asker's corrections of themselves
/// applied ("can you grasp — sorry, can you release a screw?").
pub fn as_meant(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> String {
    let set = coursework::as_asked(text);
    repair::repaired(vocabulary, tree, &set).into_owned()
}

/// Reads a question about a tree. A post that tells its story before it
/// asks ("We ran the cell overnight … Why did reset arm run?") is read
/// whole, and, where the whole is not read surely, its questions are read
/// each on its own: the surest of them, the first of equals (what follows
/// a question is most often about it: "Is this a bug?"), is what it asks.
pub fn read(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    let text = &the_text_asked(vocabulary, tree, text);
    let whole = read_one(vocabulary, tree, text);
    let questions = questions_in(text);
    let (asked, all_of_the_world) = surest_question(vocabulary, tree, &questions);
    // "Why is the controller running again? I thought it failed": a
    // question that stands on its own (no "it" or "that" pointing into
    // the story, no topic before a colon), read surely, is what the post
    // asks; the story around it only tells when.
    if let (Some(w), [q]) = (&whole, &questions[..]) {
        match asked.clone() {
            // "Why is it being ticked again?": Han's why asks of what runs
            // now, whatever "it" the story names.
            Some(mut a)
                if a.confidence >= SURE
                    && !after_a_supposition(whole.as_ref(), &a)
                    && (stands_alone(text, q, of_the_robot(&a))
                        || a.intent == Intent::Fixed(Question::Tree(TreeQuestion::Why))
                            && q.to_lowercase().contains(" again")) =>
            {
                let story = &text[..text.find(*q).unwrap_or(0)];
                a.when = a
                    .when
                    .or_else(|| moment_of_the_node(vocabulary, tree, story, &a))
                    .or(w.when);
                return Some(a);
            }
            _ => {}
        }
    }
    if let Some(a) =
        asked_after_the_story(vocabulary, tree, text, whole.as_ref().and_then(|w| w.when))
    {
        return Some(a);
    }
    // "Random one, apologies. Who wrote this tree? I'd like to ask them
    // about the retry counts.": a post whose questions all ask of the
    // world asks nothing of the run, whatever its story names.
    if all_of_the_world {
        return None;
    }
    if whole.as_ref().is_some_and(|r| r.confidence >= SURE) {
        return whole;
    }
    // "Final status is SUCCESS but two nodes are red, did anything go
    // wrong": where nothing of the whole is read, the question after the
    // story's comma, read surely (where the whole is read, the words before
    // the comma say what it is about: "the ask about the large gear, when
    // was it triggered?").
    if whole.is_none() && asked.as_ref().is_none_or(|q| q.confidence < SURE) {
        if let Some(mut a) =
            asked_after_a_comma(vocabulary, tree, text).filter(|a| a.confidence >= SURE)
        {
            // "Up to and including tick 2, has anything gone wrong?": the
            // moment said before the comma.
            a.when = a
                .when
                .or_else(|| when::find(&words::words(text)).map(|(w, _)| w));
            return Some(a);
        }
    }
    match (whole, asked) {
        (Some(w), Some(a)) if a.confidence <= w.confidence => Some(w),
        (Some(w), Some(a)) if after_a_supposition(Some(&w), &a) => Some(w),
        // "Actual: FollowPath FAILURE. … Why did it fail?": "it" is the
        // node the story told of doing what the question asks about.
        (Some(w), Some(a)) if the_story_asks_it(&a, &w) && reported(text) => Some(w),
        // The moment the story told ("… returned FAILURE at tick 10. Why
        // did look at chuck fail there?"), where the question says none.
        (Some(w), Some(mut a)) => {
            a.when = a.when.or(w.when);
            Some(a)
        }
        (w, a) => a.or(w),
    }
}

/// The surest reading of the questions a text asks, the first of equals,
/// and whether they all ask of the robot's world.
fn surest_question(
    vocabulary: &Vocabulary,
    tree: &Tree,
    questions: &[&str],
) -> (Option<Reading>, bool) {
    let heard_each: Vec<Result<Reading, Unread>> = questions
        .iter()
        .map(|q| heard(vocabulary, tree, q))
        .collect();
    let all_of_the_world = !heard_each.is_empty()
        && heard_each
            .iter()
            .all(|h| matches!(h, Err(Unread::OfTheWorld)));
    let asked = heard_each
        .into_iter()
        .filter_map(Result::ok)
        .reduce(|a, b| if b.confidence > a.confidence { b } else { a });
    (asked, all_of_the_world)
}

/// The text as its asker meant it, without what they add to a question
/// that asks nothing more (a guess at its answer, an aside, a doubt), a
/// bare "why?" after a story asked of the story.
fn the_text_asked(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> String {
    // "… lost track of where we are -- which part is it on?": a typed
    // double hyphen is the dash it stands for.
    let meant = as_meant(vocabulary, tree, text).replace(" -- ", " - ");
    let unaside = without_asides(&meant);
    let text = without_a_guess(without_a_challenge(&unaside));
    why_of_the_story(text).unwrap_or_else(|| text.to_string())
}

/// "Assume FollowPath held at tick 4. How'd the run go?": a question after
/// what the story supposes (the whole read as a what-if) asks what comes
/// of it, however surely it reads alone.
fn after_a_supposition(whole: Option<&Reading>, asked: &Reading) -> bool {
    whole.is_some_and(|w| matches!(w.intent, Intent::WhatIf { .. }))
        && !matches!(asked.intent, Intent::WhatIf { .. })
}

/// Whether a reading asks of an event of the task or "it", no node named
/// ("how often did it run?").
pub fn asks_of_the_task_unnamed(i: &Intent) -> bool {
    match i {
        Intent::Why { node, .. }
        | Intent::When { node, .. }
        | Intent::HowOften { node, .. }
        | Intent::WhatIf { node, .. } => matches!(node, Subject::Task | Subject::It),
        Intent::WhyNot { done, instead } => {
            !matches!(done, Subject::Nodes(..)) || !matches!(instead, Subject::Nodes(..))
        }
        _ => false,
    }
}

/// Words that ask for advice, which no run holds ("can you recommend
/// a better detector?").
pub const ADVICE: &[&str] = &[
    "recommend",
    "recommendation",
    "recommendations",
    "suggest",
    "advise",
    "advice",
    "opinion",
];

/// An intent said back in btx's words, for "did you mean".
pub fn wording(tree: &Tree, intent: &Intent) -> String {
    let who = |s: &Subject| match s {
        Subject::Task => "the task".to_string(),
        Subject::It => "it".to_string(),
        Subject::Named(p) => p.clone(),
        Subject::Nodes(us, _) => tree.told(us[0]),
    };
    let verb = |e: Event| match e {
        Event::Fail => "fail",
        Event::Succeed => "succeed",
        Event::Run => "run",
        Event::NotRun => "not run",
        Event::Skipped => "get skipped",
        Event::Halted => "get halted",
        Event::KeepRunning => "keep running",
        Event::Finish => "finish",
    };
    match intent {
        Intent::Fixed(q) => q.wording(),
        Intent::Why { node, event, .. } => format!("Why did {} {}?", who(node), verb(*event)),
        Intent::WhyNot { done, instead } => {
            format!("Why did I do {} and not {}?", who(done), who(instead))
        }
        Intent::When { node, event, .. } => format!("When did {} {}?", who(node), verb(*event)),
        Intent::HowOften { node, event } => {
            format!("How often did {} {}?", who(node), verb(*event))
        }
        Intent::Tick(n) => format!("What happened at tick {n}?"),
        Intent::Next => "What will you do next?".into(),
        Intent::WhatIf {
            node,
            event: Event::KeepRunning,
        } => format!("What if {} keeps running?", who(node)),
        Intent::WhatIf { node, event } => format!("What if {} {}s?", who(node), verb(*event)),
        Intent::Recovered => "Did the recovery work?".into(),
    }
}
