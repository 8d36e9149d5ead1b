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
mod rewrite;
mod shorthand;
pub use shorthand::initials_naming_nothing;
pub mod when;
pub mod words;

use super::parse::{Event, Intent, Subject};
use crate::explain::{Question, TreeQuestion};
use crate::model::{Kind, Tree, Uid};
use can_you::can_you;
pub use can_you::wraps_a_question;
use classify::classify;
use clauses::{
    children_by_place, counted_among_alike, deepest, elided_foil, failure_clause,
    governing_verbs_dropped, moment_of_an_event, scoped, tick_of_a_failure,
};
use event::{
    event, foil, gave_up, joined, loops_of, negated_first, progressive, subject, uids_of, verbless,
};
pub use mentions::{Mention, Vocabulary};
use rewrite::{ids_as_uids, named_as_uids, paths_as_uids, ports_as_uids, states_as_outcomes};
pub use when::{ordinal_word, Side, When};
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
    "to", "know",
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

/// Words that ask, by stem: a node named by one of them only is a weak
/// mention ("wait" in "wait, what failed?").
/// Words of questions about the robot's world, not its run (what it costs,
/// what software it runs, its upkeep): the run holds no answer, so no node
/// named, none is read.
fn about_the_world(word: &str) -> bool {
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
    ];
    WORLD.contains(&word)
}

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

/// Reads a question about a tree. A post that tells its story before it
/// asks ("We ran the cell overnight … Why did reset arm run?") is read
/// whole, and, where the whole is not read surely, its questions are read
/// each on its own: the surest of them, the first of equals (what follows
/// a question is most often about it: "Is this a bug?"), is what it asks.
pub fn read(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    let set = coursework::as_asked(text);
    let text = without_a_challenge(after_a_correction(&set));
    let why_asked = why_of_the_story(text);
    let text = why_asked.as_deref().unwrap_or(text);
    let whole = read_one(vocabulary, tree, text);
    let questions = questions_in(text);
    let asked = questions
        .iter()
        .filter_map(|q| read_one(vocabulary, tree, q))
        .reduce(|a, b| if b.confidence > a.confidence { b } else { a });
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
                    && (stands_alone(text, q, of_the_robot(&a))
                        || a.intent == Intent::Fixed(Question::Tree(TreeQuestion::Why))
                            && q.to_lowercase().contains(" again")) =>
            {
                a.when = a.when.or(w.when);
                return Some(a);
            }
            _ => {}
        }
    }
    // "Spin failed a moment ago within this same tick, so why is it
    // running again?": what follows ", so" is asked; the story before it
    // says when.
    if let Some(mut a) = asked_after_so(vocabulary, tree, text).filter(|a| a.confidence >= SURE) {
        a.when = a.when.or(whole.as_ref().and_then(|w| w.when));
        return Some(a);
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

/// Whether the question `q` of the post `text` stands on its own: no
/// "it" or "that" pointing into the story (in a question of Han's that
/// names no node, "it" is the robot: "The arm has moved over to the caddy
/// now. How does it go about the task it's currently on?"), no topic
/// before a colon. "At this point" points at the story's moment, which
/// the reading takes from the whole, not at a thing the story names.
fn stands_alone(text: &str, q: &str, it_is_the_robot: bool) -> bool {
    let said = words::words(q);
    let pointing: &[&str] = if it_is_the_robot {
        &["that", "this", "there", "them", "they", "these", "those"]
    } else {
        &[
            "it", "its", "that", "this", "there", "them", "they", "these", "those",
        ]
    };
    // "What went on in it?": an "it" after a preposition is a thing.
    let a_thing = |i: usize| {
        i > 0
            && [
                "in", "of", "on", "at", "about", "with", "for", "from", "during",
            ]
            .contains(&said[i - 1].text.as_str())
    };
    said.len() >= 3
        && !text[..text.find(q).unwrap_or(0)].trim_end().ends_with(':')
        && !said.iter().enumerate().any(|(i, w)| {
            (pointing.contains(&w.text.as_str())
                || it_is_the_robot && ["it", "its"].contains(&w.text.as_str()) && a_thing(i))
                && !said.get(i + 1).is_some_and(|n| {
                    ["point", "moment", "instant", "stage", "time"].contains(&n.text.as_str())
                })
        })
}

/// Whether "it" in a question of Han's is the robot: one that names no
/// node, or a why that names its own ("… Why is it asking for help at
/// this point?").
fn of_the_robot(a: &Reading) -> bool {
    match a.intent {
        Intent::Fixed(Question::Tree(TreeQuestion::Why)) => a.about.is_some(),
        Intent::Fixed(Question::Tree(_)) => a.about.is_none(),
        _ => false,
    }
}

/// A report of what was expected and what happened ("Actual: …",
/// "Expected: …", "Observed: …").
fn reported(text: &str) -> bool {
    words::words(text)
        .iter()
        .any(|w| ["expected", "actual", "observed"].contains(&w.text.as_str()))
}

/// Whether the story's reading is what its short question asks: "Why did
/// it fail?" and "Root cause?" of the node the story told failed; "Why
/// ask?" after "expected a 4th attempt, actual: ask ran" of the contrast.
fn the_story_asks_it(asked: &Reading, story: &Reading) -> bool {
    match (&asked.intent, &story.intent) {
        (
            Intent::Why {
                node: Subject::It | Subject::Task,
                event: a,
                foil: None,
            },
            Intent::Why {
                node: Subject::Nodes(..),
                event: b,
                foil: None,
            },
        ) => a == b || *a == Event::Run,
        (
            Intent::Why {
                node: Subject::It | Subject::Task,
                ..
            },
            Intent::WhyNot { .. },
        ) => true,
        (
            Intent::Fixed(Question::Tree(TreeQuestion::Why)),
            Intent::WhyNot {
                done: Subject::Nodes(us, _),
                ..
            },
        ) => asked.about.as_ref() == Some(us),
        (
            Intent::Why {
                node: Subject::Nodes(a, _),
                ..
            },
            Intent::WhyNot {
                done: Subject::Nodes(b, _),
                ..
            },
        ) => a == b,
        _ => false,
    }
}

/// "Retreat arm succeeded at 11:1 but reset arm still returned FAILURE at
/// 11:3. Why?": a bare why after a story that sets one thing against
/// another asks why of the part after its last "but" or "yet".
fn why_of_the_story(text: &str) -> Option<String> {
    const BARE: &[&str] = &[
        "why?",
        "why so?",
        "why is that?",
        "but why?",
        "how come?",
        "why though?",
    ];
    let t = text.trim();
    // ASCII: the lowercase copy keeps the text's offsets.
    if !t.is_ascii() {
        return None;
    }
    let lower = t.to_ascii_lowercase();
    let bare = BARE.iter().find(|b| lower.ends_with(*b))?;
    // Only after a sentence of its own: "…FAILURE at 11:3. Why?".
    let story = t[..t.len() - bare.len()]
        .trim_end()
        .strip_suffix(['.', ',', ';', '-'])?
        .trim_end();
    if story.is_empty() {
        return None;
    }
    let last = story
        .rfind(['.', '!', ';'])
        .map_or(story, |i| &story[i + 1..]);
    let l = last.to_ascii_lowercase();
    // "We expected L1 here but actually saw L2. Why?": an expectation
    // against what happened asks why the one and not the other, read whole.
    if [
        "expect", "thought", "should", "supposed", "wanted", "instead",
    ]
    .iter()
    .any(|w| l.contains(w))
    {
        return None;
    }
    // Only the part a "but" sets apart is the surprise; a story without
    // one is read whole (the why asks of what it tells as a whole).
    let after = [" but ", " yet "]
        .iter()
        .filter_map(|c| l.rfind(c).map(|i| i + c.len()))
        .max()?;
    let told = &last[after..];
    (told.split_whitespace().count() >= 2).then(|| format!("why {}?", told.trim()))
}

/// A question without the doubt put after it ("why is look at chuck
/// roughly being run again? didn't it already succeed?"): the doubt says
/// what the asker thought, not what is asked.
fn without_a_challenge(text: &str) -> &str {
    const DOUBTS: &[&str] = &[
        "didn't",
        "didnt",
        "wasn't",
        "wasnt",
        "hasn't",
        "hasnt",
        "isn't",
        "isnt",
        "doesn't",
        "doesnt",
        "shouldn't",
        "shouldnt",
        "wouldn't",
        "wouldnt",
    ];
    let Some(end) = text.find("? ") else {
        return text;
    };
    let rest = text[end + 2..].trim_start();
    // "… but didn't it already succeed?" too.
    let mut words = rest
        .split_whitespace()
        .map(|w| w.to_lowercase())
        .skip_while(|w| w == "but");
    let doubt = words.next().is_some_and(|w| DOUBTS.contains(&w.as_str()));
    let asks_why = text[..end].to_lowercase().starts_with("why");
    if doubt && asks_why && !rest[..rest.len().saturating_sub(1)].contains('?') {
        &text[..=end]
    } else {
        text
    }
}

/// What is asked after the asker corrected themselves ("why did the uh no
/// wait when did look at chuck fail"): the words after the last "no
/// wait", "wait no" or "scratch that", where they are a question.
fn after_a_correction(text: &str) -> &str {
    const MARKS: &[&str] = &["no wait", "wait no", "scratch that", "no sorry", "sorry no"];
    let lower = text.to_lowercase();
    if lower.len() != text.len() {
        return text;
    }
    MARKS
        .iter()
        .filter_map(|m| lower.rfind(m).map(|i| i + m.len()))
        .max()
        .map(|end| text[end..].trim_start_matches([',', '.', ' ']))
        .filter(|rest| rest.split_whitespace().count() >= 3)
        .unwrap_or(text)
}

/// The surest reading of what follows a comma where a question opens
/// there ("…, can the taxi move down", "…, what is it doing now").
fn asked_after_a_comma(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    const OPENS: &[&str] = &[
        "what", "whats", "what's", "why", "how", "when", "which", "where", "did", "does", "do",
        "is", "was", "were", "are", "can", "could", "has", "have", "will", "would",
    ];
    // "…, but did anything go wrong on the way?".
    text.match_indices(", ")
        .map(|(i, _)| text[i + 2..].strip_prefix("but ").unwrap_or(&text[i + 2..]))
        .filter(|rest| {
            rest.split_whitespace()
                .next()
                .is_some_and(|w| OPENS.contains(&w.to_lowercase().as_str()))
        })
        .filter_map(|rest| read_one(vocabulary, tree, rest))
        .reduce(|a, b| if b.confidence > a.confidence { b } else { a })
}

/// The reading of a question that follows ", so" ("…, so why is it
/// running again?").
fn asked_after_so(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    const OPENS: &[&str] = &["what", "why", "how", "when", "which", "where"];
    let (_, rest) = text.rsplit_once(", so ")?;
    let first = rest.split_whitespace().next()?.to_lowercase();
    OPENS
        .contains(&first.as_str())
        .then(|| read_one(vocabulary, tree, rest))
        .flatten()
}

/// The questions a text of several sentences asks: each sentence that
/// ends in "?", and what follows a colon ("I need the exact point in the
/// run: when did look at chuck fail?"). None for a text of one sentence.
fn questions_in(text: &str) -> Vec<&str> {
    let mut cuts = vec![0];
    let b = text.as_bytes();
    for i in 0..b.len().saturating_sub(1) {
        if matches!(b[i], b'.' | b'?' | b'!' | b':' | b';') && b[i + 1].is_ascii_whitespace() {
            cuts.push(i + 1);
        }
    }
    cuts.push(text.len());
    if cuts.len() <= 2 {
        return Vec::new();
    }
    // "CaseStudySequence has just returned FAILURE. Explain what went
    // wrong.": a last sentence that bids is asked as a question is.
    let last = cuts.len() - 2;
    cuts.windows(2)
        .enumerate()
        .map(|(i, w)| (i, text[w[0]..w[1]].trim()))
        .filter(|&(i, s)| s.ends_with('?') || i == last && bids(s, &text[..cuts[last]]))
        .map(|(_, s)| s)
        .collect()
}

/// A sentence that bids the reader explain or describe, after a story that
/// supposes nothing ("Explain what went wrong.", not "Suppose X had
/// failed. Describe what the tree would do.").
fn bids(sentence: &str, story: &str) -> bool {
    let mut words = sentence.split_whitespace();
    let first = words.next().unwrap_or("").to_lowercase();
    if !["explain", "describe"].contains(&first.as_str()) || words.count() < 2 {
        return false;
    }
    let supposes = story.split_whitespace().any(|w| {
        ["suppose", "imagine", "had", "if", "would", "hypothetically"].contains(
            &w.to_lowercase()
                .trim_matches(|c: char| !c.is_alphanumeric()),
        )
    });
    !supposes
}

fn read_one(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    if text.trim().eq_ignore_ascii_case("q5") {
        return Some(Reading {
            intent: Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)),
            confidence: 1.0,
            alternatives: Vec::new(),
            when: None,
            about: None,
        });
    }
    let text = states_as_outcomes(
        tree,
        &ids_as_uids(
            tree,
            &paths_as_uids(
                tree,
                &named_as_uids(
                    tree,
                    &ports_as_uids(
                        tree,
                        &shorthand::spelled_out(tree, &colours::as_statuses(tree, text)),
                    ),
                ),
            ),
        ),
    );
    let q = words::words(&text);
    if q.is_empty() {
        return None;
    }
    let (s, when) = named_parts(vocabulary, tree, &q);
    let mut in_mention = vec![false; q.len()];
    for m in &s.nodes {
        for f in &mut in_mention[m.start..m.end] {
            *f = true;
        }
    }
    // Typos in the words that ask ("wen", "frist", "fial"), now that the
    // tree's names have been found as they were written.
    let q: Vec<Word> = q
        .iter()
        .enumerate()
        .map(|(i, w)| {
            if in_mention[i] || s.used[i] {
                w.clone()
            } else {
                corrected(w, s.tree_words)
            }
        })
        .collect();
    if not_of_the_run(tree, &q, &s, &in_mention) {
        return None;
    }
    chosen(tree, &s, &q, readings(tree, &s, &q), when)
}

/// The moment a question names and the nodes it names, each with the
/// words it takes: "at tick 9", "#18", "look at chuck", and the clauses
/// that pick among nodes named alike or say when ("before FollowPath
/// failed").
fn named_parts<'a>(
    vocabulary: &'a Vocabulary,
    tree: &Tree,
    q: &'a [Word],
) -> (Sentence<'a>, Option<When>) {
    let mut s = Sentence {
        q,
        tree_words: vocabulary.stems(),
        used: vec![false; q.len()],
        nodes: Vec::new(),
    };
    let mut when = when::find(q).map(|(w, used)| {
        for i in used {
            if i < s.used.len() {
                s.used[i] = true;
            }
        }
        w
    });
    for i in naming_nothing(q) {
        s.used[i] = true;
    }
    for m in uids_said(tree, q, &s.used) {
        s.used[m.start] = true;
        s.nodes.push(m);
    }
    let mut mentions = vocabulary.mentions(tree, &free_words(q, &s.used), &asks);
    // "What were you doing just before look at chuck failed?", "describe
    // the tick where the spin failed": the clause says when; what is asked
    // is the rest.
    type Clause = fn(&Tree, &[Word], &[bool], &[Mention]) -> Option<(When, Vec<usize>)>;
    for clause in [
        failure_clause as Clause,
        tick_of_a_failure,
        moment_of_an_event,
    ] {
        if when.is_some() {
            break;
        }
        if let Some((w, used)) = clause(tree, q, &s.used, &mentions) {
            when = Some(w);
            for i in used {
                s.used[i] = true;
            }
            mentions.retain(|m| !(m.start..m.end).any(|i| s.used[i]));
        }
    }
    s.nodes.extend(mentions);
    s.nodes = right_as_a_tag(q, std::mem::take(&mut s.nodes));
    s.nodes = uids_told_of_names(std::mem::take(&mut s.nodes));
    s.nodes.sort_by_key(|m| m.start);
    s.nodes = halves_joined(std::mem::take(&mut s.nodes));
    s.nodes = children_by_place(tree, q, std::mem::take(&mut s.nodes));
    s.nodes = scoped(tree, q, std::mem::take(&mut s.nodes));
    s.nodes = governing_verbs_dropped(q, std::mem::take(&mut s.nodes));
    s.nodes = counted_among_alike(tree, q, std::mem::take(&mut s.nodes));
    if let Some(m) = elided_foil(vocabulary, tree, q, &s.nodes) {
        s.nodes.push(m);
    }
    (s, when)
}

/// "Clear costmap": parts of one name side by side, each found alone
/// (ClearLocalCostmap's first word and its last), are one mention.
fn halves_joined(nodes: Vec<Mention>) -> Vec<Mention> {
    let mut out: Vec<Mention> = Vec::with_capacity(nodes.len());
    for m in nodes {
        match out.last_mut() {
            Some(p) if p.end == m.start && p.uids == m.uids && !p.weak && !m.weak => {
                p.end = m.end;
                p.score = p.score.min(m.score);
                p.phrase = format!("{} {}", p.phrase, m.phrase);
            }
            _ => out.push(m),
        }
    }
    out
}

/// Words that name no node and ask nothing of their own: Han's framing
/// named, a bag's goal by number, "right" saying when.
fn naming_nothing(q: &[Word]) -> Vec<usize> {
    let mut used = han_framing(q);
    for i in 0..q.len().saturating_sub(1) {
        let next = q[i + 1].text.as_str();
        // "In goal 1", "the first tick of goal 2": a bag's goals by number
        // name the run, not the goal asked about.
        if q[i].text == "goal" && next.bytes().all(|b| b.is_ascii_digit()) {
            used.extend([i, i + 1]);
        }
        // "Right now", "right after": "right" says when, it names no move.
        if q[i].text == "right"
            && ["now", "away", "after", "before", "then", "there", "here"].contains(&next)
        {
            used.push(i);
        }
    }
    used
}

/// "#18": a uid, as everywhere in btx, among the words not yet read.
fn uids_said(tree: &Tree, q: &[Word], used: &[bool]) -> Vec<Mention> {
    q.iter()
        .enumerate()
        .filter(|(i, _)| !used[*i])
        .filter_map(|(i, w)| {
            let uid = w.text.strip_prefix('#')?.parse::<Uid>().ok()?;
            tree.get(uid)?;
            Some(Mention {
                start: i,
                end: i + 1,
                uids: vec![uid],
                score: 1.0,
                weak: false,
                phrase: w.text.clone(),
            })
        })
        .collect()
}

/// "In the goal/subgoals/steps/actions framing", "Han et al. partition
/// the tree into {goal, subgoals, steps, actions}": the framing's four
/// words in a row name the framing, not one of its questions.
fn han_framing(q: &[Word]) -> Vec<usize> {
    const PARTS: &[&str] = &["goal", "subgoal", "step", "action"];
    let part = |w: &Word| PARTS.contains(&w.stem.as_str());
    let mut used = Vec::new();
    let mut i = 0;
    while i < q.len() {
        let mut j = i;
        while j < q.len() && (part(&q[j]) || q[j].text == "and" && j > i) {
            j += 1;
        }
        let kinds: rustc_hash::FxHashSet<&str> = q[i..j]
            .iter()
            .filter(|w| part(w))
            .map(|w| w.stem.as_str())
            .collect();
        if kinds.len() >= 3 {
            used.extend(i..j);
        }
        i = j.max(i + 1);
    }
    used
}

/// "No errors, right?": a last "right" that names nothing else in the
/// question asks yes or no; it is no move right ("… go right?" is).
fn right_as_a_tag(q: &[Word], mut nodes: Vec<Mention>) -> Vec<Mention> {
    const MOVED: &[&str] = &[
        "move", "moves", "moved", "moving", "go", "goes", "went", "going", "turn", "turned",
        "turning", "the", "to", "and", "or", "than", "of",
    ];
    let tag = |m: &Mention| {
        m.end == q.len()
            && m.start + 1 == m.end
            && q[m.start].text == "right"
            && m.start > 0
            && !MOVED.contains(&q[m.start - 1].text.as_str())
    };
    if let [only] = &nodes[..] {
        if tag(only) {
            nodes.clear();
        }
    }
    nodes
}

/// "The move right at the start of navigate to destination (#15)": a uid
/// the asker adds to a name shared by several nodes says which of them
/// is meant; the name is that node, said once.
fn uids_told_of_names(mut nodes: Vec<Mention>) -> Vec<Mention> {
    let told: Vec<Uid> = nodes
        .iter()
        .filter(|m| m.phrase.starts_with('#'))
        .map(|m| m.uids[0])
        .collect();
    let mut merged = Vec::new();
    for m in nodes.iter_mut().filter(|m| !m.phrase.starts_with('#')) {
        if m.uids.len() > 1 {
            if let Some(&u) = told.iter().find(|u| m.uids.contains(u)) {
                m.uids = vec![u];
                merged.push(u);
            }
        }
    }
    nodes.retain(|m| !(m.phrase.starts_with('#') && merged.contains(&m.uids[0])));
    nodes
}

/// Advice ("what should I set num_attempts to?", "should I use
/// py_trees?") and the robot's world where no node but the task is named
/// ("what was the temperature in the cell?"): no run holds the answer.
fn not_of_the_run(tree: &Tree, q: &[Word], s: &Sentence, in_mention: &[bool]) -> bool {
    let advice = q
        .windows(2)
        .any(|p| p[0].text == "should" && ["i", "we"].contains(&p[1].text.as_str()))
        || q.iter().any(|w| ADVICE.contains(&w.text.as_str()));
    // "How much battery did it burn?": an amount the run does not hold
    // ("how much time" it does).
    let amount = q.windows(3).any(|p| {
        p[0].text == "how"
            && p[1].text == "much"
            && !["time", "longer"].contains(&p[2].text.as_str())
    });
    // "How far did it walk?": a distance in the world.
    let far = q
        .windows(2)
        .any(|p| p[0].text == "how" && p[1].text == "far");
    // "How many meters did the base drive?": a measure of the world,
    // whatever node the question names.
    let measure = q.windows(3).any(|p| {
        p[0].text == "how" && p[1].text == "many" && MEASURES.contains(&p[2].text.as_str())
    });
    // "Is Nav2 going to deprecate the Spin behavior?", "how frustrated was
    // the operator?": the world's future and feelings, whatever is named.
    // A node's own words ("feel surface") are not the world's.
    let outside = q
        .iter()
        .enumerate()
        .any(|(i, w)| !in_mention[i] && OUTSIDE.contains(&w.text.as_str()))
        // "Is the next Nav2 release going to fix this?".
        || q.windows(2).any(|p| {
            p[0].text == "next" && ["release", "version", "sprint"].contains(&p[1].text.as_str())
        });
    // "What was the battery level when the goal was reached?", "which
    // operator was on shift": the robot's world ("can you charge your
    // battery?" asks what it can do).
    let can_ask = q
        .first()
        .is_some_and(|w| ["can", "could"].contains(&w.text.as_str()));
    let world_state = !can_ask
        && q.iter()
            .enumerate()
            .any(|(i, w)| !in_mention[i] && w.text == "battery")
        || q.windows(2)
            .any(|p| p[0].text == "on" && p[1].text == "shift");
    advice
        || measure
        || outside
        || far
        || s.nodes
            .iter()
            .filter(|m| !m.weak)
            .all(|m| m.uids == [tree.root().uid])
            && (amount
                || world_state
                || q.iter()
                    .enumerate()
                    .any(|(i, w)| !in_mention[i] && about_the_world(&w.text)))
}

/// Units of the world's measures ("how many meters"; "how many frames"
/// is ticks, `words` says).
const MEASURES: &[&str] = &[
    "meters",
    "metres",
    "kilometers",
    "kilometres",
    "km",
    "miles",
    "feet",
    "centimeters",
    "cm",
    "mm",
    "millimeters",
    "degrees",
    "radians",
    "volts",
    "amps",
    "watts",
    "joules",
    "kwh",
    "calories",
    "pixels",
];

/// Words of the world's future and of feelings, which no run holds.
const OUTSIDE: &[&str] = &[
    "deprecate",
    "deprecated",
    "deprecation",
    "roadmap",
    "funding",
    "funded",
    "frustrated",
    "frustration",
    "salary",
    "budget",
    "firmware",
    "feel",
    "feels",
    "feeling",
    "feelings",
    "sprint",
];

/// What the sentence asks, best first: read with its strong mentions;
/// weak ones ("wait" in "wait, what failed?") stay words unless the
/// question names no other node and asks about one.
fn readings(tree: &Tree, s: &Sentence, q: &[Word]) -> Vec<(Intent, f32)> {
    let strong: Vec<Mention> = s.nodes.iter().filter(|m| !m.weak).cloned().collect();
    let with_strong = s.with_nodes(q, strong);
    let mut r = classify(&with_strong, tree);
    if r.is_empty()
        || r.iter().all(|(i, _)| needs_node(i))
        || r.first().is_some_and(|(i, _)| about_task(i))
    {
        let weak: Vec<Mention> = s.nodes.iter().filter(|m| m.weak).cloned().collect();
        if !weak.is_empty() && with_strong.nodes.is_empty() {
            let with_weak = s.with_nodes(q, weak);
            let alt = classify(&with_weak, tree);
            if alt.iter().any(|(i, _)| subject_of(i).is_some()) {
                r = alt;
            }
        }
    }
    // "Why did it go to recoveries instead of trying the controller": a
    // contrast needs two nodes, and a node named by a word that also asks
    // ("recoveries") is the second.
    let contrast = with_strong.phrase(&["instead", "of"]).is_some()
        || with_strong.phrase(&["rather", "than"]).is_some();
    if contrast && with_strong.nodes.len() == 1 && s.nodes.len() > 1 {
        let all = s.with_nodes(q, s.nodes.clone());
        let alt = classify(&all, tree);
        if alt
            .first()
            .is_some_and(|(i, _)| matches!(i, Intent::WhyNot { .. }))
        {
            r = alt;
        }
    }
    r.sort_by(|a, b| b.1.total_cmp(&a.1));
    r
}

/// The best reading, up to three others as alternatives, the moment it is
/// asked at, and the node a question of Han's names.
fn chosen(
    tree: &Tree,
    s: &Sentence,
    q: &[Word],
    readings: Vec<(Intent, f32)>,
    when: Option<When>,
) -> Option<Reading> {
    let mut it = readings.into_iter();
    let (intent, confidence) = it.next()?;
    let mut alternatives: Vec<Intent> = Vec::new();
    for (i, _) in it {
        if i != intent && !alternatives.contains(&i) && alternatives.len() < 3 {
            alternatives.push(i);
        }
    }
    // "Did it recover after the failure?": the failure is what the
    // recovery is from, not the moment to ask at.
    let when = match (&intent, when) {
        (Intent::Recovered, Some(When::AfterFailure | When::AfterRecovery)) => None,
        (_, w) => w,
    };
    let when = match (when::nth_time(q), when) {
        (Some(n), Some(When::BeforeFailureOf(uid) | When::AfterFailureOf(uid))) => {
            Some(When::Ended {
                uid,
                n,
                failed: true,
                side: if matches!(when, Some(When::BeforeFailureOf(_))) {
                    Side::Before
                } else {
                    Side::After
                },
            })
        }
        (Some(n), None) => nth_end(tree, &intent, n),
        (_, w) => w,
    };
    let about = match intent {
        Intent::Fixed(Question::Tree(_)) => s
            .nodes
            .iter()
            .find(|m| !m.weak && m.uids != [tree.root().uid])
            .map(|m| m.uids.clone()),
        _ => None,
    };
    Some(Reading {
        intent,
        confidence: confidence.clamp(0.0, 1.0),
        alternatives,
        when,
        about,
    })
}

/// "Why did FollowPath fail the second time?", "what if detect chuck
/// had succeeded on the third try?": the moment of the node's N-th end:
/// its N-th failure where a why asks about failing, else its N-th run to
/// an end ("why did it manage the second time": the second try; a
/// what-if's is the run it would change). "When did it fail the first
/// time" asks which, not at when.
fn nth_end(tree: &Tree, intent: &Intent, n: u32) -> Option<When> {
    let (uids, failed) = match intent {
        // "Why did it stall the first time?": of the robot, whose failures
        // are its actions'.
        Intent::Why {
            node: Subject::It,
            event: Event::Fail,
            ..
        } => return Some(When::NthFailure(n)),
        Intent::Why {
            node: Subject::Nodes(us, _),
            event,
            ..
        } => (us, *event == Event::Fail),
        Intent::WhatIf {
            node: Subject::Nodes(us, _),
            ..
        } => (us, false),
        _ => return None,
    };
    Some(When::Ended {
        uid: deepest(tree, uids),
        n,
        failed,
        side: Side::At,
    })
}

/// The words not read yet; those read are blanked.
fn free_words(q: &[Word], used: &[bool]) -> Vec<Word> {
    q.iter()
        .enumerate()
        .map(|(i, w)| {
            if used[i] {
                Word {
                    text: "\u{0}".into(),
                    stem: "\u{0}".into(),
                }
            } else {
                w.clone()
            }
        })
        .collect()
}

/// A reading about the task or "it", where a weak mention may be the node.
fn about_task(i: &Intent) -> bool {
    matches!(
        i,
        Intent::Why {
            node: Subject::Task | Subject::It,
            ..
        } | Intent::When {
            node: Subject::Task | Subject::It,
            ..
        } | Intent::HowOften {
            node: Subject::Task | Subject::It,
            ..
        }
    )
}

/// Words that ask, to correct a typo in one of them against.
const CUE_WORDS: &[&str] = &[
    "when",
    "what",
    "why",
    "first",
    "fail",
    "failed",
    "failure",
    "happened",
    "happen",
    "succeed",
    "succeeded",
    "recover",
    "recovered",
    "recovery",
    "running",
    "started",
    "doing",
    "subgoal",
    "goal",
    "wrong",
    "next",
    "handled",
    "often",
    "times",
    "tick",
    "before",
    "after",
    "last",
    "final",
    "busy",
    "going",
    "computing",
    "finish",
    "finished",
    "halted",
    "skipped",
    "instead",
    "rather",
    "explain",
    "describe",
    "objective",
    "mission",
];

fn corrected(w: &Word, tree_words: &rustc_hash::FxHashSet<String>) -> Word {
    let t = w.text.as_str();
    // A cue word's other forms ("happens" of "happen") are not typos.
    static CUE_STEMS: std::sync::OnceLock<rustc_hash::FxHashSet<String>> =
        std::sync::OnceLock::new();
    let cue_stems = CUE_STEMS.get_or_init(|| CUE_WORDS.iter().map(|c| words::stem(c)).collect());
    if t.chars().count() < 3
        || CUE_WORDS.contains(&t)
        // Words of their own a letter from a cue ("past" is not "last").
        || [
            "past", "fast", "lost", "cast", "vast", "then", "tickle", "fall", "falls", "hell",
        ]
        .contains(&t)
        || cue_stems.contains(&w.stem)
        || tree_words.contains(&w.stem)
        || FILLER.contains(&t)
        || IMPERATIVE.contains(&t)
        || LEAD.contains(&t)
        || !t.chars().all(|c| c.is_ascii_alphabetic())
    {
        return w.clone();
    }
    // "computin": a dropped g.
    if t.ends_with("in") && t.len() >= 5 {
        let g = format!("{t}g");
        let stem = words::stem(&g);
        if CUE_WORDS.contains(&g.as_str()) || tree_words.contains(&stem) {
            return Word { stem, text: g };
        }
    }
    let best = CUE_WORDS
        .iter()
        .filter(|c| c.len() >= 4 && c.len().abs_diff(t.len()) <= 1)
        .find(|c| strsim::osa_distance(c, t) <= 1 && (t.len() >= 4 || c.starts_with(&t[..1])));
    match best {
        Some(c) => Word {
            text: c.to_string(),
            stem: words::stem(c),
        },
        None => w.clone(),
    }
}

fn needs_node(i: &Intent) -> bool {
    matches!(
        i,
        Intent::Why {
            node: Subject::Task,
            ..
        }
    )
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

fn subject_of(i: &Intent) -> Option<&Subject> {
    match i {
        Intent::Why { node, .. }
        | Intent::When { node, .. }
        | Intent::HowOften { node, .. }
        | Intent::WhatIf { node, .. } => Some(node).filter(|s| matches!(s, Subject::Nodes(..))),
        _ => None,
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
