//! Every answer is a claim about the run (#39 item 6): on generated runs,
//! the Nav2 navigators with generated plans and a real BehaviorTree.CPP
//! patrol, each answer kind's claims are read back against the log, never
//! against the sentence expected: what happens next, what if X fails or
//! succeeds, which node repeats or retries, how often a node started, can
//! you X once the run has ended, and which recovery ran.

mod common;
#[path = "common/trees.rs"]
mod trees;

use btx::ask::{ask, Context};
use btx::causal::ahead::{ahead, Record};
use btx::model::Uid;
use btx::run::world::random::Rng;
use btx::run::Status;
use btx::session::{Moment, Session};
use btx::xml::LoadOptions;

/// The runs: generated trees, the Nav2 navigators with generated plans,
/// and the recorded patrol.
fn runs() -> Vec<(String, Session)> {
    let mut out = Vec::new();
    for seed in 0..120 {
        let c = trees::generate(seed);
        if let Some(s) = common::planned(&c.xml, &c.plan, None) {
            out.push((format!("generated {seed} ({}; {})", c.xml, c.plan), s));
        }
    }
    let mut rng = Rng::new(39);
    for nav in common::nav2_navigators() {
        let models = common::nav2_models_for(&nav);
        let xml = std::fs::read_to_string(&nav).unwrap();
        for k in 0..2 {
            let outcome = |rng: &mut Rng| {
                let r = rng.range(0, 3);
                let s = if rng.range(0, 2) == 0 { "F" } else { "S" };
                format!("{r}R{s}")
            };
            let follow: Vec<String> = (0..4).map(|_| outcome(&mut rng)).collect();
            let plan = format!(
                "@default_action = 1RS\n@default_condition = S\nFollowPath = {}\nComputePathToPose = {}\n",
                follow.join(", "),
                outcome(&mut rng)
            );
            match common::planned(&xml, &plan, Some(&models)) {
                Some(s) => out.push((format!("{} plan {k}: {plan}", nav.display()), s)),
                None => panic!("{}: the navigator did not run", nav.display()),
            }
        }
    }
    let patrol = btx::input::open(
        &common::fixture("logs/patrol_battery_drops.btlog"),
        &LoadOptions {
            run_tree: Some(common::fixture("answers/patrol-battery.xml")),
            ..LoadOptions::default()
        },
    )
    .unwrap();
    let btx::input::Input::Session(patrol) = patrol else {
        panic!("the patrol log is a run")
    };
    out.push(("patrol".into(), *patrol));
    out
}

fn cx<'a>(s: &'a Session, at: Moment) -> Context<'a> {
    Context {
        tree: &s.tree,
        session: Some(s),
        at: Some(s.at(at).unwrap()),
        tick: None,
        node: None,
        detail: Default::default(),
        last: Default::default(),
    }
}

/// The (uid, status) pairs a sentence claims, in order: "X (#3) fails".
fn claimed(text: &str) -> Vec<(Uid, Status)> {
    let mut out = Vec::new();
    for (i, _) in text.match_indices("(#") {
        let rest = &text[i + 2..];
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let Ok(u) = digits.parse::<Uid>() else {
            continue;
        };
        let after = &rest[digits.len()..];
        let status = if after.starts_with(") fails") {
            Status::Failure
        } else if after.starts_with(") succeeds") {
            Status::Success
        } else {
            continue;
        };
        out.push((u, status));
    }
    out
}

fn completes(s: Status) -> bool {
    matches!(s, Status::Success | Status::Failure)
}

/// "What if X fails / succeeds?", asked of every leaf outcome the run has:
/// each node the answer says ends, ends so in the log after that outcome,
/// in order; "I will Y next" is the next leaf the log calls; a loop that
/// "repeats" or "tries again" ticks the child again or ends as it must.
#[test]
fn what_if_answers_hold_at_every_outcome_in_the_log() {
    let (mut checked, mut wrong) = (0usize, Vec::new());
    for (name, s) in runs() {
        let tr = &s.index.transitions;
        let end = Moment {
            tick: s.index.ticks(),
            step: None,
        };
        let c = cx(&s, end);
        let mut asked: Vec<(Uid, Status)> = Vec::new();
        for t in tr.iter() {
            let leaf = s.tree.node(t.uid).kind.is_leaf() && s.tree.node(t.uid).builtin.is_none();
            if leaf && completes(t.status) && !asked.contains(&(t.uid, t.status)) {
                asked.push((t.uid, t.status));
            }
        }
        for (u, st) in asked {
            let word = if st == Status::Failure {
                "fails"
            } else {
                "succeeds"
            };
            let r = ask(&c, &format!("what if #{u} {word}?"));
            if !r.answered {
                continue;
            }
            let text = r.answer.clone();
            // Every outcome of u of that kind in the log.
            for (q, _) in tr
                .iter()
                .enumerate()
                .filter(|(_, t)| t.uid == u && t.status == st)
            {
                let after = &tr[q + 1..];
                checked += 1;
                let mut from = 0usize;
                for (v, vs) in claimed(&text).into_iter().skip(1) {
                    match after[from..]
                        .iter()
                        .position(|t| t.uid == v && completes(t.status))
                    {
                        Some(k) if after[from + k].status == vs => from += k + 1,
                        Some(k) => wrong.push(format!(
                            "{name}: {text} — but #{v} became {} at position {}",
                            after[from + k].status.as_str(),
                            q + 2 + from + k
                        )),
                        // The record ends first: nothing contradicts it.
                        None => break,
                    }
                }
                if text.contains(", I will ") {
                    let next = r.nodes.last().copied().unwrap();
                    let called = after
                        .iter()
                        .find(|t| s.tree.node(t.uid).kind.is_leaf() && t.status != Status::Idle);
                    if let Some(t) = called {
                        // A running leaf ticked again leaves no transition.
                        let running = tr[..=q]
                            .iter()
                            .rev()
                            .find(|x| x.uid == next)
                            .is_some_and(|x| x.status == Status::Running);
                        if t.uid != next && !running {
                            wrong.push(format!(
                                "{name}: {text} — but #{} was called next, at position {}",
                                t.uid,
                                q + 2 + after.iter().position(|x| std::ptr::eq(x, t)).unwrap(),
                            ));
                        }
                    }
                }
                if text.contains(" again (while") || text.contains(" (while it has cycles left)") {
                    // The loop node: the last node the answer names.
                    let lp = r.nodes[1];
                    let child = s.tree.node(lp).children[0];
                    let restarts = after.iter().position(|t| {
                        t.uid == child && t.prev == Status::Idle && t.status != Status::Idle
                    });
                    let ends = after
                        .iter()
                        .position(|t| t.uid == lp && completes(t.status));
                    let retry = text.contains(" again (while");
                    let fine = match (restarts, ends) {
                        (Some(a), Some(b)) if a < b => true,
                        (_, Some(b)) => {
                            // Out of attempts (cycles): it ends with that outcome.
                            after[b].status
                                == if retry {
                                    Status::Failure
                                } else {
                                    Status::Success
                                }
                        }
                        _ => true,
                    };
                    if !fine {
                        wrong.push(format!("{name}: {text} — but #{lp} ended otherwise"));
                    }
                }
            }
        }
    }
    eprintln!(
        "what if: {checked} outcomes checked, {} claims disproved",
        wrong.len()
    );
    assert!(checked >= 500, "{checked}");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// "What happens next?" at the end of every tick: the tree is run on from
/// the moment. Wherever the record's next tick gave the leaves the
/// outcomes the prediction gave them, the record is the prediction,
/// transition for transition; and where the answer says the run went
/// otherwise, the record shows that transition there.
#[test]
fn what_happens_next_is_what_the_tree_does_on_those_outcomes() {
    let (mut same, mut parted, mut wrong) = (0usize, 0usize, Vec::new());
    for (name, s) in runs() {
        let idx = &s.index;
        for tick in 1..idx.ticks() {
            let pos = idx.tick_range(tick).end as u32;
            if pos == 0 {
                continue;
            }
            let Ok(a) = ahead(&s, pos) else { continue };
            let span = &idx.transitions[pos as usize..idx.tick_range(a.tick).end];
            let leaves = |it: &mut dyn Iterator<Item = (Uid, Status)>| -> Vec<(Uid, Status)> {
                it.filter(|(u, st)| s.tree.node(*u).kind.is_leaf() && *st != Status::Idle)
                    .collect()
            };
            let rec = leaves(&mut span.iter().map(|t| (t.uid, t.status)));
            let pred = leaves(&mut a.steps.iter().map(|t| (t.uid, t.status)));
            match &a.record {
                Record::Same => {
                    same += 1;
                    if rec != pred {
                        wrong.push(format!("{name}: at {tick}, said the same, leaves differ"));
                    }
                }
                Record::Parted(Some(p)) => {
                    parted += 1;
                    let t = idx.transitions[idx.tick_range(p.tick).start + p.step as usize - 1];
                    if (t.uid, t.status) != (p.uid, p.status) {
                        wrong.push(format!(
                            "{name}: at {tick}, the record at {}:{} is not #{}",
                            p.tick, p.step, p.uid
                        ));
                    }
                    if rec == pred {
                        wrong.push(format!("{name}: at {tick}, the leaves did as predicted, and the tree did otherwise"));
                    }
                }
                _ => {}
            }
            // The sentence says each leaf's predicted outcome.
            let text = a.text(&s.tree);
            for (u, st) in claimed(&text) {
                if !a.steps.iter().any(|t| t.uid == u && t.status == st) {
                    wrong.push(format!("{name}: at {tick}: {text}"));
                }
            }
        }
    }
    eprintln!("what happens next: {same} ticks as predicted, {parted} where the run went otherwise, {} claims disproved", wrong.len());
    assert!(same >= 200 && parted >= 50, "{same} {parted}");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// "How often did X start?": a start is a node leaving IDLE, except just
/// after its own halt in the same tick (a RecoveryNode's IDLE → FAILURE);
/// and "Can you X?" once the root has ended is refused.
#[test]
fn starts_are_counted_as_the_log_shows_and_a_finished_run_takes_nothing() {
    let (mut checked, mut wrong) = (0usize, Vec::new());
    for (name, s) in runs() {
        let tr = &s.index.transitions;
        let end = Moment {
            tick: s.index.ticks(),
            step: None,
        };
        let c = cx(&s, end);
        for u in 1..=s.tree.len() as Uid {
            let mut starts = 0usize;
            let mut last: Option<(u32, Status, Status)> = None;
            for t in tr.iter().filter(|t| t.uid == u) {
                let after_halt = last.is_some_and(|(tick, prev, st)| {
                    tick == t.tick && prev == Status::Running && st == Status::Idle
                });
                // Leaving IDLE, or ticked again after it completed.
                if t.prev != Status::Running && t.status != Status::Idle && !after_halt {
                    starts += 1;
                }
                last = Some((t.tick, t.prev, t.status));
            }
            let r = ask(&c, &format!("how often did #{u} start?"));
            if !r.answered {
                continue;
            }
            checked += 1;
            let said = match &r.answer {
                a if a.contains(" never ") || a.contains("did not start") => 0,
                a if a.contains(" started once") => 1,
                a if a.contains(" started twice") => 2,
                a => a
                    .split(" started ")
                    .nth(1)
                    .and_then(|w| w.split(' ').next())
                    .and_then(|n| n.replace(',', "").parse().ok())
                    .unwrap_or(usize::MAX),
            };
            if said != starts {
                wrong.push(format!(
                    "{name}: #{u}: {} — the log shows {starts}: {:?}",
                    r.answer,
                    tr.iter().filter(|t| t.uid == u).collect::<Vec<_>>()
                ));
            }
        }
        let root = tr
            .iter()
            .rev()
            .find(|t| t.uid == s.tree.root().uid && completes(t.status));
        if root.is_some() {
            let leaf = (1..=s.tree.len() as Uid)
                .find(|&u| s.tree.node(u).kind.is_leaf())
                .unwrap();
            let r = ask(&c, &format!("can you {}?", s.tree.description(leaf)));
            if r.answered && !r.answer.starts_with("No") {
                wrong.push(format!("{name}: can you, after the end: {}", r.answer));
            }
        }
    }
    eprintln!(
        "how often: {checked} nodes checked, {} claims disproved",
        wrong.len()
    );
    assert!(checked >= 1000, "{checked}");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// "Which recovery ran?" at the end of each run: the handler it says
/// succeeded did, at that tick, and one it says tried first and failed
/// did fail after the first failure.
#[test]
fn the_recovery_said_is_the_one_the_log_shows() {
    let (mut checked, mut wrong) = (0usize, Vec::new());
    for (name, s) in runs() {
        let tr = &s.index.transitions;
        let c = cx(
            &s,
            Moment {
                tick: s.index.ticks(),
                step: None,
            },
        );
        let r = ask(&c, "which recovery ran?");
        let a = &r.answer;
        let Some(i) = a
            .find(") recovered")
            .or_else(|| a.find(") tried again and succeeded"))
            .or_else(|| a.find(") went on and succeeded"))
        else {
            continue;
        };
        checked += 1;
        let open = a[..i].rfind("(#").unwrap();
        let h: Uid = a[open + 2..i].parse().unwrap();
        let tick: u32 = a
            .split("succeeded at tick ")
            .nth(1)
            .and_then(|t| t.trim_end_matches('.').parse().ok())
            .unwrap();
        if !tr
            .iter()
            .any(|t| t.uid == h && t.tick == tick && t.status == Status::Success)
        {
            wrong.push(format!(
                "{name}: {a} — but #{h} did not succeed at tick {tick}"
            ));
        }
        for part in a.split("; ").filter(|p| p.contains(") first ")) {
            let g: Uid = part[part.find("(#").unwrap() + 2..part.find(") first").unwrap()]
                .parse()
                .unwrap();
            if !s.tree.is_ancestor(h, g)
                || !tr.iter().any(|t| t.uid == g && t.status == Status::Failure)
            {
                wrong.push(format!(
                    "{name}: {a} — but #{g} is not a handler below #{h} that failed"
                ));
            }
        }
    }
    eprintln!(
        "which recovery: {checked} runs checked, {} claims disproved",
        wrong.len()
    );
    assert!(checked >= 10, "{checked}");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The patrol of the issue, recorded by BehaviorTree.CPP 4.8: the answers
/// that were false, now as the log shows.
#[test]
fn the_patrols_answers_are_true() {
    let runs = runs();
    let s = &runs.last().unwrap().1;
    let at = |tick, step| Moment { tick, step };
    let c = cx(s, at(6, None));
    let say = |c: &Context, q: &str| ask(c, q).answer;
    assert_eq!(
        say(&c, "what if battery ok fails?"),
        "If battery ok (#7) fails, guarded patrol step (#4) fails, then patrol twice (#3) fails, so the task fails."
    );
    assert_eq!(
        say(&c, "why are you doing battery ok?"),
        "I check whether the battery is ok in order to run the guarded patrol step."
    );
    assert_eq!(
        say(&c, "what happens next?"),
        "Next, in tick 7, emergency stop pressed (#6) fails, battery ok (#7) succeeds and scan area (#8) keeps running (since 5:18). This assumes emergency stop pressed (#6) and battery ok (#7) answer as they last did and actions keep running. The run went otherwise: battery ok (#7) failed at 7:5."
    );
    let c = cx(s, at(7, None));
    assert_eq!(
        say(&c, "why was scan area halted?"),
        "Scan area (#8) was halted at 7:8 because battery ok (#7) became FAILURE at 7:5, so the ReactiveSequence guarded patrol step (#4) stopped ticking it."
    );
    assert!(say(&c, "can you scan the area?").starts_with("No, not now: the run had ended by then"));
    assert!(say(&c, "why did the patrol fail?")
        .contains("because battery ok (#7) returned FAILURE at 7:5"));
    assert_eq!(
        say(&c, "how often did scan area start?"),
        "Scan area (#8) started twice by the end of the run at tick 7 (at 2:9 and 5:18)."
    );
}

/// Faults and branches (#39 item 5): in the patrol the e-stop check under
/// its Inverter answers no in every tick as designed, and the battery
/// check's no fails the patrol; in Nav2's navigator FollowPath's failures
/// are faults, and GoalUpdated's and WouldA…RecoveryHelp's noes are
/// branches; in the kitting run, a grasp check after the grasp is a fault.
#[test]
fn faults_are_told_from_branches_taken() {
    use btx::explain::fault::is_fault;
    let said = |s: &Session| -> Vec<(String, bool)> {
        let mut out: Vec<(String, bool)> = Vec::new();
        for (i, t) in s.index.transitions.iter().enumerate() {
            if t.status == Status::Failure && s.tree.node(t.uid).kind.is_leaf() {
                let e = (
                    s.tree.description(t.uid).to_string(),
                    is_fault(&s.tree, &s.index, i as u32 + 1),
                );
                if !out.contains(&e) {
                    out.push(e);
                }
            }
        }
        out
    };
    let runs = runs();
    let patrol = &runs.last().unwrap().1;
    assert_eq!(
        said(patrol),
        [
            ("emergency stop pressed".to_string(), false),
            ("battery ok".to_string(), true)
        ]
    );
    let nav =
        common::fixture("realworld/nav2-a3a9704/navigate_to_pose_w_replanning_and_recovery.xml");
    let models = common::fixture("realworld/nav2-a3a9704/nav2_tree_nodes.xml");
    let plan = "@default_action = 1RS\n@default_condition = S\nFollowPath = 2RF, 2RF, 3RS\nGoalUpdated = F\nWouldAControllerRecoveryHelp = F\n";
    let s = common::planned(&std::fs::read_to_string(&nav).unwrap(), plan, Some(&models)).unwrap();
    let nav_said = said(&s);
    assert!(
        nav_said.contains(&("FollowPath".to_string(), true)),
        "{nav_said:?}"
    );
    assert!(
        nav_said.contains(&("GoalUpdated".to_string(), false)),
        "{nav_said:?}"
    );
    assert!(
        nav_said.contains(&("WouldAControllerRecoveryHelp".to_string(), false)),
        "{nav_said:?}"
    );
    assert!(
        nav_said.iter().all(|(n, f)| *f == (n == "FollowPath")),
        "{nav_said:?}"
    );
    let kit = btx::input::open(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sessions/kitting-grasp-check-fails-first.jsonl"),
        &LoadOptions::default(),
    )
    .unwrap();
    let kit = kit.session().unwrap();
    assert!(
        said(kit).contains(&("check if grasped".to_string(), true)),
        "{:?}",
        said(kit)
    );
}

/// A leaf's own outcome says what it read and wrote, where the run holds
/// the blackboard (#39 item 4): look at chuck read the pose detect chuck
/// wrote, and detect chuck wrote it.
#[test]
fn a_leafs_call_says_what_it_read_and_wrote() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = btx::input::open(
        &root.join("sessions/kitting-nominal.jsonl"),
        &LoadOptions::default(),
    )
    .unwrap();
    let s = input.session().unwrap();
    let c = cx(
        s,
        Moment {
            tick: 46,
            step: None,
        },
    );
    let look = ask(&c, "why did look at chuck succeed?").answer;
    assert!(
        look.contains("It read object pose = \"value of output from 'detect chuck'\"."),
        "{look}"
    );
    let detect = ask(&c, "why did #12 succeed?").answer;
    assert!(
        detect.contains("It wrote object pose = \"value of output from 'detect chuck'\"."),
        "{detect}"
    );
}
