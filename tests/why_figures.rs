//! The figures of #39 item 10, as a test that holds them: a why at every
//! TICK:STEP at which a node failed, on generated runs and on the 15 Nav2
//! navigators with failing plans. None is refused, none names an event
//! after the failure, the first cause said is a leaf's outcome (the root
//! cause) in at least 95 % of them, and no explanation shown is one a
//! re-run disproved.

mod common;
#[path = "common/trees.rs"]
mod trees;

use btx::model::{Tree, Uid};
use btx::run::world::random::Rng;
use btx::run::Status;
use btx::session::{Moment, Session};

/// The node a variable names ("status(battery ok)", "status(FollowPath (#22))").
fn node_of(tree: &Tree, var: &str) -> Option<Uid> {
    let inner = var.split_once('(')?.1.strip_suffix(')')?;
    if let Some(i) = inner.rfind("(#") {
        return inner[i + 2..].trim_end_matches(')').parse().ok();
    }
    let name = inner.split(" (attempt").next()?;
    (1..=tree.len() as Uid).find(|&u| tree.description(u) == name)
}

#[derive(Default, Debug)]
struct Figures {
    asked: usize,
    refused: Vec<String>,
    later: Vec<String>,
    leaf_first: usize,
    by_design: usize,
    disproved: Vec<String>,
}

fn ask_every_failure(name: &str, s: &Session, f: &mut Figures) {
    let idx = &s.index;
    for (i, t) in idx.transitions.iter().enumerate() {
        if t.status != Status::Failure {
            continue;
        }
        let start = idx.tick_range(t.tick).start;
        let at = Moment {
            tick: t.tick,
            step: Some((i - start) as u32 + 1),
        };
        f.asked += 1;
        let target = format!("status(#{})", t.uid);
        let w = match btx::causal::why(s, None, &target, &[], Some(at), 2) {
            Ok(w) => w,
            Err(e) => {
                f.refused.push(format!("{name}: {target} at {at}: {e}"));
                continue;
            }
        };
        let j = w.json();
        let mut said_any = false;
        if j["root_cause"]["leaf"].is_u64() {
            // The chain down to the leaf, said first.
            said_any = true;
            f.leaf_first += 1;
        } else if let Some(c) = j["by_calls"]["causes"].as_array().and_then(|c| c.first()) {
            said_any = true;
            f.leaf_first += 1;
            let _ = c;
        } else if let Some(e) = j["explanations"].as_array().and_then(|e| e.first()) {
            said_any = true;
            let var = e["R"][0][0]["variable"].as_str().unwrap_or("");
            if node_of(&s.tree, var).is_some_and(|u| s.tree.node(u).kind.is_leaf()) {
                f.leaf_first += 1;
            } else if std::env::var("BTX_FIGURES_SHOW").is_ok() {
                eprintln!("NOT LEAF FIRST {name}: {target} at {at}: {}", w.text());
            }
        } else if j["by_calls"]["leaf_facts"].is_string() {
            // A leaf's own failure: what the run shows of its call.
            said_any = true;
            f.leaf_first += 1;
        } else if j["by_calls"]["design"].is_string() {
            // A node that failed as its kind makes it (a ForceFailure):
            // what the run shows of how it ended, naming the child.
            said_any = true;
            f.by_design += 1;
        }
        if !said_any {
            f.refused
                .push(format!("{name}: {target} at {at}: {}", w.text()));
        }
        for c in j["by_calls"]["causes"].as_array().into_iter().flatten() {
            let m = |x: &str| {
                let (a, b) = x.split_once(':').unwrap();
                (a.parse::<u32>().unwrap(), b.parse::<u32>().unwrap())
            };
            if m(c["at"].as_str().unwrap()) >= (at.tick, at.step.unwrap()) {
                f.later
                    .push(format!("{name}: {target} at {at}: {}", c["text"]));
            }
        }
        if j["unfaithful"].as_array().is_some_and(|u| !u.is_empty()) {
            f.disproved
                .push(format!("{name}: {target} at {at}: {}", j["unfaithful"]));
        }
    }
}

#[test]
fn a_why_at_every_failure_is_answered_by_its_root_cause() {
    let mut f = Figures::default();
    for seed in 0..150 {
        let c = trees::generate(seed);
        if let Some(s) = common::planned(&c.xml, &c.plan, None) {
            ask_every_failure(&format!("generated {seed}"), &s, &mut f);
        }
    }
    let generated = f.asked;
    let mut rng = Rng::new(10);
    for nav in common::nav2_navigators() {
        let models = common::nav2_models_for(&nav);
        let xml = std::fs::read_to_string(&nav).unwrap();
        for _ in 0..2 {
            let fails = |rng: &mut Rng| {
                (0..3)
                    .map(|_| format!("{}R{}", rng.range(0, 2), if rng.coin() { "F" } else { "S" }))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let plan = format!(
                "@default_action = 1RS\n@default_condition = S\nFollowPath = 2RF, {}\nComputePathToPose = {}\n",
                fails(&mut rng),
                fails(&mut rng)
            );
            let s = common::planned(&xml, &plan, Some(&models)).expect("the navigator runs");
            ask_every_failure(&format!("{} with {plan}", nav.display()), &s, &mut f);
        }
    }
    eprintln!(
        "why at every failure: {} asked ({generated} on generated runs, {} on the Nav2 navigators); {} refused; {} naming a later event; root cause first in {} ({:.1} %), by the node's own kind in {}; {} explanations shown that a re-run disproved",
        f.asked,
        f.asked - generated,
        f.refused.len(),
        f.later.len(),
        f.leaf_first,
        100.0 * f.leaf_first as f64 / f.asked.max(1) as f64,
        f.by_design,
        f.disproved.len()
    );
    assert!(f.asked >= 1000, "{}", f.asked);
    assert!(
        f.refused.is_empty(),
        "{:#?}",
        &f.refused[..f.refused.len().min(10)]
    );
    assert!(
        f.later.is_empty(),
        "{:#?}",
        &f.later[..f.later.len().min(10)]
    );
    assert!(
        f.disproved.is_empty(),
        "{:#?}",
        &f.disproved[..f.disproved.len().min(10)]
    );
    assert!(
        f.leaf_first * 100 >= f.asked * 95,
        "{} of {}",
        f.leaf_first,
        f.asked
    );
}
