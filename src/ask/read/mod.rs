//! A question → what it asks, read as an intent reader reads: its words
//! made standard (`words`), the moment it names taken out (`when`), the
//! nodes it names found as spans against this tree's vocabulary
//! (`mentions`), then what is asked, from the words that are left (cue
//! words, negation, "instead of"), with a confidence. The order of the
//! parts, imperatives ("explain", "tell me") and filler change nothing.

pub mod mentions;
pub mod when;
pub mod words;

use super::parse::{Event, Intent, Subject, Which};
use crate::explain::{Question, RunQuestion, TreeQuestion};
use crate::model::{Kind, Tree, Uid};
pub use mentions::{Mention, Vocabulary};
pub use when::{ordinal_word, When};
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
    ];
    WORLD.contains(&word)
}

/// "Why did it move right instead of up": a contrast whose second part
/// leaves out the verb the first has. Where nothing after "instead of" or
/// "rather than" names a node, the first mention's first word and the
/// words after are looked up together ("move up").
fn elided_foil(
    vocabulary: &mentions::Vocabulary,
    tree: &Tree,
    q: &[Word],
    nodes: &[Mention],
) -> Option<Mention> {
    let after = (0..q.len().saturating_sub(1)).find_map(|i| {
        let pair = (q[i].text.as_str(), q[i + 1].text.as_str());
        matches!(pair, ("instead", "of") | ("rather", "than")).then_some(i + 2)
    })?;
    let [fact] = nodes else { return None };
    if fact.end > after || fact.end - fact.start < 2 || after >= q.len() {
        return None;
    }
    let rest = &q[after..q.len().min(after + 4)];
    let words: Vec<Word> = std::iter::once(q[fact.start].clone())
        .chain(rest.iter().cloned())
        .collect();
    let found = vocabulary
        .mentions(tree, &words, &asks)
        .into_iter()
        .find(|m| m.start == 0 && m.end >= 2 && !m.weak && m.uids != fact.uids)?;
    let end = after + found.end - 1;
    Some(Mention {
        start: after,
        end,
        uids: found.uids,
        score: found.score,
        weak: false,
        phrase: q[after..end]
            .iter()
            .map(|w| w.text.as_str())
            .collect::<Vec<_>>()
            .join(" "),
    })
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
    let whole = read_one(vocabulary, tree, text);
    if whole.as_ref().is_some_and(|r| r.confidence >= SURE) {
        return whole;
    }
    let asked = questions_in(text)
        .into_iter()
        .filter_map(|q| read_one(vocabulary, tree, q))
        .reduce(|a, b| if b.confidence > a.confidence { b } else { a });
    match (whole, asked) {
        (Some(w), Some(a)) if a.confidence <= w.confidence => Some(w),
        // The moment the story told ("… returned FAILURE at tick 10. Why
        // did look at chuck fail there?"), where the question says none.
        (Some(w), Some(mut a)) => {
            a.when = a.when.or(w.when);
            Some(a)
        }
        (w, a) => a.or(w),
    }
}

/// The questions a text of several sentences asks: each sentence that
/// ends in "?", and what follows a colon ("I need the exact point in the
/// run: when did look at chuck fail?"). None for a text of one sentence.
fn questions_in(text: &str) -> Vec<&str> {
    let mut cuts = vec![0];
    let b = text.as_bytes();
    for i in 0..b.len().saturating_sub(1) {
        if matches!(b[i], b'.' | b'?' | b'!' | b':') && b[i + 1].is_ascii_whitespace() {
            cuts.push(i + 1);
        }
    }
    cuts.push(text.len());
    if cuts.len() <= 2 {
        return Vec::new();
    }
    cuts.windows(2)
        .map(|w| text[w[0]..w[1]].trim())
        .filter(|s| s.ends_with('?'))
        .collect()
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
    let text = paths_as_uids(tree, text);
    let text = states_as_outcomes(tree, &text);
    let q = words::words(&text);
    if q.is_empty() {
        return None;
    }
    let mut s = Sentence {
        q: &q,
        tree_words: vocabulary.stems(),
        used: vec![false; q.len()],
        nodes: Vec::new(),
    };
    let mut when = when::find(&q).map(|(w, used)| {
        for i in used {
            if i < s.used.len() {
                s.used[i] = true;
            }
        }
        w
    });
    // "Right now", "right after": "right" says when, it names no move.
    for i in 0..q.len().saturating_sub(1) {
        if q[i].text == "right"
            && ["now", "away", "after", "before", "then", "there", "here"]
                .contains(&q[i + 1].text.as_str())
        {
            s.used[i] = true;
        }
    }
    // "#18": a uid, as everywhere in btx.
    for (i, w) in q.iter().enumerate() {
        if s.used[i] {
            continue;
        }
        if let Some(uid) = w.text.strip_prefix('#').and_then(|n| n.parse::<Uid>().ok()) {
            if tree.get(uid).is_some() {
                s.nodes.push(Mention {
                    start: i,
                    end: i + 1,
                    uids: vec![uid],
                    score: 1.0,
                    weak: false,
                    phrase: w.text.clone(),
                });
                s.used[i] = true;
            }
        }
    }
    let mut mentions = vocabulary.mentions(tree, &free_words(&q, &s.used), &asks);
    // "What were you doing just before look at chuck failed?": the clause
    // says when; what is asked is the rest.
    if when.is_none() {
        if let Some((w, used)) = failure_clause(tree, &q, &s.used, &mentions) {
            when = Some(w);
            for i in used {
                s.used[i] = true;
            }
            mentions.retain(|m| !(m.start..m.end).any(|i| s.used[i]));
        }
    }
    for m in mentions {
        s.nodes.push(m);
    }
    s.nodes.sort_by_key(|m| m.start);
    s.nodes = scoped(tree, &q, std::mem::take(&mut s.nodes));
    s.nodes = governing_verbs_dropped(&q, std::mem::take(&mut s.nodes));
    if let Some(m) = elided_foil(vocabulary, tree, &q, &s.nodes) {
        s.nodes.push(m);
    }
    // Typos in the words that ask ("wen", "frist", "fial"), now that the
    // tree's names have been found as they were written.
    let mut in_mention = vec![false; q.len()];
    for m in &s.nodes {
        for f in &mut in_mention[m.start..m.end] {
            *f = true;
        }
    }
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
    let q = &q[..];
    // Weak mentions stay words unless the question names no other node
    // and asks about one.
    let strong: Vec<Mention> = s.nodes.iter().filter(|m| !m.weak).cloned().collect();
    // "What should I set num_attempts to?", "should I use py_trees?":
    // advice, which no run holds.
    let advice = q
        .windows(2)
        .any(|p| p[0].text == "should" && ["i", "we"].contains(&p[1].text.as_str()))
        || q.iter().any(|w| ADVICE.contains(&w.text.as_str()));
    if advice
        || strong.iter().all(|m| m.uids == [tree.root().uid])
            && q.iter()
                .enumerate()
                .any(|(i, w)| !in_mention[i] && about_the_world(&w.text))
    {
        return None;
    }
    let readings = {
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
        // "Why did it go to recoveries instead of trying the controller":
        // a contrast needs two nodes, and a node named by a word that also
        // asks ("recoveries") is the second.
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
        r
    };
    let mut readings = readings;
    readings.sort_by(|a, b| b.1.total_cmp(&a.1));
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
                before: matches!(when, Some(When::BeforeFailureOf(_))),
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
        before: false,
    })
}

/// Of nodes named alike, the one deepest in the tree.
fn deepest(tree: &Tree, uids: &[Uid]) -> Uid {
    uids.iter()
        .copied()
        .max_by_key(|&u| tree.ancestors(u).count())
        .unwrap_or(tree.root().uid)
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

/// "(just) before X failed", "right after the X failure", in a question
/// that asks what was done or running: the moment, and the words that say
/// it (the marker, the node's name, the failure).
fn failure_clause(
    tree: &Tree,
    q: &[Word],
    used: &[bool],
    mentions: &[Mention],
) -> Option<(When, Vec<usize>)> {
    let doing = q.iter().any(|w| {
        [
            "doing",
            "running",
            "subgoal",
            "goal",
            "happening",
            "active",
            "executing",
        ]
        .contains(&w.text.as_str())
    });
    if !doing {
        return None;
    }
    let k = q
        .iter()
        .enumerate()
        .position(|(i, w)| !used[i] && (w.text == "before" || w.text == "after"))?;
    // The name right after the marker (an article between), then the failure.
    let m = mentions
        .iter()
        .find(|m| m.start > k && q[k + 1..m.start].iter().all(|w| w.text == "the"))?;
    let end = (m.end..q.len().min(m.end + 2)).find(|&i| q[i].stem == "fail")?;
    let mut said: Vec<usize> = (k..=end).collect();
    for j in (0..k).rev() {
        if ["just", "right"].contains(&q[j].text.as_str()) {
            said.push(j);
        } else {
            break;
        }
    }
    // Of nodes named alike, the innermost: the one whose failure the
    // others pass on (the FollowPath action, not its RecoveryNode).
    let uid = deepest(tree, &m.uids);
    let w = if q[k].text == "before" {
        When::BeforeFailureOf(uid)
    } else {
        When::AfterFailureOf(uid)
    };
    Some((w, said))
}

/// "The retreat arm in reset arm", "the costmap clearing under the
/// recovery branch": a node named within another is one of those under
/// it, and the other names no node of its own.
fn scoped(tree: &Tree, q: &[Word], nodes: Vec<Mention>) -> Vec<Mention> {
    const WITHIN: &[&str] = &[
        "in", "under", "inside", "within", "of", "below", "beneath", "for", "from",
    ];
    let mut out: Vec<Mention> = Vec::with_capacity(nodes.len());
    for m in nodes {
        if let Some(a) = out.last_mut() {
            let between = &q[a.end..m.start];
            // "GoalUpdated fails in the RecoveryFallback": what it does
            // may come between the node and where it is.
            let deed = |w: &Word| {
                [
                    "fail", "succeed", "return", "run", "ran", "had", "has", "have", "been",
                ]
                .contains(&w.stem.as_str())
                    || ["false", "true", "fails", "failed", "succeeds", "succeeded"]
                        .contains(&w.text.as_str())
            };
            let within = !between.is_empty()
                && between.iter().any(|w| WITHIN.contains(&w.text.as_str()))
                && between.iter().all(|w| {
                    WITHIN.contains(&w.text.as_str())
                        || ["the", "a"].contains(&w.text.as_str())
                        || deed(w)
                });
            let told = between.iter().any(deed);
            let under: Vec<Uid> = a
                .uids
                .iter()
                .copied()
                .filter(|&u| m.uids.iter().any(|&p| p != u && tree.is_ancestor(p, u)))
                .collect();
            if within && !under.is_empty() && !m.weak && told {
                // The deed stays a word of the question; the place only
                // picks which of the nodes named alike.
                a.uids = under;
                continue;
            }
            if within && !under.is_empty() && !m.weak {
                a.uids = under;
                a.end = m.end;
                a.score = a.score.min(m.score);
                a.phrase = q[a.start..a.end]
                    .iter()
                    .map(|w| w.text.as_str())
                    .collect::<Vec<_>>()
                    .join(" ");
                continue;
            }
        }
        out.push(m);
    }
    out
}

/// "Instead of retrying FollowPath": a verb said of a name right after it
/// is what was done to that node, not a node of its own (a Retry).
fn governing_verbs_dropped(q: &[Word], nodes: Vec<Mention>) -> Vec<Mention> {
    let verb_before = |a: &Mention, b: &Mention| {
        a.end - a.start == 1
            && q[a.start].text.ends_with("ing")
            && a.end <= b.start
            && q[a.end..b.start]
                .iter()
                .all(|w| ["the", "a"].contains(&w.text.as_str()))
    };
    let keep: Vec<bool> = (0..nodes.len())
        .map(|i| !nodes.get(i + 1).is_some_and(|b| verb_before(&nodes[i], b)))
        .collect();
    nodes
        .into_iter()
        .zip(keep)
        .filter_map(|(m, k)| k.then_some(m))
        .collect()
}

/// A path ("go insert large gear/look at chuck") picks a node as it does
/// everywhere in btx: the longest that picks one is written as its #uid.
/// "Was the path clear?", "if the path had been clear", "why was the
/// battery not ok": a condition named as a thing and its state ("path
/// clear", "battery ok") said with a verb between them is the condition
/// succeeding, or failing with "not". The span is said as the reader reads
/// outcomes: "did path clear succeed", "path clear failed".
fn states_as_outcomes(tree: &Tree, text: &str) -> String {
    const BE: &[&str] = &[
        "is", "was", "were", "are", "be", "been", "being", "had", "has", "have", "isnt", "wasnt",
        "werent", "arent", "not", "never",
    ];
    const ASKING: &[&str] = &[
        "is", "was", "were", "are", "isnt", "wasnt", "werent", "arent",
    ];
    const NOT: &[&str] = &["not", "never", "isnt", "wasnt", "werent", "arent"];
    let toks: Vec<&str> = text.split_whitespace().collect();
    let low: Vec<String> = toks
        .iter()
        .map(|t| {
            t.chars()
                .filter(|c| c.is_alphanumeric())
                .collect::<String>()
                .to_lowercase()
        })
        .collect();
    let article = |i: usize| matches!(low[i].as_str(), "the" | "a" | "an" | "its");
    for n in tree.nodes.iter().filter(|n| n.kind == Kind::Condition) {
        let d = tree.description(n.uid);
        let name: Vec<String> = d
            .split(|c: char| c.is_whitespace() || c == '_')
            .filter(|w| !w.is_empty())
            .map(str::to_lowercase)
            .collect();
        if name.len() < 2 {
            continue;
        }
        let (thing, state) = name.split_at(name.len() - 1);
        for i in 0..low.len().saturating_sub(thing.len()) {
            if low[i..i + thing.len()] != *thing {
                continue;
            }
            let mut start = i;
            if start > 0 && article(start - 1) {
                start -= 1;
            }
            // "was the path (not) clear": asked, the verb first.
            let after = i + thing.len();
            let not_after = low.get(after).is_some_and(|w| NOT.contains(&w.as_str()));
            let end = after + usize::from(not_after);
            // Not "was path clear checked": the name, then a passive verb.
            let passive = low.get(end + 1).is_some_and(|w| w.ends_with("ed"));
            if start > 0
                && ASKING.contains(&low[start - 1].as_str())
                && low.get(end) == Some(&state[0])
                && !passive
            {
                let failed = not_after || NOT.contains(&low[start - 1].as_str());
                let said = format!("did {d} {}", if failed { "fail" } else { "succeed" });
                return spliced(&toks, start - 1, end + 1, &said);
            }
            // "the path had (not) been clear": told, the verb between.
            let mut j = after;
            let mut failed = false;
            while j < low.len() && BE.contains(&low[j].as_str()) {
                failed |= NOT.contains(&low[j].as_str());
                j += 1;
            }
            if j > after && low.get(j) == Some(&state[0]) {
                let said = format!("{d} {}", if failed { "failed" } else { "succeeded" });
                return spliced(&toks, start, j + 1, &said);
            }
        }
    }
    text.to_string()
}

/// `toks` with `toks[from..to]` said as `said`, the last token's closing
/// punctuation kept.
fn spliced(toks: &[&str], from: usize, to: usize, said: &str) -> String {
    let tail: String = toks[to - 1]
        .chars()
        .rev()
        .take_while(|c| !c.is_alphanumeric())
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    let mut out: Vec<String> = toks[..from].iter().map(|t| t.to_string()).collect();
    out.push(format!("{said}{tail}"));
    out.extend(toks[to..].iter().map(|t| t.to_string()));
    out.join(" ")
}

fn paths_as_uids(tree: &Tree, text: &str) -> String {
    if !text.contains('/') {
        return text.to_string();
    }
    let toks: Vec<&str> = text.split_whitespace().collect();
    for len in (1..=toks.len().min(12)).rev() {
        for i in 0..=toks.len() - len {
            let span = toks[i..i + len].join(" ");
            if !span.contains('/') {
                continue;
            }
            let bare = span.trim_matches(|c: char| "?!.,'\"".contains(c));
            if let Ok(uid) = crate::pick::pick(tree, bare) {
                let mut out: Vec<String> = toks[..i].iter().map(|t| t.to_string()).collect();
                out.push(format!("#{uid}"));
                out.extend(toks[i + len..].iter().map(|t| t.to_string()));
                return out.join(" ");
            }
        }
    }
    text.to_string()
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

fn subject_of(i: &Intent) -> Option<&Subject> {
    match i {
        Intent::Why { node, .. }
        | Intent::When { node, .. }
        | Intent::HowOften { node, .. }
        | Intent::WhatIf { node, .. } => Some(node).filter(|s| matches!(s, Subject::Nodes(..))),
        _ => None,
    }
}

/// The event a question's verbs name, if any, and whether they are negated.
/// "The retry gave up", "why did it stop trying to detect the chuck": a
/// loop that stopped trying failed.
fn gave_up(s: &Sentence) -> bool {
    let give = ["give", "gave", "giving", "gives", "given"];
    let stop = ["stop", "stopped", "stops", "stopping", "quit", "quits"];
    let trying = ["trying", "retrying", "attempting"];
    give.iter().any(|g| s.phrase(&[g, "up"]).is_some())
        || stop
            .iter()
            .any(|st| trying.iter().any(|t| s.phrase(&[st, t]).is_some()))
}

/// Of nodes a question says stopped trying, the loops that tried them: each
/// node's nearest retry above it (itself, if it is one); `None` where one
/// has none.
fn loops_of(tree: &Tree, us: &[Uid]) -> Option<Vec<Uid>> {
    let retries = |u: Uid| {
        let id = &tree.node(u).id;
        id.starts_with("Retry") || id == "RecoveryNode"
    };
    let mut out: Vec<Uid> = Vec::new();
    for &u in us {
        let l = std::iter::once(u)
            .chain(tree.ancestors(u))
            .find(|&a| retries(a))?;
        if !out.contains(&l) {
            out.push(l);
        }
    }
    Some(out)
}

fn event(s: &Sentence) -> (Option<Event>, bool) {
    // "Why did X succeed even though the controller failed": what is
    // granted after "even though" is not the event asked about.
    let concession = s.q.iter().enumerate().position(|(i, w)| {
        ["although", "despite", "though"].contains(&w.text.as_str())
            || w.text == "even" && s.q.get(i + 1).is_some_and(|n| n.text == "if")
    });
    if let Some(k) = concession.filter(|&k| k > 0) {
        let mut used = s.used.clone();
        for u in &mut used[k..] {
            *u = true;
        }
        let before = Sentence {
            q: s.q,
            tree_words: s.tree_words,
            used,
            nodes: Vec::new(),
        };
        return event_of(&before);
    }
    event_of(s)
}

fn event_of(s: &Sentence) -> (Option<Event>, bool) {
    let negated = s.has("not") || s.has("never") || s.has("no") && !s.has("one");
    let keep = s.has_stem(&["keep", "still", "stick", "forev", "hang", "slow"])
        || s.has("longer")
        || s.phrase(&["so", "long"]).is_some()
        || s.phrase(&["take", "long"]).is_some()
        || s.phrase(&["taking", "long"]).is_some()
        || s.phrase(&["took", "long"]).is_some()
        || s.phrase(&["long", "time"]).is_some();
    // "Had path clear stayed true": a condition's outcome said as its
    // value.
    let e = if gave_up(s)
        || s.has("false")
        || s.has_stem(&[
            "fail", "abort", "crash", "die", "error", "fault", "broke", "break",
        ]) {
        Some(Event::Fail)
    } else if s.has_stem(&["skip"]) {
        Some(Event::Skipped)
    } else if s.has_stem(&[
        "halt",
        "stop",
        "interrupt",
        "cancel",
        "preempt",
        "kill",
        "abandon",
    ]) {
        Some(Event::Halted)
    } else if keep {
        Some(Event::KeepRunning)
    } else if s.has_stem(&["succeed", "success", "pass", "manag", "ok"])
        || s.has("true")
        || s.has("successful")
        || s.has("successfully")
        || s.has("work")
        || s.has("worked")
        || s.has("works")
    {
        Some(Event::Succeed)
    } else if s.has_stem(&["finish", "end", "complet", "done"]) {
        Some(Event::Finish)
    } else if s.has_stem(&[
        "run", "start", "execut", "tick", "call", "trigger", "begin", "activ", "launch", "fire",
        "check", "kick", "invok", "attempt", "tri", "tried", "enter", "chose", "choos", "pick",
        "select", "use",
    ]) {
        Some(Event::Run)
    } else if s.has_stem(&["reach", "arriv"]) {
        // "When did it reach the goal": got there, said of the task.
        Some(Event::Succeed)
    } else {
        None
    };
    // "Why did it keep trying to detect the chuck?": it ran again and
    // again, which is starting, not one call running on.
    let retrying = s.has_stem(&["keep", "kept"])
        && s.free().any(|(_, w)| {
            ["trying", "retrying", "attempting", "restarting"].contains(&w.text.as_str())
        });
    let e = if retrying && e == Some(Event::KeepRunning) {
        Some(Event::Run)
    } else {
        e
    };
    let e = match (e, negated) {
        (Some(Event::Run), true) => Some(Event::NotRun),
        (Some(Event::Succeed), true) => Some(Event::Fail),
        (Some(Event::Fail), true) if s.has_stem(&["fail"]) => Some(Event::Succeed),
        (Some(Event::Finish), true) => Some(Event::KeepRunning),
        (None, true) => Some(Event::NotRun),
        (e, _) => e,
    };
    (e, negated)
}

/// The subject of a question about a node: the node named, "it"/"that",
/// or the task itself.
fn subject(s: &Sentence, root: Uid) -> Option<Subject> {
    // The task named ("nav2", "the patrol") yields to another node named.
    let m = s
        .nodes
        .iter()
        .find(|m| m.uids != [root])
        .or_else(|| s.nodes.first());
    if let Some(m) = m {
        return Some(Subject::Nodes(m.uids.clone(), m.phrase.clone()));
    }
    if s.has("it") || s.has("that") || s.has("this") || s.has("thing") {
        return Some(Subject::It);
    }
    if s.has("you")
        || s.has_stem(&[
            "robot", "task", "mission", "tree", "bt", "run", "root", "agent", "navig", "whole",
            "overal", "everyth", "i", "trip", "journey", "taxi", "car", "vehicl", "drone", "kit",
            "job",
        ])
    {
        return Some(Subject::Task);
    }
    None
}

/// What is asked, with a confidence for each reading that fits.
fn classify(s: &Sentence, tree: &Tree) -> Vec<(Intent, f32)> {
    let mut out: Vec<(Intent, f32)> = Vec::new();
    let node_score = s.nodes.iter().map(|m| m.score).fold(1.0f32, f32::min);
    let unexplained = unexplained(s);
    // How sure a reading is: the words it leaves unexplained count
    // against it, and so do loosely matched names where it rests on them.
    let words_sure = 0.93f32.powi(unexplained.min(6) as i32);
    let sure = |base: f32| base * node_score * words_sure;
    let sure_of_words = |base: f32| base * words_sure;
    let (ev, negated) = event(s);
    let first = s.first_free().unwrap_or("");
    let yes_no = [
        "did",
        "do",
        "does",
        "was",
        "were",
        "is",
        "are",
        "has",
        "have",
        "had",
        "any",
        "anything",
        "everything",
        "all",
        "were",
        "could",
        "you",
    ]
    .contains(&first);
    let root = tree.root().uid;
    // Nodes named other than the task itself ("nav2", "the patrol").
    let named: Vec<&Mention> = s.nodes.iter().filter(|m| m.uids != [root]).collect();
    let why = s.has("why")
        || s.has_stem(&["justifi", "justif"])
        || s.phrase(&["how", "come"]).is_some()
        || s.phrase(&["what", "caused"]).is_some()
        || s.phrase(&["what", "made"]).is_some()
        || s.has_stem(&["reason", "caus", "cause"])
        || (s.has("explain") && !s.has("how") && !s.nodes.is_empty() && ev.is_some());
    let what = s.has("what") || s.has("which") || IMPERATIVE.iter().any(|w| s.has(w));
    // "How much does it cost", "how much RAM": an amount, never the steps.
    let how = s.has("how") && s.phrase(&["how", "much"]).is_none();
    // "After it couldn't detect the chuck": not managing is failing.
    let could_not = s.phrase(&["could", "not"]).is_some()
        || s.phrase(&["can", "not"]).is_some()
        || s.phrase(&["was", "unable"]).is_some()
        || s.phrase(&["unable", "to"]).is_some();
    let break_down = s.phrase(&["break", "down"]).is_some();
    let problem = could_not
        || !break_down
            && s.has_stem(&[
                "wrong", "problem", "error", "issu", "fail", "broke", "break", "fault", "bad",
                "mess",
            ]);
    let fine = s.has_stem(&["ok", "fine", "good", "alright", "smooth", "normal"]);
    let doing_words = s.has("doing")
        || s.phrase(&["going", "on"]).is_some()
        || s.phrase(&["went", "on"]).is_some()
        || s.has_stem(&["busi", "busy", "work", "activ", "perform", "activ"])
        || s.phrase(&["up", "to"]).is_some()
        || s.has("activity");
    let now_words = s.has("now")
        || s.has("currently")
        || s.has("current")
        || s.phrase(&["this", "part"]).is_some()
        || s.has("moment")
        || s.has("working")
        || s.has("towards");
    let whole = s.has("whole")
        || s.has("end")
        || s.has("final")
        || s.has("mission")
        || s.has("big")
        || s.has("overall")
        || s.has("entire")
        || s.has("ultimate")
        || s.has("ultimately")
        || s.has("eventually")
        || s.has("main")
        || s.has("everything")
        || s.has("all");

    // "Which node failed?": what went wrong.
    if (s.has("which") || s.has("what"))
        && s.has_stem(&[
            "node", "step", "action", "part", "thing", "behavior", "leaf",
        ])
        && ev == Some(Event::Fail)
        && named.is_empty()
    {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            sure_of_words(0.93),
        ));
        return out;
    }
    // "Can you X?": the rest of the words are the behaviour.
    if let Some(x) = can_you(s, tree) {
        out.push((Intent::Fixed(Question::CanYou(x)), sure_of_words(0.95)));
        return out;
    }
    // "What if X fails?", "what would have happened if X had failed".
    let conditional = s.phrase(&["what", "if"]).is_some()
        || s.phrase(&["happen", "if"]).is_some()
        || s.phrase(&["happens", "if"]).is_some()
        || s.phrase(&["happened", "if"]).is_some()
        || s.phrase(&["do", "if"]).is_some()
        || s.has("suppose")
        || s.has("imagine")
        || s.has("hypothetically")
        || first == "if";
    if conditional {
        if let Some(node @ Subject::Nodes(..)) = subject(s, root) {
            let e = match ev {
                Some(Event::Succeed) => Event::Succeed,
                _ => Event::Fail,
            };
            out.push((Intent::WhatIf { node, event: e }, sure(0.92)));
            return out;
        }
    }
    // "Robot ok??", "something wrong?": a few words asking whether all is well.
    if s.q.len() <= 3 && (problem || fine) && named.is_empty() && !why && !what {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            sure_of_words(0.9),
        ));
        return out;
    }
    // "Did anything fail (while patrolling)?": yes or no, whatever is named.
    if yes_no
        && (s.has("anything") || s.has("something") || s.has("any"))
        && (problem || fine)
        && !why
        && !s.has_prefix(&["recover"])
    {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            sure_of_words(0.93),
        ));
        return out;
    }
    // Did the recovery work?
    let generic = |m: &Mention| {
        m.phrase.split_whitespace().all(|w| {
            [
                "the",
                "recovery",
                "recoveries",
                "retry",
                "retries",
                "fallback",
                "behaviors",
                "behaviours",
                "actions",
                "node",
            ]
            .contains(&w)
        })
    };
    let recovery_word = s.has_prefix(&["recover"]) || s.nodes.iter().any(generic);
    let retry_word = s.has_prefix(&["retr", "fallback"]);
    let fixed_it = s.has_stem(&["fix"]) && (s.has("it") || s.has("that") || s.has("things"));
    let on_track =
        s.phrase(&["on", "track"]).is_some() || s.phrase(&["back", "to", "normal"]).is_some();
    if !how
        && !why
        && (yes_no || s.has("manage") || s.has("managed") || first.starts_with("recover"))
        && (recovery_word || fixed_it || on_track || retry_word && named.iter().all(|m| generic(m)))
        && !matches!(ev, Some(Event::Halted | Event::Skipped | Event::NotRun))
        && (ev != Some(Event::Fail) || recovery_word)
    {
        out.push((Intent::Recovered, sure_of_words(0.93)));
        return out;
    }
    let often = s.phrase(&["how", "often"]).is_some()
        || s.phrase(&["how", "many"]).is_some()
        || s.phrase(&["how", "frequently"]).is_some()
        || s.phrase(&["number", "of"]).is_some()
        || s.has_stem(&["count"]);
    if often {
        if let Some(node) = subject(s, root) {
            let e = match ev {
                Some(Event::NotRun) | Some(Event::Skipped) | None => Event::Run,
                Some(e) => e,
            };
            out.push((Intent::HowOften { node, event: e }, sure(0.95)));
            return out;
        }
    }
    let every_time = (s.has("every") || s.has("each") || s.has("all"))
        && (s.has("time") || s.has("times"))
        && !why;
    let when_q = every_time
        || s.has("when")
        || s.phrase(&["what", "time"]).is_some()
        || s.phrase(&["which", "tick"]).is_some()
        || s.phrase(&["what", "tick"]).is_some()
        || s.phrase(&["which", "step"]).is_some()
        || s.phrase(&["what", "step"]).is_some()
        || s.phrase(&["at", "what", "point"]).is_some()
        // "list the ticks where it failed".
        || (s.has("tick") || s.has("ticks")) && ["list", "where", "show", "give"].iter().any(|w| s.has(w));
    let after_failure = (s.has("after") || s.has("when") || s.has("once"))
        && (problem || s.has_stem(&["block", "stuck"]))
        && (s.phrase(&["did", "it", "do"]).is_some()
            // "what did the fallback do when …".
            || s.has("what") && s.has("did") && s.has("do")
            || s.phrase(&["did", "you", "do"]).is_some()
            || s.phrase(&["was", "done"]).is_some()
            || s.phrase(&["did", "the", "robot", "do"]).is_some());
    // "How'd it handle it when it couldn't look at the chuck": the "when"
    // says which failure, the question is how it was handled.
    let how_handled =
        s.has("how") && s.has_stem(&["handl", "deal", "dealt", "respond", "react", "cope"]);
    if when_q && !why && !after_failure && !how_handled {
        let node = subject(s, root);
        let named_or_event = matches!(node, Some(Subject::Nodes(..))) || ev.is_some();
        if let (Some(node), true) = (node, named_or_event) {
            let which = if s.has("first") || s.has("1st") || s.has("initially") {
                Which::First
            } else if s.has("last") || s.has("final") || s.has("finally") || s.has("latest") {
                Which::Last
            } else {
                Which::Every
            };
            let e = match ev {
                Some(Event::NotRun) | Some(Event::Skipped) | None => Event::Run,
                Some(e) => e,
            };
            out.push((
                Intent::When {
                    node,
                    event: e,
                    which,
                },
                sure(0.95),
            ));
            return out;
        }
    }
    // "What's the purpose of the thing you're doing now?", "what is L2
    // for?", "whats the point of driving right now?": why it does what it
    // does (the task's purpose is its goal, asked below).
    let purpose = s.has_stem(&["purpos", "reason"])
        || s.phrase(&["point", "of"]).is_some()
        || what && s.q.last().is_some_and(|w| w.text == "for");
    let current = doing_words || s.has("now") || s.has("current") || s.has_stem(&["action"]);
    if purpose && !why && matches!(ev, None | Some(Event::Run)) && (current || !named.is_empty()) {
        out.push((
            Intent::Fixed(Question::Tree(TreeQuestion::Why)),
            sure_of_words(0.9),
        ));
        return out;
    }
    // "Why look around?": a bare verb after "why" asks why it does it.
    let bare = s.q.first().is_some_and(|w| w.text == "why")
        && s.q
            .get(1)
            .is_some_and(|w| !NOT_A_VERB.contains(&w.text.as_str()));
    let contrast = s.has("instead") || s.phrase(&["rather", "than"]).is_some();
    if why && bare && !contrast && matches!(ev, None | Some(Event::Run)) && !named.is_empty() {
        out.push((
            Intent::Fixed(Question::Tree(TreeQuestion::Why)),
            sure_of_words(0.85),
        ));
        return out;
    }
    if why {
        // "Why didn't it X after Y failed": a why about X; the clause after
        // "after", "when" or "once" only says when.
        if named.len() >= 2 {
            let marker = s.q[named[0].end..named[1].start]
                .iter()
                .position(|w| {
                    ["after", "when", "once", "while", "since", "because"]
                        .contains(&w.text.as_str())
                })
                .map(|i| i + named[0].end);
            if let Some(cut) = marker {
                let mut main = Sentence {
                    q: s.q,
                    tree_words: s.tree_words,
                    used: s.used.clone(),
                    nodes: s.nodes.iter().filter(|m| m.end <= cut).cloned().collect(),
                };
                for u in &mut main.used[cut..] {
                    *u = true;
                }
                return classify(&main, tree);
            }
        }
        // "Why X and not Y", "why X instead of Y": two nodes.
        let not_between = named.len() >= 2
            && s.q[named[0].end..named[1].start]
                .iter()
                .any(|w| w.text == "not" || w.text == "never");
        let contrast = s.phrase(&["instead", "of"]).is_some()
            || s.phrase(&["rather", "than"]).is_some()
            || not_between
            || s.has("over")
            || s.has("vs")
            || s.has("versus");
        // A node is never contrasted with itself ("why was the path not
        // clear" names path clear twice).
        if named.len() >= 2 && contrast && named[0].uids != named[1].uids {
            let done = Subject::Nodes(named[0].uids.clone(), named[0].phrase.clone());
            let instead = Subject::Nodes(named[1].uids.clone(), named[1].phrase.clone());
            let (done, instead) = if negated_first(s, named[0], named[1]) {
                (instead, done)
            } else {
                (done, instead)
            };
            out.push((Intent::WhyNot { done, instead }, sure(0.93)));
            return out;
        }
        // "Why is FollowPath still running?": a node named as running on.
        if s.has("still") && !named.is_empty() && progressive(s) {
            if let Some(node) = subject(s, root) {
                out.push((
                    Intent::Why {
                        node,
                        event: Event::KeepRunning,
                        foil: None,
                    },
                    sure(0.9),
                ));
                return out;
            }
        }
        // "Why is it looking at the chuck?", "why drop the passenger off
        // now?": why it is doing what it does.
        let now = s.has("now") && !["did", "was", "were", "had"].iter().any(|w| s.has(w));
        if (progressive(s) || now)
            && matches!(ev, None | Some(Event::Run) | Some(Event::KeepRunning))
        {
            out.push((
                Intent::Fixed(Question::Tree(TreeQuestion::Why)),
                sure_of_words(0.93),
            ));
            return out;
        }
        if let Some(node) = subject(s, root) {
            let doing_this =
                matches!(node, Subject::It) && (s.has("doing") || s.has("this") && ev.is_none());
            if doing_this && ev.is_none() {
                out.push((
                    Intent::Fixed(Question::Tree(TreeQuestion::Why)),
                    sure_of_words(0.95),
                ));
                return out;
            }
            let node = match node {
                Subject::Nodes(us, p) if gave_up(s) => match loops_of(tree, &us) {
                    Some(loops) => Subject::Nodes(loops, p),
                    None => Subject::Nodes(us, p),
                },
                other => other,
            };
            let foil = foil(s);
            let e = match ev {
                Some(e) => e,
                None if negated => Event::NotRun,
                None => Event::Run,
            };
            let base = if ev.is_some() || matches!(node, Subject::Nodes(..)) {
                0.95
            } else {
                0.6
            };
            out.push((
                Intent::Why {
                    node,
                    event: e,
                    foil,
                },
                sure(base),
            ));
            if matches!(e, Event::Fail) {
                out.push((
                    Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
                    0.3,
                ));
            }
            return out;
        }
        if s.has("doing") || s.has("this") || s.has("that") {
            out.push((
                Intent::Fixed(Question::Tree(TreeQuestion::Why)),
                sure_of_words(0.9),
            ));
            return out;
        }
        return out;
    }
    // How was it handled?
    let handle = s.has_stem(&[
        "handl", "deal", "dealt", "respond", "react", "cope", "mitig", "recov", "recoveri", "fix",
        "fixed", "past", "overcom", "surviv",
    ]) || s.has_prefix(&["recover", "handl"]);
    if (how && (handle || problem && !s.has("often") && !s.has("many")))
        || after_failure
        || s.phrase(&["do", "about"]).is_some()
        || s.phrase(&["did", "about"]).is_some()
        || s.phrase(&["done", "about"]).is_some()
        || (what && s.has_prefix(&["recover"]) && named.is_empty())
    {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::Handled)),
            sure_of_words(0.93),
        ));
        return out;
    }
    // What next?
    let next = s.has("next")
        || s.phrase(&["going", "to", "do"]).is_some()
        || s.phrase(&["will", "you", "do"]).is_some()
        || s.phrase(&["will", "it", "do"]).is_some()
        || s.phrase(&["will", "the", "robot", "do"]).is_some()
        || s.phrase(&["comes", "after"]).is_some()
        || s.phrase(&["after", "this"]).is_some()
        || s.phrase(&["after", "that"]).is_some()
        || s.has("afterwards")
        || s.has("upcoming")
        || s.phrase(&["from", "here"]).is_some() && s.has("go")
        || (s.has("after") && (s.has("will") || s.has("happens")));
    // "What happens now?", "and now what?", "what will the tree do now?",
    // "what do you plan to do after walking?".
    let past = ["did", "was", "were", "had", "happened"]
        .iter()
        .any(|w| s.has(w));
    let next = next
        || !past
            && (s.phrase(&["what", "happens"]).is_some()
                && (s.has("now") || s.has("then") || s.has("after"))
                || s.q.len() >= 2
                    && s.q[s.q.len() - 2..]
                        .iter()
                        .map(|w| w.text.as_str())
                        .eq(["now", "what"])
                || s.has("will") && s.has("do") && what
                || s.phrase(&["plan", "to", "do"]).is_some());
    if next {
        out.push((Intent::Next, sure_of_words(0.93)));
        return out;
    }
    let asked_when = when::find(s.q).map(|(w, _)| w);
    if problem && (what || s.empty() || s.has("where")) && !yes_no {
        if !named.is_empty() && ev == Some(Event::Fail) && asked_when.is_none() {
            // "what made look at chuck fail", "tell me why X failed".
            let node = subject(s, root).unwrap_or(Subject::Task);
            out.push((
                Intent::Why {
                    node,
                    event: Event::Fail,
                    foil: None,
                },
                sure(0.85),
            ));
            return out;
        }
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            sure_of_words(0.95),
        ));
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            0.3,
        ));
        return out;
    }
    if (yes_no || s.has("any")) && (problem || fine) && named.is_empty() {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            sure_of_words(0.93),
        ));
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            0.3,
        ));
        return out;
    }
    // A tick's transitions: "describe tick 9", "what happened in the last tick".
    let this_tick =
        s.phrase(&["this", "tick"]).is_some() || s.phrase(&["current", "tick"]).is_some();
    if asked_when.is_some() || this_tick {
        let n = match asked_when {
            Some(When::Tick(n) | When::Step(n, _)) => n,
            _ => 0,
        };
        let asks_tick = s.has_stem(&[
            "happen", "chang", "occur", "describ", "summar", "show", "went", "transit", "detail",
        ]) || break_down
            || s.empty()
            || (what && !doing_words && !s.has_stem(&["run", "goal", "subgoal"]));
        let walk = s.phrase(&["walk", "me", "through"]).is_some()
            || s.phrase(&["walk", "through"]).is_some()
            || s.phrase(&["went", "on"]).is_some()
            || break_down;
        let asks_tick = asks_tick || walk;
        if asks_tick && named.is_empty() && (!doing_words || walk) {
            out.push((Intent::Tick(n), sure_of_words(0.95)));
            return out;
        }
    }
    // "Did the robot still make it to the goal after the failures?":
    // whether the run came through, not what the goal is.
    let reached = s.has_stem(&["reach", "arriv"])
        || s.phrase(&["make", "it"]).is_some()
        || s.phrase(&["get", "to"]).is_some()
        || s.phrase(&["got", "to"]).is_some();
    if yes_no && reached && s.has_stem(&["goal", "destin", "target"]) && named.is_empty() {
        out.push((Intent::Recovered, sure_of_words(0.9)));
        return out;
    }
    // "At which tick did the goal get reached?": when the task succeeded.
    if when_q && reached && s.has_stem(&["goal", "destin", "target"]) && named.is_empty() {
        out.push((
            Intent::When {
                node: Subject::Task,
                event: Event::Succeed,
                which: Which::Every,
            },
            sure_of_words(0.85),
        ));
        return out;
    }
    // "Did the task succeed?", "did the robot finish the job?": whether
    // the run came through, asked of the task, not what its goal is.
    let outcome = matches!(ev, Some(Event::Succeed | Event::Fail | Event::Finish));
    if yes_no
        && outcome
        && !why
        && named.is_empty()
        && s.has_stem(&["task", "mission", "job", "run"])
    {
        out.push((
            Intent::When {
                node: Subject::Task,
                event: ev.unwrap_or(Event::Finish),
                which: Which::Every,
            },
            sure_of_words(0.9),
        ));
        return out;
    }
    // "The immediate objective", "what part of the mission": the part.
    let part = s.has_stem(&["immedi"]) || s.phrase(&["part", "of"]).is_some();
    let subgoal = s.has_stem(&["subgoal", "subtask", "milestone"])
        || part && s.has_stem(&["goal", "object", "mission", "task", "job", "aim"])
        || s.phrase(&["sub", "goal"]).is_some()
        || s.phrase(&["sub", "task"]).is_some()
        || s.phrase(&["intermediate", "goal"]).is_some()
        || s.phrase(&["current", "step"]).is_some();
    let goal = s.has_stem(&[
        "goal", "object", "mission", "aim", "purpos", "task", "intent", "job", "target",
    ]) || s.phrase(&["trying", "to"]).is_some()
        || s.phrase(&["try", "to"]).is_some()
        || s.phrase(&["supposed", "to"]).is_some()
        || s.phrase(&["working", "towards"]).is_some()
        || s.phrase(&["working", "toward"]).is_some()
        || s.phrase(&["get", "done"]).is_some()
        || s.has_stem(&["achiev", "accomplish"]);
    let steps = !s.has("doing")
        && s.has_stem(&["step", "plan", "procedur", "strategi", "approach", "outlin"])
        || s.phrase(&["walk", "me", "through"]).is_some()
        || (how
            && s.has_stem(&[
                "do",
                "get",
                "complet",
                "go",
                "make",
                "finish",
                "build",
                "work",
                "achiev",
                "accomplish",
                "reach",
            ]));
    if how || (steps && (what || s.empty() || first == "outline" || first == "walk")) {
        let goal_named = s.nodes.iter().any(|m| m.uids == [root]);
        if subgoal && (steps || how) {
            out.push((
                Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)),
                sure_of_words(0.93),
            ));
            return out;
        }
        if (goal || whole || goal_named) && (steps || how) {
            out.push((
                Intent::Fixed(Question::Tree(TreeQuestion::HowGoal)),
                sure_of_words(0.93),
            ));
            return out;
        }
        if steps {
            out.push((
                Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)),
                sure_of_words(0.85),
            ));
            out.push((Intent::Fixed(Question::Tree(TreeQuestion::HowGoal)), 0.4));
            return out;
        }
    }
    if subgoal {
        out.push((
            Intent::Fixed(Question::Tree(TreeQuestion::Subgoal)),
            sure_of_words(0.95),
        ));
        return out;
    }
    if goal && !s.has("doing") {
        let trying = s.phrase(&["trying", "to"]).is_some() || s.phrase(&["try", "to"]).is_some();
        let named_goal = s.has_stem(&["goal", "object", "mission", "purpos", "job", "target"]);
        // "What's the goal here?" names the goal; "what is it trying to get
        // done here" the part it is in.
        let here = now_words
            || (s.has("here") || s.phrase(&["this", "point"]).is_some()) && !s.has_stem(&["goal"]);
        // "What is it trying to achieve?", with neither "now" nor "in the
        // end": the whole task's goal, or that of the part it is in. Both
        // are read, and asked back.
        if trying && !named_goal && !here && !whole {
            out.push((
                Intent::Fixed(Question::Tree(TreeQuestion::Goal)),
                sure_of_words(0.65),
            ));
            out.push((Intent::Fixed(Question::Tree(TreeQuestion::Subgoal)), 0.6));
            return out;
        }
        let q = if here && !whole {
            TreeQuestion::Subgoal
        } else {
            TreeQuestion::Goal
        };
        // "Navigation fails even though the robot reaches the goal", "the
        // GoalUpdated condition cannot halt …": a goal said beside an event
        // or another node is likely not the question of what the goal is.
        let beside = !named.is_empty()
            || when_q
            || s.has_stem(&["fail", "reach", "arriv", "halt", "abort", "cancel"]);
        let base = if beside { 0.6 } else { 0.9 };
        out.push((Intent::Fixed(Question::Tree(q)), sure_of_words(base)));
        if beside && problem {
            out.push((
                Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
                0.5,
            ));
        }
        if beside {
            let other = if q == TreeQuestion::Goal {
                TreeQuestion::HowGoal
            } else {
                TreeQuestion::HowSubgoal
            };
            out.push((Intent::Fixed(Question::Tree(other)), 0.4));
        }
        return out;
    }
    let doing = doing_words
        || s.has_stem(&["happen", "run", "execut", "act", "action", "behavior"])
        || s.has_prefix(&["doin"]);
    if doing && (what || s.empty() || first == "current") && named.is_empty() {
        out.push((
            Intent::Fixed(Question::Tree(TreeQuestion::Doing)),
            sure_of_words(0.93),
        ));
        return out;
    }
    // "Did the planner run?", "has follow path failed": whether, and how often.
    if let (Some(m), Some(e), true) = (named.first(), ev, yes_no) {
        let node = Subject::Nodes(m.uids.clone(), m.phrase.clone());
        let e = if e == Event::NotRun { Event::Run } else { e };
        out.push((
            Intent::HowOften {
                node: node.clone(),
                event: e,
            },
            sure(0.85),
        ));
        out.push((
            Intent::When {
                node,
                event: e,
                which: Which::Every,
            },
            0.5,
        ));
        return out;
    }
    // A node and an event with no question word: "look at chuck failed?".
    if let (Some(m), Some(e)) = (s.nodes.first(), ev) {
        let node = Subject::Nodes(m.uids.clone(), m.phrase.clone());
        out.push((
            Intent::Why {
                node: node.clone(),
                event: e,
                foil: None,
            },
            sure(0.55),
        ));
        out.push((
            Intent::When {
                node: node.clone(),
                event: e,
                which: Which::Every,
            },
            0.45,
        ));
        out.push((Intent::HowOften { node, event: e }, 0.4));
        return out;
    }
    out
}

/// "why is it looking at the chuck", "why does it keep driving": asked
/// of what it is doing now, in the present progressive.
fn progressive(s: &Sentence) -> bool {
    if s.has("long") {
        return false;
    }
    let be = s.q.iter().enumerate().position(|(i, w)| {
        ["is", "are", "am", "was", "were", "keeps", "still"].contains(&w.text.as_str())
            || w.text == "keep" && i > 0 && ["does", "do"].contains(&s.q[i - 1].text.as_str())
            || w.text == "keep" && s.q.iter().any(|w| w.text == "does")
    });
    let Some(be) = be else {
        return false;
    };
    s.q[be + 1..].iter().any(|w| {
        w.text.len() > 4 && w.text.ends_with("ing") && w.text != "something"
            // "convertng": the i dropped.
            || w.text.len() > 6 && w.text.ends_with("ng") && !w.text.ends_with("ong")
            || ["active", "busy"].contains(&w.text.as_str())
            // "computin": the g dropped from a verb of the tree's.
            || w.text.len() > 4
                && w.text.ends_with("in")
                && s.tree_words.contains(&words::stem(&format!("{}g", w.text)))
    })
}

/// "why not X but Y": the node after a negation was the one not done.
fn negated_first(s: &Sentence, a: &Mention, b: &Mention) -> bool {
    s.q[..a.start]
        .iter()
        .any(|w| w.text == "not" || w.text == "never")
        && !s.q[a.end..b.start]
            .iter()
            .any(|w| w.text == "not" || w.text == "instead")
}

/// "X failed instead of succeeding": the outcome the person expected.
fn foil(s: &Sentence) -> Option<Event> {
    let at = s
        .phrase(&["instead", "of"])
        .or_else(|| s.phrase(&["rather", "than"]))
        .or_else(|| s.phrase(&["and", "not"]))
        .or_else(|| s.phrase(&["but", "not"]))?;
    let after: Vec<&Word> = s.q[at + 2..].iter().collect();
    after.iter().find_map(|w| match w.stem.as_str() {
        "succeed" | "pass" | "work" => Some(Event::Succeed),
        "fail" => Some(Event::Fail),
        "run" | "start" => Some(Event::Run),
        _ => None,
    })
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
];

/// "Could you confirm how many times it failed", "can you check when
/// it stopped": a question put politely, not whether the robot can.
pub fn wraps_a_question(after: &[&str]) -> bool {
    const REPORT: &[&str] = &[
        "confirm", "check", "verify", "find", "figure", "see", "look", "work", "let", "count",
        "tell", "say", "show",
    ];
    let Some((first, rest)) = after.split_first() else {
        return false;
    };
    REPORT.contains(first)
        && (rest
            .iter()
            .any(|w| ["why", "when", "what", "which", "where"].contains(w))
            || rest
                .windows(2)
                .any(|p| p[0] == "how" && ["many", "often", "much", "long"].contains(&p[1])))
}

/// The words of "Can you X?" after its opening, or `None`.
fn can_you(s: &Sentence, tree: &Tree) -> Option<String> {
    let free: Vec<(usize, &Word)> =
        s.q.iter()
            .enumerate()
            .filter(|(i, w)| {
                // "to" and "know" lead other questions ("I want to know"),
                // and are words of the openings here ("able to").
                (!LEAD.contains(&w.text.as_str()) || ["to", "know"].contains(&w.text.as_str()))
                    && !["the", "a", "an", "this", "that"].contains(&w.text.as_str())
                    // "robot, can you pick a screw": the robot addressed.
                    && (*i != 0 || !["robot", "bot"].contains(&w.text.as_str()))
            })
            .collect();
    let texts: Vec<&str> = free.iter().map(|(_, w)| w.text.as_str()).collect();
    let openings: &[&[&str]] = &[
        &["can", "you"],
        &["could", "you"],
        &["can", "it"],
        &["could", "it"],
        &["are", "you", "able", "to"],
        &["is", "it", "able", "to"],
        &["are", "you", "able"],
        &["can", "robot"],
        &["could", "robot"],
        &["is", "robot", "able", "to"],
        &["are", "you", "capable", "of"],
        &["is", "robot", "capable", "of"],
        &["is", "it", "capable", "of"],
        &["do", "you", "know", "how", "to"],
        &["would", "you", "be", "able", "to"],
        &["will", "you", "be", "able", "to"],
        &["does", "robot", "know", "how", "to"],
    ];
    // "Is clearing the local costmap something you can do?", "is detecting
    // screws something this robot can do?".
    if texts.first() == Some(&"is")
        && texts.ends_with(&["can", "do"])
        && texts.contains(&"something")
    {
        let from = free.get(1)?.0;
        let m = s.nodes.iter().find(|m| m.start >= from)?;
        return Some(tree.description(m.uids[0]).to_string());
    }
    // "Is the taxi able to …", "is this robot capable of …": the robot
    // named any way, in four words.
    let open = match openings.iter().find(|o| texts.starts_with(o)) {
        Some(o) => o.len(),
        None if texts.len() > 4
            && ["is", "are"].contains(&texts[0])
            && (texts[2..4] == ["able", "to"] || texts[2..4] == ["capable", "of"]) =>
        {
            4
        }
        None => return None,
    };
    // "can you tell me why …" asks what follows.
    let next = texts.get(open).copied().unwrap_or("");
    if wraps_a_question(&texts[open.min(texts.len())..])
        || IMPERATIVE.contains(&next)
        || next == "justify"
        || ["still", "do"].contains(&next) && texts.len() == open + 1
    {
        return None;
    }
    let from = free.get(open)?.0;
    if let Some(m) = s.nodes.iter().find(|m| m.start >= from) {
        return Some(tree.description(m.uids[0]).to_string());
    }
    let rest: Vec<&str> = s.q[from..]
        .iter()
        .map(|w| w.text.as_str())
        .filter(|w| !["the", "a", "an", "please", "again"].contains(w))
        .collect();
    (!rest.is_empty()).then(|| rest.join(" "))
}

/// Content words the reading leaves unexplained.
fn unexplained(s: &Sentence) -> usize {
    const KNOWN: &[&str] = &[
        "what",
        "why",
        "how",
        "when",
        "which",
        "where",
        "who",
        "come",
        "fail",
        "failed",
        "failing",
        "failure",
        "succeed",
        "succeeded",
        "success",
        "run",
        "ran",
        "running",
        "start",
        "started",
        "doing",
        "goal",
        "subgoal",
        "next",
        "wrong",
        "problem",
        "problems",
        "error",
        "errors",
        "recover",
        "recovered",
        "recovery",
        "handle",
        "handled",
        "not",
        "never",
        "instead",
        "rather",
        "than",
        "if",
        "often",
        "many",
        "times",
        "tick",
        "step",
        "steps",
        "achieve",
        "happening",
        "happen",
        "happens",
        "halted",
        "stopped",
        "stop",
        "give",
        "gave",
        "giving",
        "gives",
        "quit",
        "retrying",
        "attempting",
        "skipped",
        "finish",
        "finished",
        "work",
        "worked",
        "going",
        "doing",
        "busy",
        "working",
        "trying",
        "mission",
        "objective",
        "task",
        "retry",
        "fallback",
        "first",
        "last",
        "deal",
        "dealt",
        "manage",
        "managed",
        "cause",
        "caused",
        "reason",
        "made",
        "make",
        "able",
        "explain",
        "tell",
        "show",
        "describe",
        "no",
        "ok",
        "fine",
        "executing",
        "active",
        "why",
        "so",
        "long",
        "keep",
        "kept",
        "issue",
        "issues",
        "broke",
        "broken",
        "wrong",
        "purpose",
        "aim",
        "plan",
        "happened",
        "occurred",
        "changed",
        "next",
        "after",
        "before",
        "upcoming",
    ];
    s.free()
        .filter(|(_, w)| {
            let t = w.text.as_str();
            !FILLER.contains(&t)
                && !IMPERATIVE.contains(&t)
                && !KNOWN.contains(&t)
                && !asks(&w.stem)
                && !s.tree_words.contains(&w.stem)
                && t.len() > 2
        })
        .count()
}

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
        Intent::WhatIf { node, event } => format!("What if {} {}s?", who(node), verb(*event)),
        Intent::Recovered => "Did the recovery work?".into(),
    }
}
