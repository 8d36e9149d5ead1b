//! The cue words of a sentence, read once for every rule of `classify`:
//! whether it asks why, what, how or yes or no, speaks of a problem or of
//! all being well, of doing, of the whole, of when; and how sure a reading
//! that rests on its words or names can be.

use super::*;
use crate::ask::parse::Event;

/// Readings, best first by their confidence.
pub(super) type Readings = Vec<(Intent, f32)>;

/// The words of a sentence that say what kind of question it is, read
/// once for every rule.
pub(super) struct Cues<'a, 's> {
    pub(super) s: &'a Sentence<'s>,
    pub(super) tree: &'a Tree,
    pub(super) root: Uid,
    /// Nodes named other than the task itself ("nav2", "the patrol").
    pub(super) named: Vec<&'a Mention>,
    pub(super) ev: Option<Event>,
    pub(super) negated: bool,
    pub(super) first: &'a str,
    pub(super) yes_no: bool,
    pub(super) why: bool,
    pub(super) what: bool,
    pub(super) how: bool,
    pub(super) problem: bool,
    pub(super) fine: bool,
    pub(super) doing_words: bool,
    pub(super) now_words: bool,
    pub(super) whole: bool,
    pub(super) break_down: bool,
    pub(super) when_q: bool,
    pub(super) after_failure: bool,
    pub(super) how_handled: bool,
    node_score: f32,
    words_sure: f32,
}

impl<'a, 's> Cues<'a, 's> {
    pub(super) fn of(s: &'a Sentence<'s>, tree: &'a Tree) -> Cues<'a, 's> {
        let root = tree.root().uid;
        let (ev, negated) = event(s);
        let first = s.first_free().unwrap_or("");
        let why = asks_why(s, ev);
        let what = s.has("what") || s.has("which") || IMPERATIVE.iter().any(|w| s.has(w));
        // "Break it down for me": told part by part, not broken.
        let break_down = s.has("breakdown")
            || s.q.windows(3).any(|p| {
                p[0].text == "break"
                    && ["it", "that", "this"].contains(&p[1].text.as_str())
                    && p[2].text == "down"
            });
        let problem = problem(s, break_down);
        Cues {
            s,
            tree,
            root,
            named: s.nodes.iter().filter(|m| m.uids != [root]).collect(),
            ev,
            negated,
            first,
            yes_no: yes_no(s, first) && !requested(s),
            why,
            what,
            // "How much does it cost", "how much RAM": an amount, never the steps.
            // "In which way it accomplishes …", "by what way does it reach …".
            how: s.has("how") && s.phrase(&["how", "much"]).is_none()
                || s.phrase(&["which", "way"]).is_some()
                || s.phrase(&["what", "way"]).is_some(),
            problem,
            // "Is everything in order?", not "in order to".
            // "Is everything all right?", "going to plan".
            fine: s.phrase(&["all", "right"]).is_some()
                || s.phrase(&["to", "plan"]).is_some()
                || s.phrase(&["on", "track"]).is_some() && !s.q.iter().any(|w| w.text == "back")
                || s.phrase(&["as", "planned"]).is_some()
                // "Everything went grand?" (said "went well").
                || ["go", "went", "gone", "going"]
                    .iter()
                    .any(|g| s.phrase(&[g, "well"]).is_some())
                // "All green?" (a box's colour read as its status).
                || s.phrase(&["all", "success"]).is_some()
                || s.phrase(&["all", "succeeded"]).is_some()
                || s.has_stem(&[
                    "ok", "fine", "good", "alright", "smooth", "normal", "nomin", "healthi",
                    "healthy", "clean",
                ])
                || s.phrase(&["in", "order"])
                    .is_some_and(|i| s.q.get(i + 2).is_none_or(|w| w.text != "to")),
            doing_words: doing_words(s),
            now_words: s.has("now")
                || s.has("currently")
                || s.has("current")
                || s.phrase(&["this", "part"]).is_some()
                || s.has("moment")
                || s.has("working")
                || s.has("towards"),
            whole: whole(s),
            break_down,
            when_q: asks_when(s, why),
            after_failure: after_failure(s, problem),
            // "How'd it handle it when it couldn't look at the chuck": the
            // "when" says which failure, the question is how it was
            // handled. "What was the tree's response when …", "its way of
            // dealing with it".
            how_handled: (s.has("how") || what || s.has("way"))
                && s.has_stem(&[
                    "handl", "deal", "dealt", "respond", "respons", "react", "cope",
                ]),
            node_score: s.nodes.iter().map(|m| m.score).fold(1.0f32, f32::min),
            // How sure a reading is: the words it leaves unexplained count
            // against it, and so do loosely matched names where it rests
            // on them.
            words_sure: 0.93f32.powi(unexplained(s).min(6) as i32),
        }
    }

    /// How sure a reading that rests on the names found is.
    pub(super) fn sure(&self, base: f32) -> f32 {
        base * self.node_score * self.words_sure
    }

    /// How sure a reading that rests on the words alone is.
    pub(super) fn sure_of_words(&self, base: f32) -> f32 {
        base * self.words_sure
    }

    pub(super) fn subject(&self) -> Option<Subject> {
        subject(self.s, self.root)
    }

    /// One reading, as sure as its words.
    pub(super) fn only(&self, intent: Intent, base: f32) -> Option<Readings> {
        Some(vec![(intent, self.sure_of_words(base))])
    }
}

/// Whether a sentence asks why: "why", "how come", "what caused", "on
/// what grounds", or "explain" said of an event.
fn asks_why(s: &Sentence, ev: Option<Event>) -> bool {
    s.has("why")
        || s.has_stem(&["justifi", "justif"])
        || s.phrase(&["how", "come"]).is_some()
        || s.phrase(&["what", "caused"]).is_some()
        || s.phrase(&["what", "made"]).is_some()
        // Not "what went wrong that caused this": what went wrong is asked.
        || s.has_stem(&["reason", "caus", "cause", "rational"]) && s.phrase(&["went", "wrong"]).is_none()
        // "On what grounds did …", "on what basis".
        || s.phrase(&["what", "grounds"]).is_some()
        || s.phrase(&["what", "basis"]).is_some()
        // "Explain look at chuck's failure"; not "explain the strategy
        // this BT uses", "explain what went wrong in this run".
        || (s.has("explain")
            && !s.has("how")
            && !s.has("what")
            && !s.nodes.is_empty()
            && ev.is_some_and(|e| e != Event::Run))
}

/// Whether a sentence speaks of the whole task ("overall", "in the end").
fn whole(s: &Sentence) -> bool {
    [
        "whole",
        "end",
        "final",
        "mission",
        "big",
        "overall",
        "entire",
        "ultimate",
        "ultimately",
        "eventually",
        "main",
        "everything",
        "all",
        "top",
        "recording",
    ]
    .iter()
    .any(|w| s.has(w))
        // "In general, how does it get where it is sent?"
        || s.phrase(&["in", "general"]).is_some()
        || s.has("generally")
}

/// "Could you please tell us what went wrong?": a request to tell, whose
/// question is what follows, not a yes or no.
fn requested(s: &Sentence) -> bool {
    s.q.windows(2).enumerate().any(|(i, p)| {
        ["could", "would", "can"].contains(&p[0].text.as_str())
            && p[1].text == "you"
            && s.q[i + 2..]
                .iter()
                .take(3)
                .find(|w| !["please", "kindly", "pls"].contains(&w.text.as_str()))
                .is_some_and(|w| IMPERATIVE.contains(&w.text.as_str()) || w.text == "check")
    })
}

fn yes_no(s: &Sentence, first: &str) -> bool {
    [
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
        "could",
        "you",
    ]
    .contains(&first)
        // "No problems so far, right?", "problems in the run, yes or no?".
        || first == "no"
        || s.q.last().is_some_and(|w| w.text == "right")
        // "Clean run or not".
        || s.q.len() > 2 && s.ends_with(&["or", "not"])
        || s.phrase(&["yes", "or", "no"]).is_some()
}

/// The stems of a problem's words.
pub(super) const PROBLEM: &[&str] = &[
    "wrong", "problem", "error", "issu", "fail", "broke", "break", "fault", "bad", "mess",
    "hiccup", "glitch", "snag", "hitch", "troubl", "anomali", "anomal", "deviat", "incid",
    "abnorm", "sideway",
];

fn problem(s: &Sentence, break_down: bool) -> bool {
    // "After it couldn't detect the chuck": not managing is failing.
    let could_not = super::event::could_not(s);
    // "For our incident report, …": the report's name, not a problem.
    let report = |i: usize| {
        s.q.get(i + 1)
            .is_some_and(|n| ["report", "log", "ticket", "review"].contains(&n.text.as_str()))
    };
    let said = s.free().any(|(i, w)| {
        PROBLEM.contains(&w.stem.as_str()) && !(w.stem.starts_with("incid") && report(i))
    });
    // "Was it stuck?", "did it give up?": a person's words for a failure,
    // asked yes or no.
    let asked_if = s.q.first().is_some_and(|w| {
        ["did", "was", "is", "has", "had", "does", "were"].contains(&w.text.as_str())
    });
    let plain = asked_if && (s.has("stuck") || super::event::gave_up(s));
    could_not || !break_down && (said || plain) || s.phrase(&["off", "the", "rails"]).is_some()
}

fn doing_words(s: &Sentence) -> bool {
    s.has("doing")
        || s.phrase(&["going", "on"]).is_some()
        || s.phrase(&["went", "on"]).is_some()
        || s.has_stem(&["busi", "busy", "work", "activ", "perform"])
        || s.phrase(&["up", "to"]).is_some()
        || s.phrase(&["carrying", "out"]).is_some()
        || s.phrase(&["carry", "out"]).is_some()
        || s.phrase(&["engaged", "in"]).is_some()
        || s.phrase(&["occupied", "with"]).is_some()
        || s.has("activity")
        // py_trees' "tip of the tree": the deepest behaviour running.
        || s.has("tip")
        // SMACH's "which state is the arm in".
        || (s.phrase(&["which", "state"]).is_some() || s.phrase(&["what", "state"]).is_some())
            && s.has("in")
}

fn asks_when(s: &Sentence, why: bool) -> bool {
    let every_time = (s.has("every") || s.has("each") || s.has("all"))
        && (s.has("time") || s.has("times"))
        && !why;
    every_time
        // "What went wrong when it dropped the passenger off?": the
        // "when" says which time.
        || s.has("when") && s.phrase(&["wrong", "when"]).is_none() && !when_says_which_time(s)
        || s.phrase(&["what", "time"]).is_some()
        || ["which", "what"].iter().any(|q| {
            ["tick", "ticks", "transition", "transitions"]
                .iter()
                .any(|t| s.phrase(&[q, t]).is_some())
        })
        // "Which step did it fail at?", not "which step is it on?" or
        // "which step of the patrol is it in?".
        || (s.phrase(&["which", "step"]).is_some() || s.phrase(&["what", "step"]).is_some())
            && !s.has("on")
            && s.phrase(&["is", "it", "in"]).is_none()
            && s.phrase(&["it", "is", "in"]).is_none()
        || s.phrase(&["at", "what", "point"]).is_some()
        // "At which point during the run did …", not "at this point".
        || s.phrase(&["at", "which", "point"]).is_some()
        // "Identify the tick at which X returned SUCCESS".
        || ["tick", "ticks", "step", "steps"].iter().any(|t| s.has(t))
            && (s.phrase(&["at", "which"]).is_some() || s.phrase(&["in", "which"]).is_some())
        // "list the ticks where it failed".
        // ("Give me all of it" about this tick asks what happened in it.)
        || s.has("ticks") && ["list", "where", "show", "give"].iter().any(|w| s.has(w))
        || s.has("tick") && ["list", "where", "show"].iter().any(|w| s.has(w))
        || tick_asked_for(s)
}

/// "Tick of the last detect_chuck failure?", "last tick X returned
/// SUCCESS?", "first move down: tick?": a tick asked for as a query is
/// typed, with no question word; not "last tick, anything wrong?".
fn tick_asked_for(s: &Sentence) -> bool {
    const ASKS: &[&str] = &[
        "what", "whats", "why", "how", "which", "who", "where", "when", "anything",
    ];
    const ORDINAL: &[&str] = &["first", "last", "final", "earliest", "latest"];
    if s.nodes.is_empty() || s.free().any(|(_, w)| ASKS.contains(&w.text.as_str())) {
        return false;
    }
    let free: Vec<&str> = s
        .free()
        .map(|(_, w)| w.text.as_str())
        .skip_while(|w| ["the", "say", "request", "confirm", "give"].contains(w))
        .collect();
    // "Time of first FollowPath abort?", "time L0 went red?".
    let time_of = ["time", "timestamp"].contains(&free.first().copied().unwrap_or(""))
        && s.q
            .iter()
            .position(|w| ["time", "timestamp"].contains(&w.text.as_str()))
            .is_some_and(|i| {
                s.q.get(i + 1)
                    .is_some_and(|n| n.text == "of" || n.text == "the")
                    || s.used.get(i + 1) == Some(&true)
            });
    let tick_of =
        free.starts_with(&["tick", "of"]) || free.starts_with(&["tick", "number", "of"]) || time_of;
    let ordinal_tick = free.len() > 2 && ORDINAL.contains(&free[0]) && free[1] == "tick";
    // The last word, after a name: "first move down: tick?".
    let tick_last = s.q.len() > 1 && s.q[s.q.len() - 1].text == "tick" && s.used[s.q.len() - 2];
    tick_of || ordinal_tick || tick_last
}

/// "What went on in tick 10 when everything turned green": a "when"
/// after another question word, not joined to it by "and" or "or", says
/// which time the question is about.
fn when_says_which_time(s: &Sentence) -> bool {
    const ASKS: &[&str] = &["what", "whats", "why", "how", "which", "who", "where"];
    // "In which case, when exactly is halt called": a question's inversion.
    let inverted = |i: usize| {
        s.q.get(i + 1).is_some_and(|n| {
            [
                "exactly", "did", "does", "do", "is", "was", "were", "will", "has", "had",
            ]
            .contains(&n.text.as_str())
        })
    };
    s.free().filter(|(_, w)| w.text == "when").all(|(i, _)| {
        i > 0
            && !inverted(i)
            && !["and", "or", "but", "so", "then", "exactly"].contains(&s.q[i - 1].text.as_str())
            && s.q[..i].iter().any(|w| ASKS.contains(&w.text.as_str()))
    })
}

/// "What did it do after it failed?": how a failure was handled.
fn after_failure(s: &Sentence, problem: bool) -> bool {
    failure_told_first(s)
        || (s.has("after") || s.has("when") || s.has("once"))
            && (problem || s.has_stem(&["block", "stuck"]))
            && (s.phrase(&["did", "it", "do"]).is_some()
            // "what did the fallback do when …".
            || s.has("what") && s.has("did") && s.has("do")
            || s.phrase(&["did", "you", "do"]).is_some()
            // "When guarded drive failed, did anything in the tree do
            // something about it?".
            || s.has("did") && s.has("do") && s.phrase(&["about", "it"]).is_some()
            || s.phrase(&["was", "done"]).is_some()
            || s.phrase(&["did", "the", "robot", "do"]).is_some())
}

/// "Guarded drive failed - what did the tree do", "reset arm FAILURE
/// then what": a failure told, then what came of it asked.
fn failure_told_first(s: &Sentence) -> bool {
    let at = |words: &[&str]| {
        s.free()
            .find(|(_, w)| words.contains(&w.text.as_str()))
            .map(|(i, _)| i)
    };
    let (Some(failed), Some(what)) = (at(&["failed", "failure", "aborted"]), at(&["what"])) else {
        return false;
    };
    let then_what = s.phrase(&["then", "what"]).is_some() || s.phrase(&["what", "then"]).is_some();
    let did_do =
        s.q[what..].iter().any(|w| w.text == "did") && s.q[what..].iter().any(|w| w.text == "do");
    failed < what && !s.has("why") && !s.has("if") && (then_what || did_do)
}

/// Words every reading explains: the cue words of the questions and their
/// forms, and the words of asking itself.
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
    "achieved",
    "achieves",
    "achieving",
    "accomplish",
    "accomplished",
    "reach",
    "reached",
    "overall",
    "supposed",
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

/// Content words the reading leaves unexplained.
pub(super) fn unexplained(s: &Sentence) -> usize {
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
