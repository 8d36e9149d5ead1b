//! The moment a question names, if it names one: "at tick 9", "at 7:1",
//! "in the last tick", "just before the failure", "after the recovery".
//! Read before the nodes, so that "tick 9" is not a node's name.

use super::words::Word;

/// A moment as a question says it; `ask` finds it in the run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum When {
    /// The end of tick N.
    Tick(u32),
    /// After the STEP-th transition of tick N.
    Step(u32, u32),
    FirstTick,
    LastTick,
    /// Just before the first failure of the run.
    BeforeFailure,
    /// Just after the first failure.
    AfterFailure,
    /// When the failure's handler succeeded.
    AfterRecovery,
    /// Just before this node failed (its last failure by the moment asked,
    /// else its first).
    BeforeFailureOf(crate::model::Uid),
    /// Just after this node failed.
    AfterFailureOf(crate::model::Uid),
    /// Just before this node started ("right before ask kicked in"; its
    /// last start by the moment asked, else its first).
    BeforeStartOf(crate::model::Uid),
    /// Just after this node started.
    AfterStartOf(crate::model::Uid),
    /// The N-th failure of an action or condition in the run: "the
    /// first time it stalled" asked of the robot, not of a node.
    NthFailure(u32),
    /// The N-th time (from 1) this node ended, failed if `failed` ("the
    /// second time it failed", "on the third try"), and which side of it.
    Ended {
        uid: crate::model::Uid,
        n: u32,
        failed: bool,
        side: Side,
    },
}

/// Which side of an event a moment told by it stands: "just before X
/// failed the second time", "when X failed the second time", "after the
/// first X failure" (the moment of the event itself, from which what is
/// asked about is looked for after it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Before,
    At,
    After,
}

impl When {
    /// As an answer says it.
    pub fn words(self) -> String {
        match self {
            When::Tick(n) => format!("at tick {n}"),
            When::Step(t, s) => format!("at {t}:{s}"),
            When::FirstTick => "in the first tick".into(),
            When::LastTick => "in the last tick".into(),
            When::BeforeFailure => "just before the failure".into(),
            When::AfterFailure => "just after the failure".into(),
            When::AfterRecovery => "after the recovery".into(),
            When::BeforeFailureOf(u) => format!("just before #{u} failed"),
            When::AfterFailureOf(u) => format!("just after #{u} failed"),
            When::BeforeStartOf(u) => format!("just before #{u} started"),
            When::AfterStartOf(u) => format!("just after #{u} started"),
            When::NthFailure(n) => format!("at the {} failure", ordinal_word(n)),
            When::Ended {
                uid,
                n,
                failed,
                side,
            } => ended(&format!("#{uid}"), n, failed, side),
        }
    }

    /// As an answer says it, the node by its name.
    pub fn told(self, tree: &crate::model::Tree) -> String {
        match self {
            When::BeforeFailureOf(u) => format!("just before {} failed", tree.told(u)),
            When::AfterFailureOf(u) => format!("just after {} failed", tree.told(u)),
            When::BeforeStartOf(u) => format!("just before {} started", started(tree, u)),
            When::AfterStartOf(u) => format!("just after {} started", started(tree, u)),
            When::Ended {
                uid,
                n,
                failed,
                side,
            } => ended(&tree.told(uid), n, failed, side),
            w => w.words(),
        }
    }
}

/// The same behaviour as `u` wherever the tree has it: its ID and name
/// ("ask" in three subtrees), not a node that only shares the name (the
/// FollowPath RecoveryNode beside the FollowPath action).
pub fn alike(tree: &crate::model::Tree, u: crate::model::Uid) -> Vec<crate::model::Uid> {
    let n = tree.node(u);
    (1..=tree.len() as crate::model::Uid)
        .filter(|&v| {
            let m = tree.node(v);
            m.id == n.id && tree.description(v) == tree.description(u)
        })
        .collect()
}

/// The node a start is told by: by name where the behaviour is in several
/// places (the run says which started), else the node itself.
fn started(tree: &crate::model::Tree, u: crate::model::Uid) -> String {
    match alike(tree, u).len() {
        1 => tree.told(u),
        _ => tree.description(u).to_string(),
    }
}

fn ended(node: &str, n: u32, failed: bool, side: Side) -> String {
    let verb = if failed { "failed" } else { "ended" };
    let at = match side {
        Side::Before => "just before",
        Side::At => "when",
        Side::After => "just after",
    };
    format!("{at} {node} {verb} for the {} time", ordinal_word(n))
}

fn number(w: &str) -> Option<u32> {
    let w = w.trim_start_matches('#');
    w.parse().ok().filter(|&n| n > 0)
}

fn step(w: &str) -> Option<(u32, u32)> {
    let (t, s) = w.split_once(':')?;
    Some((number(t)?, s.parse().ok()?))
}

const ORDINALS: &[&str] = &[
    "first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "tenth",
];

/// A count from 1 in words: "second", "11th".
pub fn ordinal_word(n: u32) -> String {
    ORDINALS
        .get((n as usize).wrapping_sub(1))
        .map_or(format!("{n}th"), |w| w.to_string())
}

/// "second", "3rd", "tenth": a count from 1.
pub fn ordinal(w: &str) -> Option<u32> {
    if let Some(i) = ORDINALS.iter().position(|x| *x == w) {
        return Some(i as u32 + 1);
    }
    let digits = w.trim_end_matches(|c: char| c.is_ascii_alphabetic());
    let suffix = &w[digits.len()..];
    (["st", "nd", "rd", "th"].contains(&suffix))
        .then(|| digits.parse().ok())
        .flatten()
        .filter(|&n| n > 0)
}

/// "The second time", "on the third try", "the first FollowPath
/// attempt": which of a node's runs, counted from 1. The node is the one
/// the question names; `ask` finds that run's end.
pub fn nth_time(q: &[Word]) -> Option<u32> {
    const TIME: &[&str] = &["time", "try", "attempt", "tries", "attempts", "go", "round"];
    (0..q.len()).find_map(|i| {
        let n = ordinal(&q[i].text)?;
        // A name may come between: "the second FollowPath attempt".
        (i + 1..q.len().min(i + 6))
            .any(|j| TIME.contains(&q[j].text.as_str()))
            .then_some(n)
    })
}

const BEFORE: &[&str] = &[
    "at", "in", "on", "during", "of", "for", "from", "by", "around",
];

/// Words that move through a run, as a user scrolls a timeline.
const MOVES: &[&str] = &[
    "back",
    "forward",
    "forwards",
    "ahead",
    "scroll",
    "scrolling",
    "scrolled",
    "jump",
    "jumping",
    "jumped",
    "go",
    "going",
    "went",
    "rewind",
    "rewinding",
    "rewound",
    "skip",
    "skipping",
    "step",
    "stepping",
    "move",
    "moving",
    "fast",
];

/// The moment named, and the word positions that said it.
pub fn find(q: &[Word]) -> Option<(When, Vec<usize>)> {
    // A tick said by its number comes before "the end of the run" said
    // elsewhere ("at the end of the run, what did frame 13 do?").
    (0..q.len())
        .find_map(|i| {
            tick_said(q, i)
                .or_else(|| step_of_tick(q, i))
                .or_else(|| moment_said(q, i))
                .or_else(|| end_or_start(q, i).filter(|(w, _)| matches!(w, When::Tick(_))))
                .or_else(|| at_a_number(q, i))
        })
        .or_else(|| {
            (0..q.len()).find_map(|i| end_or_start(q, i).or_else(|| around_a_failure(q, i)))
        })
}

/// "Why was drive halted at 5", "what if it had gone green at 10": a
/// number after "at", with no unit after it, is a tick.
fn at_a_number(q: &[Word], i: usize) -> Option<(When, Vec<usize>)> {
    const UNITS: &[&str] = &[
        "hz", "m", "s", "ms", "sec", "secs", "second", "seconds", "percent", "metres", "meters",
        "metre", "meter", "mph", "kmh", "degrees", "deg", "rad", "x", "times", "fps", "pm", "am",
        "hours", "hour", "minutes", "minute", "mins", "min", "cm", "mm", "km", "kg", "g", "v",
        "volts", "a", "amps", "w", "watts", "o'clock", "oclock", "nodes", "ticks",
    ];
    let t = |i: usize| text(q, i);
    if t(i) != "at" || !t(i + 1).chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let n = number(t(i + 1))?;
    // "At 1.0 hz": a decimal's parts are two words.
    let unit =
        |w: &str| UNITS.contains(&w) || !w.is_empty() && w.chars().all(|c| c.is_ascii_digit());
    if unit(t(i + 2)) {
        return None;
    }
    Some((When::Tick(n), vec![i, i + 1]))
}

/// Word `i` of `q`, or "" past the end.
fn text(q: &[Word], i: usize) -> &str {
    q.get(i).map(|w| w.text.as_str()).unwrap_or("")
}

/// The positions `used` of a moment that starts at `i`, with the words
/// before it that are part of it: "at", "just", "right", "the", and the
/// words of moving through a timeline ("scrolling back to tick 20", "jump
/// to 7:1"), which name no node ("back to approach pose").
fn lead(q: &[Word], i: usize, mut used: Vec<usize>) -> Vec<usize> {
    let t = |i: usize| text(q, i);
    let mut k = i;
    while k > 0 && (BEFORE.contains(&t(k - 1)) || ["just", "right", "the"].contains(&t(k - 1))) {
        k -= 1;
        used.push(k);
    }
    if k > 0 && t(k - 1) == "to" {
        let mut m = k - 1;
        while m > 0 && MOVES.contains(&t(m - 1)) {
            m -= 1;
        }
        if m < k - 1 {
            used.extend(m..k);
        }
    }
    used
}

/// "tick 9", "tick #9", "tick number 9", "tick 9 step 2", "the third
/// tick", "the last tick".
fn tick_said(q: &[Word], i: usize) -> Option<(When, Vec<usize>)> {
    let t = |i: usize| text(q, i);
    if t(i) != "tick" && t(i) != "ticks" {
        return None;
    }
    let mut j = i + 1;
    if ["number", "no", "num", "nr"].contains(&t(j)) {
        j += 1;
    }
    if let Some((tk, s)) = step(t(j)) {
        return Some((When::Step(tk, s), lead(q, i, (i..=j).collect())));
    }
    if let Some(n) = number(t(j)) {
        if t(j + 1) == "step" {
            if let Some(s) = number(t(j + 2)) {
                return Some((When::Step(n, s), lead(q, i, (i..=j + 2).collect())));
            }
        }
        return Some((When::Tick(n), lead(q, i, (i..=j).collect())));
    }
    // "the third tick", "the 2nd tick": the tick counted from 1.
    if let Some(n) = i.checked_sub(1).and_then(|k| ordinal(t(k))) {
        if n > 1 {
            return Some((When::Tick(n), lead(q, i - 1, vec![i - 1, i])));
        }
    }
    // "the last tick", "the final tick", "the first tick".
    if i > 0 && ["last", "final", "first", "1st"].contains(&t(i - 1)) {
        let w = if t(i - 1) == "first" || t(i - 1) == "1st" {
            When::FirstTick
        } else {
            When::LastTick
        };
        return Some((w, lead(q, i - 1, vec![i - 1, i])));
    }
    None
}

/// "step 2 of tick 9", and "at 7:1".
fn step_of_tick(q: &[Word], i: usize) -> Option<(When, Vec<usize>)> {
    let t = |i: usize| text(q, i);
    if t(i) == "step" {
        if let (Some(s), "of", "tick", Some(n)) =
            (number(t(i + 1)), t(i + 2), t(i + 3), number(t(i + 4)))
        {
            return Some((When::Step(n, s), lead(q, i, (i..=i + 4).collect())));
        }
    }
    // "at 7:1", and a moment copied from the log anywhere ("look at chuck
    // just FAILED (10:1)", "right after 2:8"): "TICK:STEP" is no other word.
    let (tk, s) = step(t(i))?;
    Some((When::Step(tk, s), lead(q, i, vec![i])))
}

/// "moment 9": the end of tick 9.
fn moment_said(q: &[Word], i: usize) -> Option<(When, Vec<usize>)> {
    if text(q, i) != "moment" {
        return None;
    }
    let n = number(text(q, i + 1))?;
    Some((When::Tick(n), lead(q, i, vec![i, i + 1])))
}

/// "at the end (of the run)", "at the start".
fn end_or_start(q: &[Word], i: usize) -> Option<(When, Vec<usize>)> {
    let t = |i: usize| text(q, i);
    let w = t(i);
    if !((w == "end" || w == "start" || w == "beginning")
        && i >= 2
        && t(i - 1) == "the"
        && ["at", "by", "near", "towards", "toward"].contains(&t(i - 2)))
    {
        return None;
    }
    let mut used = vec![i - 2, i - 1, i];
    // "At the end of tick 2" is that tick, not the run's last; "at the
    // start of tick 3", the end of the one before.
    if t(i + 1) == "of" {
        if let Some((When::Tick(n), said)) = tick_said(q, i + 2) {
            used.push(i + 1);
            used.extend(said);
            let n = if w == "end" { n } else { n.saturating_sub(1) };
            return (n > 0).then_some((When::Tick(n), used));
        }
    }
    if t(i + 1) == "of" && ["run", "mission", "log", "task"].contains(&t(i + 3)) {
        used.extend([i + 1, i + 2, i + 3]);
    }
    let when = if w == "end" {
        When::LastTick
    } else {
        When::FirstTick
    };
    Some((when, used))
}

/// "before the failure", "after it failed", "after the recovery".
fn around_a_failure(q: &[Word], i: usize) -> Option<(When, Vec<usize>)> {
    let t = |i: usize| text(q, i);
    let w = t(i);
    if w != "before" && w != "after" && w != "once" {
        return None;
    }
    let mut j = i + 1;
    let mut used = vec![i];
    while ["the", "it", "that", "first", "a"].contains(&t(j)) {
        used.push(j);
        j += 1;
    }
    let next = t(j);
    let what = if ["fail", "crash", "error", "problem", "fault"]
        .iter()
        .any(|p| next.starts_with(p))
    {
        if w == "before" {
            When::BeforeFailure
        } else {
            When::AfterFailure
        }
    } else if w != "before" && (next.starts_with("recover") || next.starts_with("retr")) {
        When::AfterRecovery
    } else {
        return None;
    };
    used.push(j);
    if t(j + 1) == "happened" || t(j + 1) == "occurred" {
        used.push(j + 1);
    }
    Some((what, lead(q, i, used)))
}

#[cfg(test)]
mod tests {
    use super::super::words::words;
    use super::*;

    fn when(s: &str) -> Option<When> {
        find(&words(s)).map(|(w, _)| w)
    }

    #[test]
    fn moments_said_in_words_are_found() {
        assert_eq!(when("what were you doing at tick 9?"), Some(When::Tick(9)));
        assert_eq!(when("describe tick #9"), Some(When::Tick(9)));
        assert_eq!(when("why did it fail at 7:1"), Some(When::Step(7, 1)));
        assert_eq!(
            when("what happened in the final tick?"),
            Some(When::LastTick)
        );
        assert_eq!(
            when("just before the failure, what was running?"),
            Some(When::BeforeFailure)
        );
        assert_eq!(
            when("what were you doing after the recovery"),
            Some(When::AfterRecovery)
        );
        assert_eq!(when("what went wrong"), None);
    }

    #[test]
    fn the_end_of_a_tick_is_that_tick_not_the_last() {
        assert_eq!(
            when("what is the subgoal at the end of tick 2?"),
            Some(When::Tick(2))
        );
        assert_eq!(when("by the end of tick 4, why"), Some(When::Tick(4)));
        assert_eq!(when("at the start of tick 3"), Some(When::Tick(2)));
        assert_eq!(when("at the end of the run"), Some(When::LastTick));
        assert_eq!(when("at the end, what failed"), Some(When::LastTick));
        assert_eq!(
            when("at the end of the run, what did frame 13 do"),
            Some(When::Tick(13))
        );
    }

    #[test]
    fn a_number_after_at_is_a_tick_unless_it_has_a_unit() {
        assert_eq!(when("why was drive halted at 5"), Some(When::Tick(5)));
        assert_eq!(
            when("what if it had gone green at 10?"),
            Some(When::Tick(10))
        );
        assert_eq!(when("why is the rate controller at 1 hz"), None);
        assert_eq!(when("why is it orange with the badge at 1.0 hz"), None);
        assert_eq!(when("why did it stop at 2 m"), None);
        assert_eq!(when("why did #18 fail at #7"), None);
    }
}
