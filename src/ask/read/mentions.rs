//! Words → the nodes they name, found as spans of the question before
//! anything else is read. A node is known by its name, its ID, the values
//! of its ports (a service name, a topic), and for Nav2 trees by the
//! field's words (`model::nav2_words`). A span matches however its writer
//! spelled the name: with articles, joined, hyphenated, in another word
//! form, with a small typo, or half of it; a kind word beside it ("the
//! FollowPath action") picks among nodes that share the name.

use super::words::{self, name_words, split_name, Word};
use crate::model::nav2_words::{self, Target};
use crate::model::{Kind, Tree, Uid};
use rustc_hash::FxHashSet;

/// Where a node's words come from; a name counts more than a port value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    Name,
    Id,
    Port,
    Field,
}

#[derive(Debug)]
struct Entry {
    uid: Uid,
    /// Stems of its words, articles left out.
    stems: Vec<String>,
    /// Its words as written, joined with nothing between ("lookatchuck").
    joined: String,
    source: Source,
    /// An ID several nodes share: a type, weaker than a name.
    shared: bool,
}

/// The words every node of a tree can be found by. Built once a tree.
#[derive(Debug)]
pub struct Vocabulary {
    entries: Vec<Entry>,
    /// Every stem of every entry, to pass over spans that share none.
    stems: FxHashSet<String>,
}

/// A span of the question that names nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Mention {
    /// Word positions `start..end` in the question.
    pub start: usize,
    pub end: usize,
    /// The nodes it names, best first (several when they share the name).
    pub uids: Vec<Uid>,
    /// 1.0 for a name as written; less for a typo, half a name, a port.
    pub score: f32,
    /// The span is only words that also ask ("wait", "goal"): a node only
    /// if the question names no other.
    pub weak: bool,
    /// The words as the user wrote them.
    pub phrase: String,
}

/// Whether a node is of the kind a word said alone names.
type IsKind = fn(&crate::model::Node) -> bool;

/// Words any sentence has: never half a name on their own.
const PLAIN: &[&str] = &[
    "with", "to", "at", "of", "in", "on", "for", "and", "or", "is", "it", "be", "do", "did",
    "does", "what", "why", "how", "when", "which", "not", "no", "if", "then", "this", "that",
    "was", "were", "are", "has", "have", "had", "can", "could", "will", "would", "a", "the",
    "from", "by", "up", "out", "all", "any", "node", "nodes", "tree", "robot", "time", "times",
    "entire", "whole", "first", "last", "after", "before", "again", "so", "while", "task",
    "mission", "goal", "job", "you", "me", "until", "action", "current", "around", "about", "over",
    "into", "through", "along",
];

/// Verbs that "back" after them makes a way of moving ("go back to").
const MOVES_BACK: &[&str] = &[
    "go", "goes", "going", "gone", "went", "get", "got", "come", "came", "coming",
];

const ARTICLES: &[&str] = &["the", "a", "an", "its", "your", "my", "our"];

/// Words of the question's own English that are never a typo of a name
/// ("list" is not "lift", "show" not "shoe"): they name a node only as
/// written.
const NEVER_TYPOS: &[&str] = &[
    "list", "show", "tell", "give", "explain", "describe", "steps", "step", "says", "said", "when",
    "then", "than", "what", "that", "went", "want", "done", "know", "need", "make", "clean",
    "cleanly", "more",
];

fn typo_of(name_word: &str, w: &Word) -> bool {
    !NEVER_TYPOS.contains(&w.text.as_str())
        && (close(name_word, &w.text) || close(name_word, &w.stem))
}

fn is_article(w: &str) -> bool {
    ARTICLES.contains(&w)
}

pub(super) fn is_kind_word(w: &str) -> bool {
    kind_word(w).is_some()
}

/// Whether a node is of the kind a kind word names.
pub(super) fn of_kind(w: &str, n: &crate::model::Node) -> bool {
    kind_word(w).is_some_and(|is| is(n))
}

/// Kind words: "the FollowPath action", "the insert large gear fallback".
fn kind_word(w: &str) -> Option<fn(&crate::model::Node) -> bool> {
    Some(match w {
        "action" | "actions" | "leaf" | "behavior" | "behaviour" => |n| n.kind == Kind::Action,
        "condition" | "check" | "conditions" => |n| n.kind == Kind::Condition,
        "fallback" | "selector" => |n| n.id.contains("Fallback") || n.id.contains("Selector"),
        "sequence" => |n| n.id.contains("Sequence"),
        "subtree" => |n| n.kind == Kind::SubTree,
        "decorator" => |n| n.kind == Kind::Decorator,
        "control" => |n| n.kind == Kind::Control,
        "recovery" => |n| n.id.contains("Recovery"),
        "node" | "step" => |_| true,
        _ => return None,
    })
}

impl Vocabulary {
    pub fn new(tree: &Tree) -> Vocabulary {
        let mut entries = Vec::new();
        // Names repeat (SubTrees, Nav2's field words for several nodes):
        // each text is read once.
        let mut read: rustc_hash::FxHashMap<String, Option<(Vec<String>, String)>> =
            Default::default();
        let mut push = |uid: Uid, text: &str, source: Source| {
            let known = read.entry(text.to_string()).or_insert_with(|| {
                let ws: Vec<String> = name_words(text)
                    .into_iter()
                    .filter(|w| !is_article(w))
                    .collect();
                let joined: String = split_name(text)
                    .to_lowercase()
                    .split(|c: char| !c.is_alphanumeric())
                    .filter(|w| !w.is_empty() && !is_article(w))
                    .collect::<String>()
                    .replace('0', "o");
                (!ws.is_empty()).then_some((ws, joined))
            });
            if let Some((stems, joined)) = known {
                entries.push(Entry {
                    uid,
                    stems: stems.clone(),
                    joined: joined.clone(),
                    source,
                    shared: false,
                });
            }
        };
        let order = tree.preorder();
        for &u in &order {
            let n = tree.node(u);
            push(u, &tree.words_of(u), Source::Name);
            // A control's ID ("RecoveryNode", "Sequence") is its kind, which
            // kind words pick by; a leaf's or a SubTree's is a name.
            if n.name != n.id && !matches!(n.kind, Kind::Control | Kind::Decorator) {
                push(u, &n.id, Source::Id);
            }
            for p in &n.ports {
                let v = p.value.to_xml();
                if p.value.key().is_none() && v.len() >= 4 && v.chars().any(char::is_alphabetic) {
                    push(u, &v, Source::Port);
                }
            }
        }
        // A Nav2 tree by its node types, or by its names where a tree (a
        // test's, a simulation's) gives Nav2's nodes a type of its own.
        let ids_and_names = tree
            .nodes
            .iter()
            .flat_map(|n| [n.id.as_str(), n.name.as_str()]);
        if nav2_words::applies(ids_and_names) {
            for ((stems, joined), (_, target)) in field_words().iter().zip(nav2_words::WORDS) {
                for u in targets(tree, &order, *target) {
                    entries.push(Entry {
                        uid: u,
                        stems: stems.clone(),
                        joined: joined.clone(),
                        source: Source::Field,
                        shared: false,
                    });
                }
            }
        }
        let mut ids: rustc_hash::FxHashMap<&str, usize> = Default::default();
        for n in &tree.nodes {
            *ids.entry(n.id.as_str()).or_default() += 1;
        }
        for e in &mut entries {
            e.shared = e.source == Source::Id && ids.get(tree.node(e.uid).id.as_str()) > Some(&1);
        }
        let stems = entries
            .iter()
            .flat_map(|e| e.stems.iter().cloned())
            .collect();
        Vocabulary { entries, stems }
    }

    /// The node mentions of a question, longest and best first, none
    /// overlapping. `asks(stem)`: a word that also asks (a cue word).
    pub fn mentions(&self, tree: &Tree, q: &[Word], asks: &dyn Fn(&str) -> bool) -> Vec<Mention> {
        let mut taken = vec![false; q.len()];
        let mut out = named_spans(tree, q, self.scored_spans(q), asks, &mut taken);
        out.extend(kinds_alone(tree, q, &mut taken));
        out.sort_by_key(|m| m.start);
        out
    }

    /// Every span of words that may name nodes, with its score and the
    /// nodes it names best, the longest and best first.
    fn scored_spans(&self, q: &[Word]) -> Vec<(f32, usize, usize, Vec<Uid>)> {
        let mut found: Vec<(f32, usize, usize, Vec<Uid>)> = Vec::new();
        // A name starts and ends with one of the tree's words (or a typo
        // of one): spans that do not are passed over unscored.
        let known: Vec<bool> = q.iter().map(|w| self.known(&w.stem, &w.text)).collect();
        // The entries each word may belong to: those holding its stem, a
        // stem it is a typo of, or a joined name it starts.
        let near: Vec<Vec<usize>> = q
            .iter()
            .zip(&known)
            .map(|(w, &k)| if k { self.near(w) } else { Vec::new() })
            .collect();
        for i in 0..q.len() {
            if is_article(&q[i].text) || q[i].text.starts_with('#') || !known[i] {
                continue;
            }
            for j in i + 1..=(i + 8).min(q.len()) {
                if is_article(&q[j - 1].text) || !known[j - 1] {
                    continue;
                }
                if q[i..j].iter().any(|w| w.text == "\u{0}") {
                    break;
                }
                let span: Vec<&Word> = q[i..j].iter().filter(|w| !is_article(&w.text)).collect();
                if never_a_name(q, i, j, &span) {
                    continue;
                }
                // "LO" for "L0": a zero read as the letter.
                let joined: String = span
                    .iter()
                    .map(|w| w.text.as_str())
                    .collect::<String>()
                    .replace('0', "o");
                let mut best = 0.0f32;
                let mut uids: Vec<Uid> = Vec::new();
                let mut entries: Vec<usize> = near[i..j].iter().flatten().copied().collect();
                entries.sort_unstable();
                entries.dedup();
                for e in entries.into_iter().map(|k| &self.entries[k]) {
                    let s = score(&span, &joined, e);
                    if s > best + 0.001 {
                        best = s;
                        uids.clear();
                    }
                    if s > 0.0 && (s - best).abs() <= 0.001 && !uids.contains(&e.uid) {
                        uids.push(e.uid);
                    }
                }
                // Half a name that only one node has is as good as its name.
                if (0.6..0.85).contains(&best) && uids.len() == 1 && !span.is_empty() {
                    let chars: usize = span.iter().map(|w| w.text.len()).sum();
                    if chars >= 4 {
                        best = 0.85;
                    }
                }
                if best >= 0.6 {
                    found.push((best, i, j, uids));
                }
            }
        }
        // Longer spans first at about the same score: "look at chuck" over "chuck".
        found.sort_by(|a, b| {
            let ka = a.0 + 0.03 * (a.2 - a.1) as f32;
            let kb = b.0 + 0.03 * (b.2 - b.1) as f32;
            kb.total_cmp(&ka).then(a.1.cmp(&b.1))
        });
        found
    }

    /// Every stem of the tree's names, IDs, ports and field words.
    pub fn stems(&self) -> &FxHashSet<String> {
        &self.stems
    }

    fn near(&self, w: &Word) -> Vec<usize> {
        let head: String = w.text.chars().take(4).collect();
        let long = w.text.chars().count() >= 4;
        self.entries
            .iter()
            .enumerate()
            .filter(|(_, e)| {
                e.stems.iter().any(|s| *s == w.stem || *s == w.text)
                    || long && e.joined.starts_with(&head)
                    || e.stems.iter().any(|s| close(s, &w.text))
                    || e.stems.len() > 1 && close(&e.joined, &w.text)
                    || e.joined == w.text.replace('0', "o")
            })
            .map(|(k, _)| k)
            .collect()
    }

    fn known(&self, stem: &str, text: &str) -> bool {
        if self.stems.contains(stem) || self.stems.contains(&text.replace('o', "0")) {
            return true;
        }
        // A typo, or a name written joined ("lookatchuck"), or both
        // ("folowpath").
        let head: String = text.chars().take(4).collect();
        text.chars().count() >= 4
            && self.entries.iter().any(|e| {
                e.joined.starts_with(&head)
                    || e.stems.iter().any(|s| close(s, text))
                    || e.stems.len() > 1 && close(&e.joined, text)
            })
    }
}

/// Spans that name no node whatever the tree's names: a kind ("recovery
/// node"), words any sentence has ("did", "with", whatever an ID says), and
/// "back" after a verb of moving ("why did it go back to planning").
fn never_a_name(q: &[Word], i: usize, j: usize, span: &[&Word]) -> bool {
    let kind = ["recovery", "retry"].contains(&q[j - 1].text.as_str())
        && q.get(j).is_some_and(|w| w.text == "node")
        && i == j - 1;
    let plain = span
        .iter()
        .all(|w| PLAIN.contains(&w.text.as_str()) || PLAIN.contains(&w.stem.as_str()));
    // "Went straight back to": an adverb may come between.
    let moved = |k: usize| MOVES_BACK.contains(&q[k].text.as_str());
    let adverb = |k: usize| ["straight", "right", "just"].contains(&q[k].text.as_str());
    // "Going back to detect chuck": "back to" is where it went, not
    // "back to approach pose".
    let moving_back = span[0].text == "back"
        && span[1..].iter().all(|w| w.text == "to")
        && i > 0
        && (moved(i - 1) || i > 1 && adverb(i - 1) && moved(i - 2));
    // "Tick 6 looks like a disaster": how it seems, not look at chuck.
    let seems = span.len() == 1
        && ["look", "looks", "looked"].contains(&span[0].text.as_str())
        && q.get(j).is_some_and(|w| w.text == "like");
    kind || plain || moving_back || seems
}

/// Nav2's field words as a question's words, read once a process.
fn field_words() -> &'static [(Vec<String>, String)] {
    static WORDS: std::sync::OnceLock<Vec<(Vec<String>, String)>> = std::sync::OnceLock::new();
    WORDS.get_or_init(|| {
        nav2_words::WORDS
            .iter()
            .map(|(phrase, _)| {
                let stems: Vec<String> = name_words(phrase)
                    .into_iter()
                    .filter(|w| !is_article(w))
                    .collect();
                let joined: String = phrase.split(' ').filter(|w| !is_article(w)).collect();
                (stems, joined)
            })
            .collect()
    })
}

/// A SubTree, Fallback or Sequence and the control node inside it named
/// alike are one: the outermost. A leaf named as the node above it (Nav2's
/// FollowPath action under the FollowPath RecoveryNode) is a node of its
/// own, and nodes that share a name otherwise stay several.
pub fn outermost(tree: &Tree, uids: Vec<Uid>) -> Vec<Uid> {
    match uids.first() {
        Some(&first)
            if uids.iter().all(|&u| {
                u == first || (tree.is_ancestor(first, u) && !tree.node(u).kind.is_leaf())
            }) =>
        {
            vec![first]
        }
        _ => uids,
    }
}

fn targets(tree: &Tree, order: &[Uid], t: Target) -> Vec<Uid> {
    let by_id = |ids: &[&str]| -> Vec<Uid> {
        order
            .iter()
            .copied()
            .filter(|&u| {
                let n = tree.node(u);
                ids.contains(&n.id.as_str()) || n.kind.is_leaf() && ids.contains(&n.name.as_str())
            })
            .collect()
    };
    match t {
        Target::Ids(ids) => by_id(ids),
        Target::Doing(ids) => {
            let doers = by_id(ids);
            order
                .iter()
                .copied()
                .filter(|&u| {
                    doers
                        .iter()
                        .any(|&d| tree.node(d).name == tree.node(u).name)
                })
                .collect()
        }
        Target::IdsWithPort(ids, text) => by_id(ids)
            .into_iter()
            .filter(|&u| {
                tree.node(u)
                    .ports
                    .iter()
                    .any(|p| p.value.to_xml().contains(text))
            })
            .collect(),
        Target::RecoveryBranch => {
            let named: Vec<Uid> = order
                .iter()
                .copied()
                .filter(|&u| {
                    let n = &tree.node(u).name;
                    n == "RecoveryFallback" || n == "RecoveryActions"
                })
                .take(1)
                .collect();
            if !named.is_empty() {
                return named;
            }
            let root = tree.root();
            if root.id == "RecoveryNode" {
                root.children.get(1).copied().into_iter().collect()
            } else {
                Vec::new()
            }
        }
        Target::Root => vec![tree.root().uid],
    }
}

/// Edits allowed between a word and the word it was meant to be.
fn allowance(len: usize) -> usize {
    match len {
        0..=3 => 0,
        4..=7 => 1,
        8..=15 => 2,
        _ => 3,
    }
}

/// A typo of one another: within the edits their length allows, the
/// first letter kept or swapped with the second ("chuk", "fial").
fn close(a: &str, b: &str) -> bool {
    let n = a.len().max(b.len());
    let (mut x, mut y) = (a.bytes(), b.bytes());
    let (a0, b0) = (x.next(), y.next());
    let first =
        a0 == b0 || (a0 == b.as_bytes().get(1).copied() && b0 == a.as_bytes().get(1).copied());
    first
        && allowance(n) > 0
        && a.len().abs_diff(b.len()) <= allowance(n)
        && strsim::osa_distance(a, b) <= allowance(n)
}

/// The span's words joined are a typo of the entry's ("lookatchuk"). A
/// word any sentence has at an end of the span is not a letter or two of
/// a misspelt name ("did it recover in the end?" names no "recovery").
fn joined_typo(span: &[&Word], joined: &str, e: &Entry) -> bool {
    let n = joined.len().max(e.joined.len());
    let plain_end = span.len() > 1
        && [span[0], span[span.len() - 1]]
            .iter()
            .any(|w| PLAIN.contains(&w.text.as_str()));
    joined.len().abs_diff(e.joined.len()) <= allowance(n)
        && !plain_end
        && n >= 5
        && joined.get(..2) == e.joined.get(..2)
        && strsim::osa_distance(joined, &e.joined) <= allowance(n)
}

/// How well a span of words names an entry: 1.0 as written, less for a
/// typo, joined words, or a part of the name.
fn score(span: &[&Word], joined: &str, e: &Entry) -> f32 {
    let weight = match e.source {
        Source::Name => 1.0,
        Source::Id if e.shared => 0.75,
        Source::Id => 0.98,
        Source::Port => 0.85,
        Source::Field => 0.97,
    };
    let same = |w: &Word, s: &str| w.stem == s || w.text == s;
    if span.len() == e.stems.len() && span.iter().zip(&e.stems).all(|(w, s)| same(w, s)) {
        return weight;
    }
    if joined == e.joined {
        return 0.97 * weight;
    }
    // "The passenger was picked up": the object of a verb and its
    // particle said first ("pick up passenger").
    if span.len() == e.stems.len() && span.len() > 2 {
        let particle = (1..span.len())
            .find(|&k| ["up", "down", "off", "on", "out", "in"].contains(&e.stems[k].as_str()));
        if let Some(k) = particle {
            let (verb, object) = e.stems.split_at(k + 1);
            let n = object.len();
            if span[..n].iter().zip(object).all(|(w, s)| same(w, s))
                && span[n..].iter().zip(verb).all(|(w, s)| same(w, s))
            {
                return 0.96 * weight;
            }
        }
    }
    if span.len() == e.stems.len() {
        let mut typos = 0;
        let all = span.iter().zip(&e.stems).all(|(w, s)| {
            if same(w, s) {
                true
            } else if !PLAIN.contains(&w.text.as_str()) && typo_of(s, w) {
                typos += 1;
                true
            } else {
                false
            }
        });
        if all {
            return (0.92 - 0.05 * typos as f32) * weight;
        }
    }
    if joined_typo(span, joined, e) {
        return 0.86 * weight;
    }
    // Half a name: the span's words in order inside the entry's, not
    // only words any sentence has ("with" of NavigateWithReplanning).
    let plain = span.iter().all(|w| PLAIN.contains(&w.text.as_str()));
    if e.source != Source::Field && span.len() < e.stems.len() && !plain {
        let chars: usize = span.iter().map(|w| w.text.len()).sum();
        if chars >= 4 {
            for start in 0..=e.stems.len() - span.len() {
                let window = &e.stems[start..start + span.len()];
                if span
                    .iter()
                    .zip(window)
                    .all(|(w, s)| same(w, s) || typo_of(s, w))
                {
                    let part = span.len() as f32 / e.stems.len() as f32;
                    return (0.55 + 0.35 * part) * weight;
                }
            }
        }
    }
    0.0
}

/// Stems of what a node does, which no name goes on past.
const DEEDS: &[&str] = &[
    "fail", "succeed", "success", "run", "ran", "start", "halt", "finish", "complet", "return",
    "stop", "end",
];

/// The spans taken, best first, none overlapping; a kind word beside a
/// name ("the FollowPath action") picks among the nodes that share it.
fn named_spans(
    tree: &Tree,
    q: &[Word],
    found: Vec<(f32, usize, usize, Vec<Uid>)>,
    asks: &dyn Fn(&str) -> bool,
    taken: &mut [bool],
) -> Vec<Mention> {
    let mut out = Vec::new();
    for (score, i, j, uids) in found {
        if taken[i..j].iter().any(|&t| t) {
            continue;
        }
        let (mut start, mut end) = (i, j);
        let mut uids = uids;
        // A kind word beside the name picks among nodes that share it.
        let after = (j..q.len()).find(|&k| !is_article(&q[k].text));
        let before = (0..i).rev().find(|&k| !is_article(&q[k].text));
        for k in [after, after.map(|a| a + 1), before].into_iter().flatten() {
            if k >= q.len() || taken[k] {
                continue;
            }
            // "When did CaseStudySequence fail (step #)?": a word past the
            // next is a kind only where the next word is no deed, and
            // "step" or "node" there picks nothing among the nodes.
            let past_next = Some(k) != after && Some(k) != before;
            if past_next
                && (["node", "step"].contains(&q[k].text.as_str())
                    || after.is_some_and(|a| DEEDS.contains(&q[a].stem.as_str())))
            {
                continue;
            }
            if let Some(is) = kind_word(&q[k].text) {
                let kept: Vec<Uid> = uids.iter().copied().filter(|&u| is(tree.node(u))).collect();
                // "GoalUpdated under RecoveryFallback": a kind a word
                // further on that none of the nodes is belongs to
                // another name.
                if kept.is_empty() && Some(k) != after {
                    continue;
                }
                if !kept.is_empty() {
                    uids = kept;
                }
                start = start.min(k);
                end = end.max(k + 1);
                if k + 1 < q.len() && q[k + 1].text == "node" {
                    end = end.max(k + 2);
                }
                break;
            }
        }
        let uids = outermost(tree, uids);
        for t in &mut taken[start..end] {
            *t = true;
        }
        let weak = q[i..j].iter().all(|w| is_article(&w.text) || asks(&w.stem));
        let phrase = words::said(&q[start..end]);
        out.push(Mention {
            start,
            end,
            uids,
            score,
            weak,
            phrase,
        });
    }
    out
}

/// The built-in IDs of a tree's nodes, lowercased, each with its nodes.
fn builtin_ids(tree: &Tree) -> Vec<(String, Vec<Uid>)> {
    let mut ids: Vec<(String, Vec<Uid>)> = Vec::new();
    for n in tree.nodes.iter().filter(|n| n.builtin.is_some()) {
        let id = n.id.to_lowercase();
        match ids.iter_mut().find(|(i, _)| *i == id) {
            Some((_, us)) => us.push(n.uid),
            None => ids.push((id, vec![n.uid])),
        }
    }
    ids
}

/// The nodes whose built-in ID (of two words or more) the words from `k`
/// spell, and how many words.
fn builtin_said(
    ids: &[(String, Vec<Uid>)],
    q: &[Word],
    k: usize,
    taken: &[bool],
) -> Option<(usize, Vec<Uid>)> {
    (2..=4).rev().find_map(|len| {
        let span = q.get(k..k + len)?;
        if taken[k..k + len].iter().any(|&t| t) {
            return None;
        }
        let joined: String = span.iter().map(|w| w.text.as_str()).collect();
        ids.iter()
            .find(|(id, _)| *id == joined)
            .map(|(_, us)| (len, us.clone()))
    })
}

/// A node called by its kind alone ("the parallel", "the retry node"):
/// every node of that kind, for the run to choose among.
fn kinds_alone(tree: &Tree, q: &[Word], taken: &mut [bool]) -> Vec<Mention> {
    let mut out = Vec::new();
    let ids = builtin_ids(tree);
    let mut k = 0;
    while k < q.len() {
        if taken[k] {
            k += 1;
            continue;
        }
        // "The ForceFailure", "the ReactiveSequence": a built-in's ID as
        // written, its words joined, names the nodes of that ID (and its
        // "failure" is no failure asked about).
        if let Some((len, uids)) = builtin_said(&ids, q, k, taken) {
            for t in &mut taken[k..k + len] {
                *t = true;
            }
            out.push(Mention {
                start: k,
                end: k + len,
                uids,
                score: 0.9,
                weak: false,
                phrase: words::said(&q[k..k + len]),
            });
            k += len;
            continue;
        }
        let two = q.get(k + 1).map(|w| w.text.as_str());
        let (len, is): (usize, Option<IsKind>) = match (q[k].text.as_str(), two) {
            ("recovery", Some("node")) => (2, Some(|n| n.id == "RecoveryNode")),
            ("retry", Some("node")) | ("retry", Some("decorator")) => {
                (2, Some(|n| n.id.starts_with("Retry")))
            }
            ("parallel", _) => (1, Some(|n| n.id.contains("Parallel"))),
            ("sequence", _) => (1, Some(|n| n.id.contains("Sequence"))),
            ("fallback", _) | ("selector", _) => (
                1,
                Some(|n| n.id.contains("Fallback") || n.id.contains("Selector")),
            ),
            ("inverter", _) => (1, Some(|n| n.id == "Inverter")),
            ("repeat", _) => (1, Some(|n| n.id == "Repeat")),
            ("timeout", _) => (1, Some(|n| n.id == "Timeout")),
            ("pipeline", _) => (1, Some(|n| n.id == "PipelineSequence")),
            // "How many times did the condition pass?": the conditions.
            ("condition", _) => (1, Some(|n| n.kind == Kind::Condition)),
            _ => (1, None),
        };
        if let Some(is) = is {
            let uids: Vec<Uid> = tree
                .preorder()
                .into_iter()
                .filter(|&u| is(tree.node(u)))
                .collect();
            if !uids.is_empty() && !taken[k..(k + len).min(q.len())].iter().any(|&t| t) {
                let end = (k + len).min(q.len());
                for t in &mut taken[k..end] {
                    *t = true;
                }
                out.push(Mention {
                    start: k,
                    end,
                    uids,
                    score: 0.9,
                    weak: false,
                    phrase: words::said(&q[k..end]),
                });
                k = end;
                continue;
            }
        }
        k += 1;
    }
    out
}
