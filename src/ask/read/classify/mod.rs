//! What a sentence asks, once its nodes and moment are found: the cue
//! words are read once (`Cues`), then each rule, in order, says what the
//! question asks or passes it on. The first rule that reads it wins; a
//! rule that returns no reading stops the rest (a why that names nothing
//! it could be about is no other question).

use super::cues::{Cues, Readings};
use super::{
    can_you, foil, gave_up, joined, loops_of, negated_first, progressive, uids_of, verbless, when,
    Mention, Sentence, When, NOT_A_VERB,
};
use crate::ask::parse::{Event, Intent, Subject, Which};
use crate::explain::{Question, RunQuestion, TreeQuestion};
use crate::model::{Tree, Uid};

mod counts;
mod events;
mod run;
mod ticks;
mod tree;
mod why;

use counts::*;
use events::*;
use run::*;
use ticks::*;
use tree::*;
use why::*;

/// The rules, in the order they are tried.
const RULES: &[fn(&Cues) -> Option<Readings>] = &[
    which_failed,
    can_you_asked,
    what_if,
    tick_by_number,
    all_well_in_few_words,
    handled_whether,
    anything_failed,
    recovered,
    how_often,
    when_it_happened,
    how_long,
    purpose,
    why_bare_verb,
    why,
    handled,
    next,
    what_went_wrong,
    anything_wrong,
    tick,
    goal_reached,
    task_outcome,
    how_achieved,
    subgoal_or_goal,
    which_of_two,
    doing,
    whether_it_happened,
    event_alone,
];

/// What a sentence asks: every reading, the best first.
pub(super) fn classify(s: &Sentence, tree: &Tree) -> Readings {
    let c = Cues::of(s, tree);
    RULES.iter().find_map(|rule| rule(&c)).unwrap_or_default()
}
