//! Expected vs actual: `btx diff` on trees, runs and fleets (Han et al.
//! §7.2.1, Fig. 14), run comparison with `--why`, and the edit script's
//! optimality against a plain dynamic programme.

mod common;

use btx::diff::align::{distance, edits, lcs, Op};
use common::btx;
use proptest::prelude::*;
use serde_json::Value;

fn json(args: &[&str]) -> Value {
    let (ok, out, err) = btx(args);
    assert!(ok, "{err}");
    serde_json::from_str(&out).unwrap()
}

/// The taxi divergence of Han Fig. 14: the optimal policy's detour through
/// the rightmost column (one more move right and one more move left on each
/// leg) against the person's path through the toll.
const TAXI: &str = r#"A  trees/taxi-expected.xml  (a tree: each subgoal's actions in tree order)
B  trees/taxi.xml  (a tree: each subgoal's actions in tree order)

go pick up passenger: edit distance 2, LCS 5 (A 5 actions, B 7 actions): 2 inserted
    #5 move right            #5 move right
    #6 move right            #6 move right
  +                          #7 move right
    #7 move up               #8 move up
    #8 move up               #9 move up
  +                          #10 move left
    #9 pick up passenger     #11 pick up passenger

go drop off passenger: edit distance 2, LCS 5 (A 5 actions, B 7 actions): 2 inserted
  +                          #15 move right
    #13 move down            #16 move down
    #14 move down            #17 move down
    #15 move left            #18 move left
    #16 move left            #19 move left
  +                          #20 move left
    #17 drop off passenger   #21 drop off passenger

In all: edit distance 4, LCS 10. First divergence: go pick up passenger: B's 3rd action, "move right" (#7), is not in A.
"#;

#[test]
fn the_taxi_detour_is_the_divergence() {
    let (ok, out, err) = btx(&["diff", "trees/taxi-expected.xml", "trees/taxi.xml"]);
    assert!(ok, "{err}");
    assert_eq!(out, TAXI);
}

#[test]
fn the_taxi_runs_diverge_as_their_trees_do() {
    let v = json(&[
        "diff",
        "sessions/taxi-expected.jsonl",
        "sessions/taxi.jsonl",
        "--format",
        "json",
    ]);
    assert_eq!(
        (v["distance"].as_u64(), v["lcs"].as_u64()),
        (Some(4), Some(10))
    );
    assert_eq!(v["a"]["kind"], "run");
    let inserted = |i: usize| -> Vec<(u64, String, u64)> {
        v["sections"][i]["inserted"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                (
                    s["uid"].as_u64().unwrap(),
                    s["name"].as_str().unwrap().to_string(),
                    s["tick"].as_u64().unwrap(),
                )
            })
            .collect()
    };
    assert_eq!(v["sections"][1]["subgoal"], "go pick up passenger");
    assert_eq!(
        inserted(1),
        [(7, "move right".into(), 3), (10, "move left".into(), 6)]
    );
    assert_eq!(
        inserted(2),
        [(15, "move right".into(), 8), (20, "move left".into(), 13)]
    );
}

#[test]
fn identical_inputs_give_an_empty_diff() {
    for (a, b) in [
        ("trees/taxi.xml", "trees/taxi.xml"),
        (
            "sessions/kitting-nominal.jsonl",
            "sessions/kitting-nominal.jsonl",
        ),
        // A run that does what its tree says, in tree order.
        ("trees/taxi.xml", "sessions/taxi.jsonl"),
    ] {
        let v = json(&["diff", a, b, "--format", "json"]);
        assert_eq!(v["identical"], true, "{a} {b}");
        assert_eq!(v["distance"], 0);
        assert!(v["first_divergence"].is_null());
        for s in v["sections"].as_array().unwrap() {
            assert!(s["edits"]
                .as_array()
                .unwrap()
                .iter()
                .all(|e| e["op"] == "same"));
        }
        let (ok, out, _) = btx(&["diff", a, b, "--exit-code"]);
        assert!(ok);
        assert!(
            out.contains("No divergence: every subgoal has the same"),
            "{out}"
        );
    }
    let (ok, _, _) = btx(&[
        "diff",
        "trees/taxi.xml",
        "trees/taxi-expected.xml",
        "--exit-code",
    ]);
    assert!(!ok, "--exit-code reports a divergence with status 1");
}

#[test]
fn a_retry_shows_as_the_inserted_attempt() {
    let v = json(&[
        "diff",
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-lookat-fails-once.jsonl",
        "--format",
        "json",
    ]);
    let s = &v["sections"][1];
    assert_eq!(s["subgoal"], "go insert large gear");
    assert_eq!(
        (s["distance"].as_u64(), s["lcs"].as_u64()),
        (Some(8), Some(15))
    );
    let first = &s["inserted"][0];
    assert_eq!(
        (
            first["uid"].as_u64(),
            &first["outcome"],
            first["tick"].as_u64()
        ),
        (Some(18), &Value::from("FAILURE"), Some(9))
    );
    // The other subgoals are untouched.
    for i in 2..4 {
        assert_eq!(
            v["sections"][i]["distance"], 0,
            "{}",
            v["sections"][i]["subgoal"]
        );
    }
}

#[test]
fn why_two_runs_diverged_is_asked_in_the_second_run() {
    let (ok, out, err) = btx(&[
        "diff",
        "sessions/serial-recall.jsonl",
        "sessions/serial-recall-no-memory.jsonl",
        "--why",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains(
        "The runs part ways at transition 35 (moment 1:35): RepeatOrEnd (#24) chose EndThisSequence in B and RepeatThisSequence in A."
    ), "{out}");
    assert!(out.contains(
        "RepeatOrEnd chose EndThisSequence because UserMemory was 0.0. If UserMemory had been between 0.1 and 0.9, RepeatOrEnd would have chosen RepeatThisSequence."
    ), "{out}");
    let v = json(&[
        "diff",
        "sessions/serial-recall.jsonl",
        "sessions/serial-recall-no-memory.jsonl",
        "--why",
        "--format",
        "json",
    ]);
    assert_eq!(v["why"]["moment"], "1:35");
    assert_eq!(v["why"]["transition"], 35);
    assert!(!v["why"]["answer"]["explanations"]
        .as_array()
        .unwrap()
        .is_empty());
    // Without a domain the failing leaf's outcome is the plan's: said so.
    let (ok, out, _) = btx(&[
        "diff",
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-lookat-fails-once.jsonl",
        "--why",
    ]);
    assert!(ok);
    assert!(
        out.contains("look at chuck (#18) became FAILURE in B and SUCCESS in A"),
        "{out}"
    );
    assert!(
        out.contains("Without a domain file, what look at chuck returns is given by the run"),
        "{out}"
    );
    // The same run twice does not diverge.
    let (ok, out, _) = btx(&[
        "diff",
        "sessions/taxi.jsonl",
        "sessions/taxi.jsonl",
        "--why",
    ]);
    assert!(ok);
    assert!(
        out.ends_with("The runs make the same transitions: they do not diverge.\n"),
        "{out}"
    );
}

#[test]
fn why_needs_two_runs_of_one_tree() {
    let (ok, _, err) = btx(&["diff", "trees/taxi.xml", "trees/taxi.xml", "--why"]);
    assert!(!ok);
    assert!(err.contains("give two sessions or logs"), "{err}");
    let (ok, _, err) = btx(&[
        "diff",
        "sessions/taxi-expected.jsonl",
        "sessions/taxi.jsonl",
        "--why",
    ]);
    assert!(!ok);
    assert!(err.contains("ran different trees"), "{err}");
    let (ok, _, err) = btx(&[
        "diff",
        "sessions/taxi.jsonl",
        "sessions/taxi.jsonl",
        "sessions/taxi.jsonl",
        "--why",
    ]);
    assert!(!ok);
    assert!(err.contains("--why compares two runs"), "{err}");
    let (ok, _, err) = btx(&["diff", "trees/taxi.xml", "trees/nope.xml"]);
    assert!(!ok);
    assert!(err.contains("trees/nope.xml"), "{err}");
}

#[test]
fn a_fleet_is_tabulated_per_subgoal() {
    let (ok, out, err) = btx(&[
        "diff",
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-lookat-fails-once.jsonl",
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-grasp-check-fails-first.jsonl",
    ]);
    assert!(ok, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "Reference: sessions/kitting-nominal.jsonl");
    let row = |name: &str| {
        lines
            .iter()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no row {name} in\n{out}"))
            .split("  ")
            .filter(|c| !c.trim().is_empty())
            .map(|c| c.trim().to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(
        row("go insert large gear"),
        ["go insert large gear", "8 (+8)", "=", "="]
    );
    assert_eq!(row("go pick screw")[2], "=");
    assert_ne!(row("go pick screw")[3], "=");
    assert!(
        out.contains("runs that do what the reference does: 1 of 3"),
        "{out}"
    );
    assert!(out.contains("kitting-lookat-fails-once.jsonl: first divergence: go insert large gear: the run's 8th action, \"look at chuck\" (#18, tick 9, FAILURE), is not in the reference"), "{out}");
    assert!(
        out.contains("go insert large gear: 1 of 3 runs diverge"),
        "{out}"
    );
    let v = json(&[
        "diff",
        "trees/taxi-expected.xml",
        "trees/taxi.xml",
        "sessions/taxi.jsonl",
        "sessions/taxi-expected.jsonl",
        "--format",
        "json",
    ]);
    let d: Vec<u64> = v["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["distance"].as_u64().unwrap())
        .collect();
    assert_eq!(d, [4, 4, 0]);
}

#[test]
fn the_shipped_comparison_sessions_are_what_their_worlds_give() {
    let dir = tempfile::tempdir().unwrap();
    for (args, shipped) in [
        (
            vec!["run", "trees/taxi-expected.xml", "--world", "taxi"],
            "sessions/taxi-expected.jsonl",
        ),
        (
            vec![
                "run",
                "trees/serial-recall.xml",
                "--domain",
                "trees/serial-recall.domain.toml",
                "--set",
                "UserMemory=0.0",
            ],
            "sessions/serial-recall-no-memory.jsonl",
        ),
    ] {
        let out = dir.path().join(shipped.replace('/', "_"));
        let mut a = args.clone();
        a.extend(["--out", out.to_str().unwrap()]);
        let (ok, _, err) = btx(&a);
        assert!(ok, "{err}");
        let fresh = btx::session::Session::load(&out).unwrap();
        let old = btx::session::Session::load(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(shipped),
        )
        .unwrap();
        assert_eq!(
            fresh.index.transitions, old.index.transitions,
            "regenerate {shipped} (see docs/formats.md)"
        );
    }
}

#[test]
fn set_names_what_it_cannot_set() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let run = |set: &str| {
        btx(&[
            "run",
            "trees/serial-recall.xml",
            "--domain",
            "trees/serial-recall.domain.toml",
            "--set",
            set,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let (ok, _, err) = run("UserConfusion=1");
    assert!(!ok);
    assert!(
        err.contains("it is computed from UserMemory, SequenceComplexity"),
        "{err}"
    );
    let (ok, _, err) = run("UserMemory=7");
    assert!(!ok);
    assert!(
        err.contains("7 is outside its range: a number from 0.0 to 1.0"),
        "{err}"
    );
    let (ok, _, err) = run("Nope=1");
    assert!(!ok);
    assert!(err.contains("the domain has no such variable"), "{err}");
    assert!(
        !out.exists(),
        "nothing is written when the run cannot start"
    );
}

/// An edit script that walks both sequences in order, keeps equal items
/// and changes only different ones.
fn valid_script(e: &[btx::diff::Edit], a: &[u8], b: &[u8]) -> Result<(), TestCaseError> {
    let left: Vec<u8> = e.iter().filter_map(|x| x.a.map(|i| a[i])).collect();
    let right: Vec<u8> = e.iter().filter_map(|x| x.b.map(|i| b[i])).collect();
    prop_assert_eq!(&left, &a);
    prop_assert_eq!(&right, &b);
    for x in e {
        match x.op {
            Op::Same => prop_assert_eq!(a[x.a.unwrap()], b[x.b.unwrap()]),
            Op::Changed => prop_assert_ne!(a[x.a.unwrap()], b[x.b.unwrap()]),
            Op::Inserted => prop_assert!(x.a.is_none() && x.b.is_some()),
            Op::Deleted => prop_assert!(x.a.is_some() && x.b.is_none()),
        }
    }
    Ok(())
}

/// Insertions plus deletions, by the textbook table.
fn dp_distance(a: &[u8], b: &[u8]) -> usize {
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    d[0] = (0..=b.len()).collect();
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            d[i][j] = if a[i - 1] == b[j - 1] {
                d[i - 1][j - 1]
            } else {
                1 + d[i - 1][j].min(d[i][j - 1])
            };
        }
    }
    d[a.len()][b.len()]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn runs_aligned_unit_by_unit_give_a_valid_script_exact_when_short(
        a in prop::collection::vec(0u8..4, 0..60),
        b in prop::collection::vec(0u8..4, 0..60),
        ua in 1usize..9,
        ub in 1usize..9,
        max in 0usize..130,
    ) {
        // #31 item 2: long runs are aligned run of the root by run of the
        // root (here: units of `ua` and `ub` items), then item by item; up
        // to `max` items together, exactly.
        let unit = move |first: bool, i: usize| (i / if first { ua } else { ub }) as u64;
        let e = btx::diff::align::edits_by_units_within(&a, &b, &[&unit], max);
        valid_script(&e, &a, &b)?;
        let exact = dp_distance(&a, &b);
        prop_assert!(distance(&e) >= exact);
        if a.len() + b.len() <= max {
            prop_assert_eq!(distance(&e), exact);
        }
        // The first divergence is a plain LCS's: where the runs stop
        // being the same, item for item.
        let first = |e: &[btx::diff::Edit]| e.iter().position(|x| x.op != Op::Same);
        prop_assert_eq!(first(&e), first(&edits(&a, &b)));
        // A run against itself (the same units) is the same throughout.
        let own = move |_: bool, i: usize| (i / ua) as u64;
        let same = btx::diff::align::edits_by_units_within(&a, &a, &[&own], max);
        prop_assert!(same.iter().all(|x| x.op == Op::Same));
    }

    #[test]
    fn the_edit_distance_is_the_dynamic_programmes(
        a in prop::collection::vec(0u8..4, 0..40),
        b in prop::collection::vec(0u8..4, 0..40),
    ) {
        let e = edits(&a, &b);
        prop_assert_eq!(distance(&e), dp_distance(&a, &b));
        prop_assert_eq!(lcs(&e), (a.len() + b.len() - dp_distance(&a, &b)) / 2);
        valid_script(&e, &a, &b)?;
    }
}

#[test]
fn a_robots_log_and_our_run_of_its_plan_do_the_same() {
    // The recorded tree names two subgoals "first screw"; they pair in place.
    let v = json(&[
        "diff",
        "tests/fixtures/logs/kitting_lookat_fails_once.btlog",
        "sessions/kitting-lookat-fails-once.jsonl",
        "--format",
        "json",
    ]);
    assert_eq!(v["identical"], true);
    assert_eq!(
        v["sections"][2]["subgoal"],
        "go pick first screw → go pick screw"
    );
    assert_eq!(v["lcs"], 50);
    // And the log of the nominal run parts from the failing run where
    // look at chuck fails.
    let (ok, out, err) = btx(&[
        "diff",
        "tests/fixtures/logs/kitting_nominal.btlog",
        "sessions/kitting-lookat-fails-once.jsonl",
        "--why",
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("at transition 32 (moment 10:1): look at chuck (#18) became FAILURE in B and SUCCESS in A"),
        "{out}"
    );
}

/// The runs of the kitting plans, recorded by BehaviorTree.CPP 4.10
/// (tests/fixtures/logs, from ../shared/fixtures/btcpp).
const KITTING: [&str; 4] = [
    "tests/fixtures/logs/kitting_nominal.btlog",
    "tests/fixtures/logs/kitting_lookat_fails_once.btlog",
    "tests/fixtures/logs/kitting_grasp_check_fails_first.btlog",
    "tests/fixtures/logs/kitting_detect_chuck_always_fails.btlog",
];

/// A run's transitions as `btx log` gives them: (uid, prev, status).
fn transitions(run: &str) -> Vec<(u64, String, String)> {
    let v = json(&["log", run, "--format", "json"]);
    v["transitions"]
        .as_array()
        .expect("a list of transitions")
        .iter()
        .map(|t| {
            (
                t["uid"].as_u64().unwrap(),
                t["prev"].as_str().unwrap().to_string(),
                t["status"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

#[test]
fn every_pair_of_runs_parts_at_one_place_in_diff_why_and_the_side_by_side() {
    // #27 item 4: `btx diff` named one first divergence, `--why` another.
    // For every ordered pair of the kitting runs: where they part is the
    // first transition the two logs differ at (read with `btx log`, apart
    // from btx diff); the step marked as the parting holds it; `--why`
    // names that transition; the side-by-side view's first `d` selects
    // that step; and no "changed" pair is two different leaves.
    for a in KITTING {
        for b in KITTING {
            let (ta, tb) = (transitions(a), transitions(b));
            let first = ta.iter().zip(&tb).position(|(x, y)| x != y);
            let first = first.or((ta.len() != tb.len()).then(|| ta.len().min(tb.len())));
            let v = json(&["diff", a, b, "--format", "json"]);
            let Some(at) = first else {
                assert!(v["parting"].is_null(), "{a} {b}");
                assert_eq!(v["identical"], true);
                continue;
            };
            let p = &v["parting"];
            assert_eq!(p["transition"].as_u64(), Some(at as u64 + 1), "{a} {b}");
            let mut parting = Vec::new();
            for s in v["sections"].as_array().unwrap() {
                for e in s["edits"].as_array().unwrap() {
                    if e["role"] == "parting" {
                        parting.push(e.clone());
                    }
                    if e["op"] == "changed" {
                        assert_eq!(e["a"]["uid"], e["b"]["uid"], "{a} {b}: {e}");
                    }
                    if e["op"] == "same" {
                        assert_eq!(e["role"], "same");
                    }
                }
            }
            assert_eq!(parting.len(), 1, "{a} {b}");
            // Its step started at or before the transition where they
            // part, in the tick of it or before (a leaf RUNNING over ticks).
            let step = if parting[0]["b"].is_null() {
                &parting[0]["a"]
            } else {
                &parting[0]["b"]
            };
            let moment_tick: u64 = p["moment"]
                .as_str()
                .unwrap()
                .split(':')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!(
                step["tick"].as_u64().unwrap() <= moment_tick,
                "{a} {b}: {step}"
            );
            let text = format!("The runs part ways {}.", p["text"].as_str().unwrap());
            assert!(
                v["first_divergence"]["text"].is_string(),
                "{a} {b}: the first divergence is the parting step"
            );
            // --why asks at that same transition.
            let w = json(&["diff", a, b, "--why", "--format", "json"]);
            assert_eq!(w["why"]["transition"], p["transition"], "{a} {b}");
            let (ok, out, _) = btx(&["diff", a, b, "--why"]);
            assert!(ok);
            assert!(out.contains(&text), "{a} {b}: {out}");
            assert_eq!(out.matches("part ways at transition").count(), 1, "{out}");
            // The side-by-side view's first divergence is that step.
            let mut app = btx::tui::open_diff(
                std::path::Path::new(a),
                std::path::Path::new(b),
                &Default::default(),
            )
            .unwrap();
            app.update(btx::tui::keymap::Action::NextDivergence);
            let said = app.shared.message.clone().unwrap();
            assert!(
                said.contains(" (the runs part ways here")
                    || said.contains(" (the first to differ after"),
                "{said}"
            );
            assert!(
                said.ends_with(v["first_divergence"]["text"].as_str().unwrap()),
                "{said}"
            );
        }
    }
}

#[test]
fn steps_made_only_because_the_runs_parted_follow_from_it() {
    // Nominal against "look at chuck fails once": look at chuck's failure
    // is where they part; the retry it caused (reset arm, then the detect
    // and insert steps again) follows from it, and is no divergence of
    // its own: the side-by-side view marks ≠ only look at chuck.
    let (a, b) = (KITTING[0], KITTING[1]);
    let (ok, out, _) = btx(&["diff", a, b]);
    assert!(ok);
    let marked: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("> +") || l.starts_with("· "))
        .collect();
    assert_eq!(marked.len(), 8, "{out}");
    assert!(marked[0].starts_with("> +") && marked[0].ends_with("t9 #18 look at chuck (FAILURE)"));
    assert!(marked[1].ends_with("t10 #27 retreat arm"), "{out}");
    assert!(marked[1..].iter().all(|l| l.starts_with("· +")));
    assert!(
        out.contains(
            "After it, 7 steps follow from where they part, and none diverges of its own."
        ),
        "{out}"
    );
    let app = btx::tui::open_diff(
        std::path::Path::new(a),
        std::path::Path::new(b),
        &Default::default(),
    )
    .unwrap();
    let mut divergent: Vec<_> = app.shared.b.divergent.iter().copied().collect();
    divergent.sort();
    assert_eq!(divergent, [18]);
    let mut following: Vec<_> = app.shared.b.following.iter().copied().collect();
    following.sort();
    assert_eq!(following, [10, 11, 12, 15, 16, 17, 27]);
    assert_eq!(app.shared.diff.divergences().len(), 1);
}

/// #39 item 9: a long loop that goes wrong once, against the same loop,
/// is aligned exactly (Myers' cost is length × distance, and the distance
/// is small), and gives the distance the short loops give.
#[test]
fn a_long_loop_that_goes_wrong_once_has_its_exact_distance() {
    let dir = tempfile::tempdir().unwrap();
    let distance = |cycles: usize| -> (u64, bool) {
        let p = |f: &str| {
            dir.path()
                .join(format!("{cycles}-{f}"))
                .to_str()
                .unwrap()
                .to_string()
        };
        let xml = format!(
            r#"<root BTCPP_format="4" main_tree_to_execute="Loop">
  <BehaviorTree ID="Loop">
    <Repeat num_cycles="{cycles}" name="loop">
      <Sequence name="cycle">
        <Fallback name="look">
          <LookAt name="look at chuck"/>
          <Relocalise name="relocalise"/>
        </Fallback>
        <Grasp name="grasp"/>
      </Sequence>
    </Repeat>
  </BehaviorTree>
  <TreeNodesModel>
    <Action ID="LookAt"/><Action ID="Relocalise"/><Action ID="Grasp"/>
  </TreeNodesModel>
</root>"#
        );
        std::fs::write(p("loop.xml"), xml).unwrap();
        std::fs::write(p("a.plan"), "look at chuck = 1RS\ngrasp = 1RS\n").unwrap();
        // Look at chuck fails once, half way through.
        let looks = vec!["1RS"; cycles / 2].join(", ");
        std::fs::write(
            p("b.plan"),
            format!("look at chuck = {looks}, 1RF, 1RS\ngrasp = 1RS\n"),
        )
        .unwrap();
        for run in ["a", "b"] {
            let (ok, _, err) = btx(&[
                "run",
                &p("loop.xml"),
                "--plan",
                &p(&format!("{run}.plan")),
                "--out",
                &p(&format!("{run}.jsonl")),
                "--max-ticks",
                "1000000",
            ]);
            assert!(ok, "{err}");
        }
        let d = json(&["diff", &p("a.jsonl"), &p("b.jsonl"), "--format", "json"]);
        let exact = d["sections"]
            .as_array()
            .unwrap()
            .iter()
            .all(|s| s["exact"] == true);
        (d["distance"].as_u64().unwrap(), exact)
    };
    // 10 cycles are short enough for any alignment; 4,000 cycles (8,001
    // actions a side) were aligned by units and labelled "at most".
    assert_eq!(distance(10), (3, true));
    assert_eq!(distance(4_000), (3, true));
}

/// #39 item 5: two runs that end apart lead with what decided the outcome,
/// not with a harmless retry that came first: here a drive that failed
/// once and was retried, then the battery check that failed the task.
#[test]
fn what_decided_the_outcome_leads_over_a_harmless_retry() {
    let dir = tempfile::tempdir().unwrap();
    let p = |f: &str| dir.path().join(f).to_str().unwrap().to_string();
    std::fs::write(
        p("t.xml"),
        r#"<root BTCPP_format="4" main_tree_to_execute="Task">
  <BehaviorTree ID="Task">
    <Sequence name="deliver">
      <RetryUntilSuccessful num_attempts="3"><Move name="drive to shelf"/></RetryUntilSuccessful>
      <Pick name="pick parcel"/>
      <Check name="battery ok"/>
      <Move name="drive to door"/>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Move"/><Action ID="Pick"/><Condition ID="Check"/></TreeNodesModel>
</root>"#,
    )
    .unwrap();
    std::fs::write(
        p("a.plan"),
        "@default_action = 1RS\n@default_condition = S\n",
    )
    .unwrap();
    std::fs::write(
        p("b.plan"),
        "@default_action = 1RS\n@default_condition = S\ndrive to shelf = 1RF, 1RS\nbattery ok = F\n",
    )
    .unwrap();
    for run in ["a", "b"] {
        let (ok, _, err) = btx(&[
            "run",
            &p("t.xml"),
            "--plan",
            &p(&format!("{run}.plan")),
            "--out",
            &p(&format!("{run}.jsonl")),
        ]);
        assert!(ok, "{err}");
    }
    let (_, out, _) = btx(&["diff", &p("a.jsonl"), &p("b.jsonl")]);
    let summary = out.lines().last().unwrap();
    assert!(
        summary.starts_with("In all: edit distance 4, LCS 2. What decided the outcome: deliver: A's 3rd action, \"battery ok\" (#5, tick 3), is \"battery ok\" (#5, tick 4, FAILURE) in B. The runs part ways"),
        "{summary}"
    );
    let d = json(&["diff", &p("a.jsonl"), &p("b.jsonl"), "--format", "json"]);
    assert_eq!(d["decisive"]["edit"], 3, "{d}");
    assert_eq!(d["first_divergence"]["edit"], 0, "{d}");
}
