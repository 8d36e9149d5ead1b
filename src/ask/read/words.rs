//! Text → words: lower case, names split where their writer joined them
//! (CamelCase, snake_case, hyphens, paths), contractions with and without
//! their apostrophe, casual spellings, and each word's stem, so that
//! "didnt", "didn't" and "did not", or "cleared" and "clear", read alike.

use rust_stemmers::{Algorithm, Stemmer};
use std::sync::OnceLock;

/// One word of a question.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Word {
    /// As read, after the spelling is made standard ("didnt" → "did", "not").
    pub text: String,
    /// Its stem ("failed" → "fail"); irregular verbs by a table.
    pub stem: String,
}

fn stemmer() -> &'static Stemmer {
    static S: OnceLock<Stemmer> = OnceLock::new();
    S.get_or_init(|| Stemmer::create(Algorithm::English))
}

/// The stem of one lower-case word.
pub fn stem(w: &str) -> String {
    if let Some((_, base)) = IRREGULAR.iter().find(|(form, _)| *form == w) {
        return (*base).to_string();
    }
    if w.starts_with('#') || w.chars().any(|c| c.is_ascii_digit()) {
        return w.to_string();
    }
    stemmer().stem(w).into_owned()
}

/// Past forms the stemmer does not bring back to their verb.
const IRREGULAR: &[(&str, &str)] = &[
    ("ran", "run"),
    ("running", "run"),
    ("spun", "spin"),
    ("spinning", "spin"),
    ("went", "go"),
    ("gone", "go"),
    ("going", "go"),
    ("took", "take"),
    ("taken", "take"),
    ("got", "get"),
    ("gotten", "get"),
    ("held", "hold"),
    ("drove", "drive"),
    ("driven", "drive"),
    ("broke", "break"),
    ("broken", "break"),
    ("began", "begin"),
    ("begun", "begin"),
    ("did", "do"),
    ("done", "do"),
    ("does", "do"),
    ("was", "be"),
    ("were", "be"),
    ("is", "be"),
    ("are", "be"),
    ("been", "be"),
    ("am", "be"),
    ("had", "have"),
    ("has", "have"),
    ("left", "leave"),
    // "One of the move lefts": a name's plural, stemmed as the name is.
    ("lefts", "leave"),
    ("brought", "bring"),
    ("caught", "catch"),
    ("found", "find"),
    ("made", "make"),
    ("kept", "keep"),
    ("stuck", "stick"),
    ("stopped", "stop"),
    ("failure", "fail"),
    ("failures", "fail"),
    ("success", "succeed"),
    ("succeeded", "succeed"),
    ("succeeds", "succeed"),
    ("succeeding", "succeed"),
];

/// Words written as one that are several ("didnt"), and casual spellings.
const SPELLINGS: &[(&str, &str)] = &[
    // Unreal's prefix of a task class, "BTT_FollowPath", "BTTask_LookAt":
    // the action of that name.
    ("btt", "action"),
    // "The FP ctrl": the controller.
    ("ctrl", "controller"),
    ("bttask", "action"),
    // A sub-objective is a subgoal.
    ("subobjective", "subgoal"),
    // "A downward move" is a move down.
    ("downward", "down"),
    ("downwards", "down"),
    ("upward", "up"),
    ("upwards", "up"),
    ("leftward", "left"),
    ("leftwards", "left"),
    ("rightward", "right"),
    ("rightwards", "right"),
    ("didnt", "did not"),
    ("dident", "did not"),
    ("dint", "did not"),
    ("dont", "do not"),
    ("doesnt", "does not"),
    ("doesn", "does not"),
    ("isnt", "is not"),
    ("wasnt", "was not"),
    ("werent", "were not"),
    ("arent", "are not"),
    ("hasnt", "has not"),
    ("havent", "have not"),
    ("hadnt", "had not"),
    ("wouldnt", "would not"),
    ("couldnt", "could not"),
    ("shouldnt", "should not"),
    ("cant", "can not"),
    ("cannot", "can not"),
    ("wont", "will not"),
    ("whats", "what is"),
    ("whatcha", "what are you"),
    ("watcha", "what are you"),
    ("wotcha", "what are you"),
    ("gonna", "going to"),
    ("wanna", "want to"),
    ("wats", "what is"),
    ("wheres", "where is"),
    ("hows", "how is"),
    ("whys", "why is"),
    ("whens", "when is"),
    ("thats", "that is"),
    ("whos", "who is"),
    ("im", "i am"),
    ("ive", "i have"),
    ("youre", "you are"),
    ("theres", "there is"),
    ("u", "you"),
    ("ya", "you"),
    ("r", "are"),
    ("ur", "your"),
    ("y", "why"),
    ("wy", "why"),
    ("wat", "what"),
    ("wut", "what"),
    ("wht", "what"),
    ("whta", "what"),
    ("waht", "what"),
    ("hwat", "what"),
    ("wha", "what"),
    ("hw", "how"),
    ("wen", "when"),
    ("whn", "when"),
    ("wehn", "when"),
    ("happend", "happened"),
    ("happnd", "happened"),
    ("bussy", "busy"),
    ("goin", "going"),
    ("doin", "doing"),
    ("runnin", "running"),
    ("atm", "now"),
    ("rn", "now"),
    ("currently", "now"),
    ("presently", "now"),
    ("pls", "please"),
    ("plz", "please"),
    ("plox", "please"),
    ("b4", "before"),
    ("cuz", "because"),
    ("coz", "because"),
    ("bc", "because"),
    ("abt", "about"),
    ("smth", "something"),
    ("sth", "something"),
    ("tho", "though"),
    ("thru", "through"),
    ("nvm", ""),
    ("pl", "please"),
    ("ok", "ok"),
    ("okay", "ok"),
    ("alright", "ok"),
    ("behaviour", "behavior"),
    // An on-call chat's shorthand.
    ("ctrl", "controller"),
    ("plnr", "planner"),
    ("recov", "recovery"),
    ("recovs", "recoveries"),
    ("recovd", "recovered"),
    ("probs", "problems"),
    ("prob", "problem"),
    ("seq", "sequence"),
    ("deco", "decorator"),
    ("nah", "not"),
    ("naw", "not"),
    ("yuh", "you"),
    ("gimme", "give me"),
    ("w", "with"),
    ("lvl", "level"),
    ("imo", "in my opinion"),
    ("imho", "in my opinion"),
    ("vs", "rather than"),
    ("versus", "rather than"),
];

/// "didn't" and "it's": the apostrophe's forms, before the apostrophe goes.
const CONTRACTIONS: &[(&str, &str)] = &[
    ("recov'd", "recovered"),
    ("can't", "can not"),
    ("won't", "will not"),
    ("n't", " not"),
    ("it's", "it is"),
    ("what's", "what is"),
    ("that's", "that is"),
    ("there's", "there is"),
    ("who's", "who is"),
    ("how's", "how is"),
    ("where's", "where is"),
    ("when's", "when is"),
    ("why's", "why is"),
    ("i'm", "i am"),
    ("you're", "you are"),
    ("'ve", " have"),
    ("'ll", " will"),
    ("'d", " would"),
    ("'re", " are"),
];

/// Splits a written name where its writer joined words: "FollowPath" →
/// "Follow Path", "ClearLocalCostmap-Context" → "Clear Local Costmap
/// Context", "look_at_chuck" → "look at chuck". Digits stay with their
/// word ("L0"), and an all-capitals run stays one word ("BT").
pub fn split_name(s: &str) -> String {
    let chars: Vec<char> = s.chars().collect();
    let mut out = String::with_capacity(s.len() + 8);
    for (i, &c) in chars.iter().enumerate() {
        if matches!(c, '_' | '-' | '/' | '.') {
            out.push(' ');
            continue;
        }
        if i > 0 && c.is_uppercase() {
            let prev = chars[i - 1];
            let next_lower = chars.get(i + 1).is_some_and(|n| n.is_lowercase());
            if prev.is_lowercase() || (prev.is_uppercase() && next_lower) {
                out.push(' ');
            }
        }
        out.push(c);
    }
    out
}

/// Phrases said as one word: what autocorrect makes of a costmap, what an
/// assessment calls the robot.
const PHRASES: &[(&str, &str)] = &[
    ("coat map", "costmap"),
    ("coast map", "costmap"),
    ("item under test", "robot"),
    ("system under test", "robot"),
    ("unit under test", "robot"),
    ("device under test", "robot"),
    ("as opposed to", "instead of"),
    ("sub objective", "subgoal"),
    // Not "bounced back to planning": that is going back.
    ("bounced back from", "recovered from"),
    ("bounces back from", "recovers from"),
    ("bounce back from", "recover from"),
    // "Why no call for help this run?": asking for help, as the tree says.
    ("call for help", "ask for help"),
    ("calls for help", "asks for help"),
    ("called for help", "asked for help"),
    ("calling for help", "asking for help"),
    // "Had a look at the run from last night": the asker looking, no
    // supposition and no look at chuck.
    ("had a look at", "checked"),
    ("have a look at", "check"),
    ("having a look at", "checking"),
    ("took a look at", "checked"),
    ("take a look at", "check"),
    ("taking a look at", "checking"),
    // "What just went down in this tick?": slang for what happened, not
    // a move down.
    ("what just went down", "what just happened"),
    ("what went down", "what happened"),
    // An idiom ("why did it fail in the first place?"), not the first time.
    ("in the first place", ""),
    // "y'all", "y'reckon": a "y" that is no "why".
    ("y'all", " "),
    ("y’all", " "),
    ("ya'll", " "),
    ("y'reckon", " "),
    ("y’reckon", " "),
    ("y'know", " "),
    ("y’know", " "),
    // How people in many places say a robot got going again, or things
    // went well or badly: "did it come right?", "come good", "pick itself
    // up", "went grand", "go pear-shaped".
    ("come right", "recover"),
    ("came right", "recovered"),
    ("come good", "recover"),
    ("came good", "recovered"),
    ("pick itself up", "recover"),
    ("picked itself up", "recovered"),
    ("went grand", "went well"),
    ("gone grand", "gone well"),
    ("pear shaped", "wrong"),
    ("pear-shaped", "wrong"),
    // Southern "fixing to" is "going to".
    ("fixin' to", "going to"),
    ("fixing to", "going to"),
    ("getting on with", "doing"),
    ("gone through fine", "succeeded"),
    ("went through fine", "succeeded"),
    ("reckon you could", "could you"),
    ("this here", "this"),
    ("run us through", "describe"),
    ("run me through", "describe"),
    ("take me through", "describe"),
    ("take us through", "describe"),
    ("talk me through", "describe"),
    ("talk us through", "describe"),
    ("the only tick", "tick 1"),
    // "How's it going to do the whole job?": its goal, not what is next.
    ("do the whole job", "achieve the goal"),
    ("do the whole task", "achieve the goal"),
    // "The first transition of tick 4" is its first step.
    ("first transition of", "step 1 of"),
    ("first step of", "step 1 of"),
];

/// The text lowercased with its names split, what it pastes or abbreviates
/// said plainly: "y/n", a log's rows, "the item under test", contractions
/// and possessives.
fn plain_text(text: &str) -> String {
    // "y/n" asks for yes or no: its "y" is no "why".
    let mut text = text.trim().to_string();
    if text.contains('/') {
        for yes_no in ["y/n", "Y/N", "y/N", "Y/n", "yes/no", "Yes/No", "YES/NO"] {
            if text.contains(yes_no) {
                text = text.replace(yes_no, " yes or no ");
            }
        }
    }
    if text.contains('`') {
        text = log_rows(&text);
    }
    let mut s = split_name(&text).to_lowercase();
    for (said, plain) in PHRASES {
        if s.contains(said) {
            s = s.replace(said, plain);
        }
    }
    if s.contains(['\'', '’', '‘', '`', '´']) {
        s = quotes_apart(&s.replace(['’', '‘', '`', '´'], "'"));
        for (from, to) in CONTRACTIONS {
            s = s.replace(from, to);
        }
        // "'s" of a possessive ("the robot's goal") goes; every other mark
        // is a word's end.
        s = s.replace("'s ", " ");
    }
    s
}

/// Quotes around a name ("why did 'detect chuck' fail?") set apart from
/// its words: a mark with no letter before it or none after it is a
/// quote, not a contraction's ("'detect" is no "'d", "would").
fn quotes_apart(s: &str) -> String {
    let chars: Vec<char> = s.chars().collect();
    let letter = |i: Option<usize>| {
        i.and_then(|i| chars.get(i))
            .is_some_and(|c| c.is_alphanumeric())
    };
    chars
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            if c == '\'' && !(letter(i.checked_sub(1)) && letter(Some(i + 1))) {
                ' '
            } else {
                c
            }
        })
        .collect()
}

/// The words of a question.
pub fn words(text: &str) -> Vec<Word> {
    let s = plain_text(text);
    let mut out = Vec::new();
    for raw in s.split(|c: char| !(c.is_alphanumeric() || c == '#' || c == ':')) {
        let raw = raw.trim_matches(':');
        if raw.is_empty() {
            continue;
        }
        // "9:2" is a moment; any other colon separates words.
        let parts: Vec<&str> = if raw
            .split(':')
            .all(|p| p.chars().all(|c| c.is_ascii_digit()))
        {
            vec![raw]
        } else {
            raw.split(':').filter(|p| !p.is_empty()).collect()
        };
        for part in parts {
            let spelled = SPELLINGS
                .iter()
                .find(|(w, _)| *w == part)
                .map_or(part, |(_, to)| *to);
            for w in spelled.split_whitespace() {
                // "Break down the plan": one word, so that "down" names
                // no move.
                if w == "down" && out.last().is_some_and(|p: &Word| p.stem == "break") {
                    let last = out.len() - 1;
                    out[last] = Word {
                        text: "breakdown".into(),
                        stem: "breakdown".into(),
                    };
                    continue;
                }
                out.push(word(w));
            }
        }
    }
    // "On frame 10", "this frame": a game engine's frame is a tick (a
    // node named with "frame" keeps it).
    for i in 0..out.len() {
        if !["frame", "frames"].contains(&out[i].text.as_str()) {
            continue;
        }
        let said_as_moment = out
            .get(i + 1)
            .is_some_and(|n| n.text.bytes().all(|b| b.is_ascii_digit()))
            || i > 0
                && [
                    "this", "that", "last", "previous", "prev", "same", "next", "first", "every",
                    "each", "per", "final", "current", "one", "many", "which", "what",
                ]
                .contains(&out[i - 1].text.as_str());
        if said_as_moment {
            let tick = if out[i].text == "frame" {
                "tick"
            } else {
                "ticks"
            };
            out[i] = word(tick);
        }
    }
    // "…, or no?" is "or not?": no "no" a node was told.
    if let [.., yes, or, no] = &mut out[..] {
        if yes.text != "yes" && or.text == "or" && no.text == "no" {
            *no = Word {
                text: "not".into(),
                stem: "not".into(),
            };
        }
    }
    as_logs_say(spoken_numbers(spoken_turns(out)))
}

/// A word as read, with its stem.
fn word(w: &str) -> Word {
    Word {
        text: w.to_string(),
        stem: stem(w),
    }
}

/// Turns of English as many places speak it, said the plain way: "can
/// back up or not?" (Singlish) is "can you back up?", "what's it at now?"
/// (Irish) is "what is it doing now?", "is X something you can do?" is
/// "can you X?".
fn spoken_turns(mut out: Vec<Word>) -> Vec<Word> {
    fn text(out: &[Word], i: usize) -> &str {
        out.get(i).map_or("", |w| w.text.as_str())
    }
    const SUBJECT: &[&str] = &[
        "you", "it", "i", "we", "they", "he", "she", "the", "this", "that", "robot", "bot", "a",
    ];
    let tail = if out.ends_with(&[word("or"), word("can"), word("not")]) {
        3
    } else if out.ends_with(&[word("or"), word("not")]) {
        2
    } else {
        0
    };
    if text(&out, 0) == "can"
        && tail > 0
        && out.len() > tail + 1
        && !SUBJECT.contains(&text(&out, 1))
    {
        out.truncate(out.len() - tail);
        out.insert(1, word("you"));
    }
    if text(&out, 0) == "what" && ["is", "was", "are", "were"].contains(&text(&out, 1)) {
        let at = (2..6.min(out.len())).find(|&i| text(&out, i) == "at");
        let then = at.map(|i| text(&out, i + 1));
        if let (Some(i), Some("" | "now" | "in" | "during" | "right" | "like" | "then" | "just")) =
            (at, then)
        {
            out[i] = word("doing");
        }
    }
    let can_do = ["something", "you", "can", "do"].map(word);
    if text(&out, 0) == "is" {
        if let Some(p) = out.windows(4).position(|w| w == can_do) {
            if p > 1 {
                let mut said = vec![word("can"), word("you")];
                said.extend_from_slice(&out[1..p]);
                said.extend_from_slice(&out[p + 4..]);
                out = said;
            }
        }
    }
    out
}

/// Numbers in words, as speech-to-text writes them.
const UNITS: [&str; 20] = [
    "zero",
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
    "thirteen",
    "fourteen",
    "fifteen",
    "sixteen",
    "seventeen",
    "eighteen",
    "nineteen",
];
const TENS: [&str; 8] = [
    "twenty", "thirty", "forty", "fifty", "sixty", "seventy", "eighty", "ninety",
];

/// The number spelled by the words of `q` from `i` ("twenty six", "one
/// hundred and four"), and how many words it took.
fn spelled_number(q: &[Word], i: usize) -> Option<(u32, usize)> {
    let at = |k: usize| q.get(k).map_or("", |w| w.text.as_str());
    let below_100 = |k: usize| -> Option<(u32, usize)> {
        if let Some(u) = UNITS.iter().position(|&u| u == at(k)) {
            return Some((u as u32, 1));
        }
        let t = TENS.iter().position(|&t| t == at(k))? as u32 * 10 + 20;
        match UNITS.iter().position(|&u| u == at(k + 1)) {
            Some(u @ 1..=9) => Some((t + u as u32, 2)),
            _ => Some((t, 1)),
        }
    };
    let (n, used) = below_100(i)?;
    if at(i + used) != "hundred" || !(1..=9).contains(&n) {
        return Some((n, used));
    }
    let k = i + used + 1 + usize::from(at(i + used + 1) == "and");
    match below_100(k) {
        Some((m, more)) => Some((n * 100 + m, k - i + more)),
        None => Some((n * 100, used + 1)),
    }
}

/// A number said in words where a log's numbers stand, after "tick",
/// "step", "node", "uid" or "#" ("tick twenty six" is tick 26), and a
/// letter said before one, as a name's ("el zero" is L0).
fn spoken_numbers(words: Vec<Word>) -> Vec<Word> {
    let spelled = |w: &Word| UNITS.contains(&w.text.as_str()) || TENS.contains(&w.text.as_str());
    if !words.iter().any(spelled) {
        return words;
    }
    let counted =
        |w: &str| ["tick", "ticks", "step", "steps", "node", "uid", "id", "#"].contains(&w);
    let letter = |w: &str| w == "el" || (w.len() == 1 && !["a", "i", "#"].contains(&w));
    let mut out: Vec<Word> = Vec::with_capacity(words.len());
    let mut i = 0;
    while i < words.len() {
        let w = &words[i];
        let before = out.last().map_or("", |p: &Word| p.text.as_str());
        let number = (counted(before) || (letter(&w.text) && i + 1 < words.len()))
            .then(|| spelled_number(&words, i + usize::from(!counted(before))))
            .flatten();
        match number {
            Some((n, used)) if counted(before) => {
                out.push(Word {
                    text: n.to_string(),
                    stem: n.to_string(),
                });
                i += used;
            }
            Some((n, used)) if n < 10 && used == 1 => {
                let name = format!("{}{n}", if w.text == "el" { "l" } else { &w.text });
                out.push(Word {
                    stem: name.clone(),
                    text: name,
                });
                i += 2;
            }
            _ => {
                out.push(w.clone());
                i += 1;
            }
        }
    }
    out
}

/// A row of `btx log` pasted into a question ("`10  1  18  look at chuck
/// RUNNING -> FAILURE`") is the moment and the node it names: "#18 at
/// 10:1". Its status words would otherwise read as an event asked about.
fn log_rows(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(open) = rest.find('`') {
        let Some(len) = rest[open + 1..].find('`') else {
            break;
        };
        let inside = &rest[open + 1..open + 1 + len];
        out.push_str(&rest[..open]);
        match log_row(inside) {
            Some((tick, step, uid)) => out.push_str(&format!(" #{uid} at {tick}:{step} ")),
            None => out.push_str(&rest[open..open + len + 2]),
        }
        rest = &rest[open + len + 2..];
    }
    out.push_str(rest);
    out
}

/// The tick, step and uid of a log row: three numbers, a name, and
/// "PREV -> STATUS".
fn log_row(row: &str) -> Option<(u32, u32, u32)> {
    let words: Vec<&str> = row.split_whitespace().collect();
    let [tick, step, uid, ..] = words[..] else {
        return None;
    };
    let status = |w: &str| ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"].contains(&w);
    let n = words.len();
    (n >= 6 && words[n - 2] == "->" && status(words[n - 1]) && status(words[n - 3]))
        .then_some(())?;
    Some((tick.parse().ok()?, step.parse().ok()?, uid.parse().ok()?))
}

/// A node and a tick as a log and its readers say them: "node 8", "uid
/// 7", "id 7" are `#8`, `#7`; "t=30" is tick 30.
fn as_logs_say(words: Vec<Word>) -> Vec<Word> {
    // "t44", "@ t6", "tick1": tick 44, tick 6, tick 1.
    let digits = |w: &Word| {
        ["tick", "t"].iter().find_map(|p| {
            w.text
                .strip_prefix(p)
                .filter(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
                .map(str::to_string)
        })
    };
    let tick_n = |w: &Word| digits(w).is_some();
    if !words
        .iter()
        .any(|w| ["node", "uid", "id", "t"].contains(&w.text.as_str()) || tick_n(w))
    {
        return words;
    }
    let number = |w: Option<&Word>| w.is_some_and(|w| w.text.chars().all(|c| c.is_ascii_digit()));
    let mut out: Vec<Word> = Vec::with_capacity(words.len());
    let mut it = words.into_iter().peekable();
    while let Some(w) = it.next() {
        if ["node", "uid", "id"].contains(&w.text.as_str()) && number(it.peek()) {
            let n = it.next().map(|n| n.text).unwrap_or_default();
            let uid = format!("#{n}");
            out.push(Word {
                stem: uid.clone(),
                text: uid,
            });
        } else if tick_n(&w) {
            out.push(Word {
                text: "tick".into(),
                stem: "tick".into(),
            });
            let n = digits(&w).unwrap_or_default();
            out.push(Word {
                stem: n.clone(),
                text: n,
            });
        } else if w.text == "t" && number(it.peek()) {
            out.push(Word {
                text: "tick".into(),
                stem: "tick".into(),
            });
        } else {
            out.push(w);
        }
    }
    out
}

/// Words as the question said them, one space between.
pub fn said(q: &[Word]) -> String {
    q.iter()
        .map(|w| w.text.as_str())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The words of a node's name, ID or port value, as a question would
/// hold them.
pub fn name_words(s: &str) -> Vec<String> {
    words(s).into_iter().map(|w| w.stem).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(s: &str) -> Vec<String> {
        words(s).into_iter().map(|w| w.text).collect()
    }

    #[test]
    fn contractions_with_and_without_apostrophes_read_alike() {
        assert_eq!(texts("why didn't it wait"), texts("why didnt it wait"));
        assert_eq!(texts("whats the goal"), texts("what's the goal"));
        assert_eq!(
            texts("y did detect chuk fail"),
            ["why", "did", "detect", "chuk", "fail"]
        );
        assert_eq!(texts("r u ok"), ["are", "you", "ok"]);
    }

    #[test]
    fn numbers_said_in_words_are_numbers_where_a_log_has_them() {
        assert_eq!(texts("at tick twenty six"), ["at", "tick", "26"]);
        assert_eq!(
            texts("tick one hundred and four step two"),
            ["tick", "104", "step", "2"]
        );
        assert_eq!(texts("node thirteen"), ["#13"]);
        assert_eq!(texts("why did el zero fail"), ["why", "did", "l0", "fail"]);
        // Elsewhere a number word is a word: "the one that failed".
        assert_eq!(
            texts("which one failed twice"),
            ["which", "one", "failed", "twice"]
        );
        assert_eq!(texts("a one off"), ["a", "one", "off"]);
    }

    #[test]
    fn joined_names_are_split_into_their_words() {
        assert_eq!(
            texts("ClearLocalCostmap-Context"),
            ["clear", "local", "costmap", "context"]
        );
        assert_eq!(texts("look_at_chuck"), ["look", "at", "chuck"]);
        assert_eq!(texts("at 9:2, #18 failed"), ["at", "9:2", "#18", "failed"]);
        assert_eq!(texts("L0"), ["l0"]);
    }

    #[test]
    fn word_forms_share_a_stem() {
        assert_eq!(stem("cleared"), stem("clear"));
        assert_eq!(stem("spun"), "spin");
        assert_eq!(stem("failed"), stem("fail"));
        assert_eq!(stem("failure"), stem("fail"));
    }
}
