//! How answers say things: an event as a verb and in the past, moments
//! as a list, a sentence's first letter.

use super::parse::Event;
use crate::explain::han::and_list;
use crate::session::Index;

/// The moment right after the transition that ends at position `pos`,
/// always as `TICK:STEP`.
pub(super) use crate::causal::calls::{step_moment, times};

pub(super) fn past(e: Event) -> &'static str {
    match e {
        Event::Fail => "failed",
        Event::Succeed => "succeeded",
        Event::Run => "started",
        Event::NotRun => "did not run",
        Event::Skipped => "was skipped",
        Event::Halted => "was halted",
        Event::KeepRunning => "was running",
        Event::Finish => "finished",
    }
}

pub(super) fn verb(e: Event) -> &'static str {
    match e {
        Event::Fail => "fail",
        Event::Succeed => "succeed",
        Event::Run => "start",
        Event::NotRun => "not run",
        Event::Skipped => "be skipped",
        Event::Halted => "get halted",
        Event::KeepRunning => "keep running",
        Event::Finish => "finish",
    }
}

pub(super) fn moments(index: &Index, ps: &[u32]) -> String {
    let ms: Vec<String> = ps
        .iter()
        .map(|&p| step_moment(index, p).to_string())
        .collect();
    if ms.len() > 12 {
        format!("{}, … and {}", ms[..10].join(", "), ms[ms.len() - 1])
    } else {
        and_list(&ms)
    }
}

pub(super) fn upper(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}
