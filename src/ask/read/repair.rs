//! What is asked after the asker corrected themselves as they typed. A
//! repair said after "sorry", "no wait", "I mean", "er, no" or "or
//! rather" replaces what it corrects: the words from the last one it
//! begins like ("what went on at tick 9 — ugh, I mean tick 6?" asks of
//! tick 6), the node named last ("why did detect chuck, no wait, look at
//! chuck fail?") or, said again in full, the question begun ("can you
//! grasp — sorry, can you release a screw?"), whose "it" is the node the
//! question begun named. A hesitation ("what if, um, the first spin had
//! worked?") replaces nothing.

use super::*;
use std::borrow::Cow;

/// Sounds made while thinking: alone between commas they may begin a
/// repair ("the current subgoal, er, the step it's in").
const HESITATIONS: &[&str] = &[
    "er", "erm", "um", "umm", "uh", "hmm", "ugh", "oh", "ah", "eh",
];

/// The words that say "what I said before was wrong".
const EDITS: &[&[&str]] = &[
    &["no", "wait"],
    &["wait", "no"],
    &["scratch", "that"],
    &["no", "sorry"],
    &["sorry", "no"],
    &["i", "mean"],
    &["or", "rather"],
    &["sorry"],
    &["actually"],
    &["wait"],
    &["no"],
];

/// A word of the text, where it lies, and the mark it ends with.
struct Token {
    start: usize,
    end: usize,
    core: String,
    /// It ends a clause: a comma, a question mark, a dash, dots.
    closes: bool,
    dash: bool,
}

fn tokens(text: &str) -> Vec<Token> {
    let mut out = Vec::new();
    let mut at = 0;
    for piece in text.split_inclusive(char::is_whitespace) {
        let word = piece.trim_end();
        let start = at;
        at += piece.len();
        if word.is_empty() {
            continue;
        }
        let core: String = word
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == '\'')
            .flat_map(char::to_lowercase)
            .collect();
        let dash = word.chars().all(|c| matches!(c, '—' | '–' | '-'));
        let closes = dash || word.ends_with([',', '?', '.', ';', ':', '!', '—', '–']);
        out.push(Token {
            start,
            end: start + word.len(),
            core,
            closes,
            dash,
        });
    }
    out
}

/// How the asker said they corrected themselves.
#[derive(Clone, Copy, PartialEq)]
enum Said {
    /// "sorry", "no wait", "I mean".
    Edit,
    /// "er", "hmm": a repair only where it begins like words it replaces.
    Hesitation,
    /// A dash alone: a repair only where the question begins again with
    /// its own words ("can you check whether — can you check if …").
    Dash,
}

/// A correction found at a token: where the words corrected end, where
/// the repair begins, and how it was said.
struct Correction {
    before: usize,
    repair: usize,
    said: Said,
    /// The words corrected were opened by a dash, so a second dash closes
    /// the repair ("the detect chuck sequence — hmm, no, the Retry above
    /// it — fail?").
    dashed: bool,
}

fn correction_at(t: &[Token], k: usize) -> Option<Correction> {
    let opened = t.get(k.checked_sub(1)?)?;
    if !opened.closes {
        return None;
    }
    let mut j = k;
    while t
        .get(j)
        .is_some_and(|w| HESITATIONS.contains(&w.core.as_str()))
    {
        j += 1;
    }
    let hesitated = j > k;
    let edit = EDITS.iter().find(|e| {
        e.iter()
            .enumerate()
            .all(|(i, w)| t.get(j + i).is_some_and(|x| x.core == *w))
            // "No" and "wait" alone are edits only before a comma
            // ("hmm, no, why did it run?"), not the answer "no" or the
            // action wait.
            && (e.len() > 1 || t[j].closes || !matches!(e[0], "no" | "wait"))
    });
    let repair = j + edit.map_or(0, |e| e.len());
    if repair >= t.len() || (!hesitated && edit.is_none() && !opened.dash) {
        return None;
    }
    Some(Correction {
        before: k - 1,
        repair,
        said: match (edit, hesitated) {
            (Some(_), _) => Said::Edit,
            (None, true) => Said::Hesitation,
            (None, false) => Said::Dash,
        },
        dashed: opened.dash || t[..k].iter().rev().skip(1).any(|w| w.dash),
    })
}

/// The question as meant, its corrections applied.
pub(super) fn repaired<'a>(vocabulary: &Vocabulary, tree: &Tree, text: &'a str) -> Cow<'a, str> {
    let mut now = Cow::Borrowed(text);
    // A correction of a correction: each is applied, the last first.
    for _ in 0..3 {
        match repaired_once(vocabulary, tree, &now) {
            Some(next) => now = Cow::Owned(next),
            None => break,
        }
    }
    match now {
        Cow::Borrowed(t) => Cow::Borrowed(after_a_correction(t)),
        owned => owned,
    }
}

fn repaired_once(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<String> {
    let t = tokens(text);
    (1..t.len()).rev().find_map(|k| {
        let c = correction_at(&t, k)?;
        let said = text[..t[c.before].end]
            .trim_end_matches(|ch: char| ch.is_whitespace() || ",;:—–-".contains(ch));
        let mut repair = &text[t[c.repair].start..];
        let mut tail = "";
        if c.dashed {
            if let Some(d) = t[c.repair..].iter().find(|w| w.dash) {
                repair = &text[t[c.repair].start..d.start];
                tail = &text[d.end..];
            }
        }
        let repair = repair.trim_end_matches(|ch: char| ch.is_whitespace() || ch == ',');
        replaced(vocabulary, tree, said, repair, c.said).map(|r| {
            let tail = tail.trim();
            if tail.is_empty() {
                r
            } else {
                format!("{r} {tail}")
            }
        })
    })
}

/// `said` with `repair` put in place of what it corrects, if it corrects
/// anything there.
fn replaced(
    vocabulary: &Vocabulary,
    tree: &Tree,
    said: &str,
    repair: &str,
    how: Said,
) -> Option<String> {
    let opens = repair.split_whitespace().next().map(|w| {
        w.trim_matches(|c: char| !c.is_alphanumeric() && c != '\'')
            .to_lowercase()
    })?;
    if said.split_whitespace().count() < 2 {
        return None;
    }
    // "… oh no wait, it hasn't even got to the screws yet. So why is it
    // asking?": what follows is told, then asked, whole.
    if [". ", "? ", "! "].iter().any(|end| repair.contains(end)) {
        return (how == Said::Edit).then(|| repair.to_string());
    }
    if OPENS.contains(&opens.as_str()) {
        return asked_again(vocabulary, tree, said, repair, how)
            .then(|| with_its_node(vocabulary, tree, said, repair));
    }
    if how == Said::Dash {
        return None;
    }
    another_ordinal(said, repair)
        .or_else(|| begun_alike(said, repair, &opens))
        .or_else(|| {
            // "Why did detect chuck, no wait, look at chuck fail?": the node
            // named last, where the words corrected end with it.
            let phrase = node_phrase(vocabulary, tree, said).filter(|_| how == Said::Edit)?;
            let lower = said.to_lowercase();
            let at = lower.rfind(&phrase).filter(|_| lower.len() == said.len())?;
            lower[at + phrase.len()..]
                .trim()
                .is_empty()
                .then(|| format!("{}{repair}", &said[..at]))
        })
}

/// Whether `repair`, which opens as a question does, asks the question
/// begun again in full ("why did it never spin — I mean, why didn't the
/// recovery actions run?"). A dash alone repairs only a question begun
/// again with its own words ("can you check whether — can you check if
/// …").
fn asked_again(vocabulary: &Vocabulary, tree: &Tree, said: &str, repair: &str, how: Said) -> bool {
    let said_words: Vec<&str> = said.split_whitespace().collect();
    let again = |n: usize| {
        said_words
            .iter()
            .zip(repair.split_whitespace())
            .take(n)
            .all(|(a, b)| a.eq_ignore_ascii_case(b))
    };
    // After a hesitation, a clause that only goes on ("what happened at
    // tick 3, uh, when the walk finished?") or leans on what was said ("—
    // er, what does it actually do for it?") is no question begun again.
    let clause = || {
        repair
            .split_whitespace()
            .nth(1)
            .is_some_and(|w| ["the", "a", "an"].contains(&w.to_lowercase().as_str()))
    };
    let reads =
        |sure: f32| read_one(vocabulary, tree, repair).is_some_and(|r| r.confidence >= sure);
    match how {
        Said::Edit => reads(0.0),
        Said::Hesitation => (said_words.len() >= 3 || again(1)) && !clause() && reads(SURE),
        Said::Dash => again(2),
    }
}

/// "The first follow path failure — sorry, the second one": the
/// ordinal said last replaced, the rest kept.
fn another_ordinal(said: &str, repair: &str) -> Option<String> {
    let words: Vec<String> = repair
        .split_whitespace()
        .map(|w| {
            w.trim_matches(|c: char| !c.is_alphanumeric())
                .to_lowercase()
        })
        .collect();
    let [.., n, last] = &words[..] else {
        return None;
    };
    if !["one", "ones"].contains(&last.as_str()) || when::ordinal(n).is_none() {
        return None;
    }
    let mut said_words: Vec<&str> = said.split_whitespace().collect();
    let i = said_words.iter().rposition(|w| {
        when::ordinal(
            &w.trim_matches(|c: char| !c.is_alphanumeric())
                .to_lowercase(),
        )
        .is_some()
    })?;
    said_words[i] = n;
    let tail = repair.trim_end().chars().last().filter(|c| *c == '?');
    Some(format!(
        "{}{}",
        said_words.join(" "),
        tail.map(String::from).unwrap_or_default()
    ))
}

/// `said` from the last word the repair begins like, replaced by it
/// ("at tick 9 — ugh, I mean tick 6").
fn begun_alike(said: &str, repair: &str, opens: &str) -> Option<String> {
    let lower = said.to_lowercase();
    if lower.len() != said.len() {
        return None;
    }
    let from = lower
        .match_indices(opens)
        .map(|(i, _)| i)
        .filter(|&i| {
            let whole_before = i == 0 || !lower.as_bytes()[i - 1].is_ascii_alphanumeric();
            let after = lower.as_bytes().get(i + opens.len());
            whole_before && !after.is_some_and(|b| b.is_ascii_alphanumeric())
        })
        .last()?;
    (from > 0).then(|| format!("{}{repair}", &said[..from]))
}

/// The words of the node a question names, as the reader read them.
fn node_phrase(vocabulary: &Vocabulary, tree: &Tree, said: &str) -> Option<String> {
    let reading = read_one(vocabulary, tree, said)?;
    match subject_of(&reading.intent)? {
        Subject::Nodes(_, phrase) => Some(phrase.to_lowercase()),
        _ => None,
    }
}

/// The question asked again, its "it" the node the question begun named
/// ("why did Spin run twice — hmm, no, why did it fail the first time?").
fn with_its_node(vocabulary: &Vocabulary, tree: &Tree, said: &str, repair: &str) -> String {
    let names_one = read_one(vocabulary, tree, repair)
        .is_some_and(|r| subject_of(&r.intent).is_some() || r.about.is_some());
    let it = repair
        .split_whitespace()
        .position(|w| w.eq_ignore_ascii_case("it"));
    match (names_one, it, node_phrase(vocabulary, tree, said)) {
        (false, Some(i), Some(phrase)) => {
            let named = with_its_ordinal(said, &phrase);
            let mut words: Vec<&str> = repair.split_whitespace().collect();
            words[i] = &named;
            words.join(" ")
        }
        _ => repair.to_string(),
    }
}

/// The node's words with the ordinal said before them ("the second move
/// up"), so the question asked again is of the same call.
fn with_its_ordinal(said: &str, phrase: &str) -> String {
    const BEFORE: &[&str] = &[
        "the", "first", "second", "third", "fourth", "fifth", "last", "final", "1st", "2nd", "3rd",
        "4th", "5th",
    ];
    let lower = said.to_lowercase();
    let Some(at) = lower.rfind(phrase) else {
        return phrase.to_string();
    };
    let before: Vec<&str> = lower[..at].split_whitespace().collect();
    let kept = before
        .iter()
        .rev()
        .take_while(|w| BEFORE.contains(w))
        .count();
    let mut words = before[before.len() - kept..].to_vec();
    words.push(phrase);
    words.join(" ")
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

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens_of(text: &str) -> Vec<String> {
        tokens(text).into_iter().map(|t| t.core).collect()
    }

    #[test]
    fn a_word_s_mark_is_not_its_core() {
        assert_eq!(
            tokens_of("what — sorry, can't"),
            ["what", "", "sorry", "can't"]
        );
        let t = tokens("tick 9 — ugh, I mean");
        assert!(t[2].dash && t[3].closes && !t[4].closes);
    }

    #[test]
    fn a_hesitation_or_a_plain_answer_is_no_correction() {
        let t = tokens("what would have happened if, um, the first spin had worked?");
        let c = correction_at(&t, 5).unwrap();
        assert!(c.said == Said::Hesitation);
        let t = tokens("did it fail, no?");
        assert!(correction_at(&t, 3).is_none());
        let t = tokens("what ran before wait?");
        assert!((1..t.len()).all(|k| correction_at(&t, k).is_none()));
    }
}
