//! What every target does with a log that opened: the questions a user
//! asks of it, so a strange tree or run that a reader lets through is
//! fuzzed past the reader too.

use btx::explain::{answer, Question};
use btx::session::{Moment, Session};

pub fn exercise(s: &Session) {
    let ticks = s.index.ticks();
    let mut seen = Vec::new();
    for tick in [1, ticks / 2, ticks] {
        if tick == 0 || seen.contains(&tick) {
            continue;
        }
        seen.push(tick);
        for step in [None, Some(0), Some(1)] {
            let Ok(at) = s.at(Moment { tick, step }) else {
                continue;
            };
            let _ = at.entries();
            if let Some(n) = at.current() {
                for q in Question::fixed() {
                    let _ = answer(&s.tree, Some(&at), n, &q);
                }
            }
        }
    }
}
