//! Domain files: Love et al.'s domain knowledge, run by the executor.

mod common;
use btx::run::domain::{Domain, DomainLeaves};
use btx::run::RunOptions;
use btx::session::record::{record, RecordError, RunRequest};
use btx::session::{Moment, Session, Source};
use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn case_study_with(edit: impl Fn(&str) -> String) -> Result<Session, String> {
    let text = edit(&std::fs::read_to_string(root().join("trees/case-study.domain.toml")).unwrap());
    let dir = tempfile::tempdir().unwrap();
    let dpath = dir.path().join("d.toml");
    std::fs::write(&dpath, &text).unwrap();
    let d = Arc::new(Domain::load(&dpath).map_err(|e| e.to_string())?);
    let tree = load(&shipped("case-study.xml"));
    let leaves = DomainLeaves::new(d, &tree).map_err(|e| e.to_string())?;
    let out = dir.path().join("s.jsonl");
    let req = RunRequest {
        tree: &tree,
        tree_file: None,
        source: Source {
            kind: "domain".into(),
            path: None,
            text: Some(text),
            name: None,
        },
        seed: Some(0),
        max_ticks: 10,
        options: RunOptions::default(),
        ask: None,
        out: &out,
    };
    match record(req, leaves) {
        Ok(_) => Ok(Session::load(&out).unwrap()),
        Err(RecordError::Script(e, _)) => Err(e.to_string()),
        Err(e) => Err(format!("{e:?}")),
    }
}

fn var(s: &Session, at: &str, name: &str) -> Value {
    let view = s.at(Moment::parse(at).unwrap()).unwrap();
    view.entry(&btx::run::blackboard::EntryId {
        scope: 0,
        key: name.into(),
    })
    .cloned()
    .unwrap()
}

#[test]
fn the_case_study_runs_as_in_the_paper() {
    let s = case_study_with(|t| t.to_string()).unwrap();
    let t = &s.index.transitions;
    // L0 fails, so the Sequence fails, L2 chooses Action2 and succeeds, the root succeeds.
    let statuses: Vec<(u32, String)> = t.iter().map(|t| (t.uid, t.status.to_string())).collect();
    assert_eq!(statuses[2], (3, "FAILURE".into()));
    assert_eq!(statuses[4], (2, "FAILURE".into()));
    assert_eq!(statuses[5], (5, "SUCCESS".into()));
    assert_eq!(statuses[8], (1, "SUCCESS".into()));
    assert!(t.iter().all(|t| t.uid != 4), "L1 never runs");
    assert_eq!(s.index.transition_decision(5), Some("Action2"));
    // Before the tick X_d = !X_b = true; after L2, X_b = true and X_d = false.
    assert_eq!(var(&s, "1:0", "X_d"), Value::Bool(true));
    assert_eq!(var(&s, "1:0", "X_c"), Value::Bool(false));
    assert_eq!(var(&s, "1", "X_b"), Value::Bool(true));
    assert_eq!(var(&s, "1", "X_d"), Value::Bool(false));
}

#[test]
fn the_shipped_case_study_session_is_current() {
    let fresh = case_study_with(|t| t.to_string()).unwrap();
    let shipped = Session::load(&root().join("sessions/case-study.jsonl")).unwrap();
    assert_eq!(fresh.index.transitions, shipped.index.transitions);
}

#[test]
fn a_changed_state_changes_the_run() {
    // With X_a true, L0 succeeds and L1 chooses Action0.
    let s = case_study_with(|t| t.replacen("initial = false", "initial = true", 1)).unwrap();
    let l1 = s
        .index
        .transitions
        .iter()
        .position(|t| t.uid == 4 && t.status == btx::run::Status::Success)
        .unwrap();
    assert_eq!(s.index.transition_decision(l1), Some("Action0"));
}

#[test]
fn a_runaway_script_is_a_located_error() {
    let e =
        case_study_with(|t| t.replace("status = \"SUCCESS\"", "status = \"\"\"\nloop { }\n\"\"\""))
            .err()
            .expect("should fail");
    assert!(
        e.contains("d.toml:") && e.contains("status of L2: Too many operations"),
        "{e}"
    );
}

/// The domain's `functions` are run (and remembered) outside the script
/// that calls them: a loop across calls must still stop.
#[test]
fn operations_are_counted_across_function_calls() {
    let with_functions = |functions: &str, status: &str| {
        case_study_with(|t| {
            t.replace(
                "name = \"Love et al. case study\"",
                &format!(
                    "name = \"Love et al. case study\"\nfunctions = \"\"\"\n{functions}\n\"\"\""
                ),
            )
            .replace(
                "status = \"SUCCESS\"",
                &format!("status = \"\"\"\n{status}\n\"\"\""),
            )
        })
    };
    let e = with_functions("fn spin() { loop { } }", "spin()")
        .err()
        .expect("should fail");
    assert!(
        e.contains("status of L2") && e.contains("Too many operations"),
        "{e}"
    );
    // Each call stays under the limit; together they do not.
    let e = with_functions(
        "fn busy(n) { let i = 0; while i < 300000 { i += 1; } n }",
        "let s = 0; for k in 0..20 { s += busy(k); } SUCCESS",
    )
    .err()
    .expect("should fail");
    assert!(
        e.contains("status of L2") && e.contains("Too many operations"),
        "{e}"
    );
    // A function called with the same arguments again gives the same result.
    let s = with_functions(
        "fn twice(x) { x * 2 }",
        "if twice(2) == 4 && twice(2) == 4 { SUCCESS } else { FAILURE }",
    )
    .unwrap();
    let fresh = case_study_with(|t| t.to_string()).unwrap();
    assert_eq!(s.index.transitions, fresh.index.transitions);
    // `eval` could read a variable without naming it (see Script::reads).
    let e = with_functions("", "eval(\"SUCCESS\")")
        .err()
        .expect("should fail");
    assert!(e.contains("status of L2"), "{e}");
}

#[test]
fn script_and_file_errors_are_located() {
    let e = case_study_with(|t| t.replace("{ FAILURE }\"", "{ FAILURE \""))
        .err()
        .expect("should fail");
    assert!(
        e.contains("d.toml:27:") && e.contains("status of L0"),
        "{e}"
    );
    let e = case_study_with(|t| t.replace("inputs = [\"X_d\"]", "inputs = [\"X_e\"]"))
        .err()
        .expect("should fail");
    assert!(e.contains("input \"X_e\" is not a state variable"), "{e}");
    let e = case_study_with(|t| t.replace("{ #{ X_b: true } } else", "{ #{ X_a: true } } else"))
        .err()
        .expect("should fail");
    assert!(
        e.contains("sets \"X_a\", which is not one of its outputs"),
        "{e}"
    );
    let e = case_study_with(|t| {
        t.replace("parents = [\"X_b\"]", "parents = [\"X_d\"]")
            .replace("!X_b", "!X_d")
    })
    .err()
    .expect("should fail");
    assert!(e.contains("cycle: X_d → X_d"), "{e}");
    let e = case_study_with(|t| t.replace("[leaf.L2]", "[leaf.L9]"))
        .err()
        .expect("should fail");
    assert!(e.contains("no [leaf] for L2 #5"), "{e}");
    let e = case_study_with(|t| t.replace("btx_domain = 1", "btx_domain = 7"))
        .err()
        .expect("should fail");
    assert!(e.contains("btx_domain = 7"), "{e}");
    let e = case_study_with(|t| {
        t.replace(
            "type = \"bool\"\ninitial = false\n\n[state.X_b]",
            "type = \"boolean\"\ninitial = false\n\n[state.X_b]",
        )
    })
    .err()
    .expect("should fail");
    assert!(e.contains("type \"boolean\" is not one of"), "{e}");
    let e = case_study_with(|t| t.replace("status = \"SUCCESS\"", "status = \"42\""))
        .err()
        .expect("should fail");
    assert!(e.contains("not SUCCESS, FAILURE or RUNNING"), "{e}");
}

#[test]
fn seeded_helpers_are_deterministic_and_in_range() {
    let text = r#"
btx_domain = 1
[state.Seed]
type = "any"
initial = 7
[state.R]
type = "float"
min = 0.0
max = 1.0
parents = ["Seed"]
function = "rand_seeded(Seed)"
[state.N]
type = "int"
min = 0
max = 9
parents = ["Seed"]
function = "rand_int_seeded(next_seed(Seed), 0, 9)"
[leaf."@default_action"]
status = "SUCCESS"
"#;
    let d = Domain::parse(Path::new("r.toml"), text).unwrap();
    let a = d.initial_state().unwrap();
    let b = d.initial_state().unwrap();
    assert_eq!(a, b);
    let r = a[d.var("R").unwrap()].as_f64().unwrap();
    assert!((0.0..1.0).contains(&r));
}

#[test]
fn the_format_expresses_serial_recall_rules() {
    let d = Domain::load(&fixture("serial-recall-excerpt.domain.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let s = d.initial_state().unwrap();
    let confusion = s[d.var("UserConfusion").unwrap()].as_f64().unwrap();
    assert!((confusion - (0.7 * 0.2 + 0.15)).abs() < 1e-9, "{confusion}");
    let errors = s[d.var("UserNumErrors").unwrap()].as_i64().unwrap();
    assert!((0..=3).contains(&errors));
    // A frustrated user (0.8 > 0.7) ends the sequence unless a rule before it applies.
    let leaf = d
        .leaves
        .iter()
        .position(|l| l.key == "RepeatOrEnd")
        .unwrap();
    let a = d.decide(leaf, &s).unwrap();
    assert_eq!(a.as_deref(), Some("EndThisSequence"));
    let mut calm = s.clone();
    calm[d.var("UserFrustration").unwrap()] = Value::from(0.2);
    calm[d.var("UserNumErrors").unwrap()] = Value::from(1);
    assert_eq!(
        d.decide(leaf, &calm).unwrap().as_deref(),
        Some("RepeatThisSequence")
    );
    assert_eq!(
        d.effect(leaf, &calm, &Some("RepeatThisSequence".into()))
            .unwrap(),
        vec![(d.var("RepeatSequence").unwrap(), Value::Bool(true))]
    );
}

#[test]
fn a_domain_declares_the_scripting_enums_the_robot_registers() {
    let d = Arc::new(
        Domain::parse(
            Path::new("e.toml"),
            "btx_domain = 1\n[enums]\nRED = 0\nGREEN = 1\n",
        )
        .unwrap(),
    );
    let tree = btx::xml::load_str(
        Path::new("e.xml"),
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><ScriptCondition code="GREEN == 1 &amp;&amp; RED == 0"/></BehaviorTree></root>"#,
        &Default::default(),
    )
    .unwrap()
    .tree;
    let leaves = DomainLeaves::new(d, &tree).unwrap();
    let mut ex = btx::run::Executor::new(&tree, leaves, RunOptions::default());
    assert_eq!(ex.tick_once().unwrap(), btx::run::Status::Success);
}

#[test]
fn a_value_is_said_as_it_was_written() {
    // TOML writes NaN as `nan`, which JSON cannot hold: it was said as
    // `null`, and 1e-300 as 300 digits (#41 item 9).
    let text = std::fs::read_to_string(root().join("trees/case-study.domain.toml"))
        .unwrap()
        .replacen(
            "[state.X_b]",
            "[state.Noise]\ntype = \"any\"\ninitial = nan\n\n[state.Tiny]\ntype = \"float\"\nmin = 0.0\nmax = 1.0\ninitial = 1e-300\n\n[state.X_b]",
            1,
        )
        .replacen("inputs = [\"X_a\"]", "inputs = [\"X_a\", \"Noise\", \"Tiny\"]", 1);
    let dir = tempfile::tempdir().unwrap();
    let (d, s) = (dir.path().join("d.toml"), dir.path().join("s.jsonl"));
    std::fs::write(&d, text).unwrap();
    let tree = shipped("case-study.xml");
    let args = [
        "run",
        tree.to_str().unwrap(),
        "--domain",
        d.to_str().unwrap(),
    ];
    let (ok, _, err) = btx(&[&args[..], &["--out", s.to_str().unwrap()]].concat());
    assert!(ok, "{err}");
    let (ok, graph, err) = btx(&["graph", s.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(graph.contains("Noise^0\\n= nan"), "{graph}");
    assert!(graph.contains("Tiny^0\\n= 1e-300"), "{graph}");
    // A range's variable cannot start outside it, NaN included.
    std::fs::write(
        &d,
        std::fs::read_to_string(&d)
            .unwrap()
            .replace("initial = 1e-300", "initial = nan"),
    )
    .unwrap();
    let again = dir.path().join("again.jsonl");
    let (ok, _, err) = btx(&[&args[..], &["--out", again.to_str().unwrap()]].concat());
    assert!(
        !ok && one_line(&err).contains("Tiny: initial value \"nan\" is outside its range"),
        "{err}"
    );
}
