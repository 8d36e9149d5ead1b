//! Counterfactual explanations: Love et al.'s case study (Fig. 5, Fig. 6,
//! Table 1) on our own run and on btcm's log of it, structure-only models,
//! and the faithfulness of the model to every shipped run.

mod common;
use btx::causal::{self, english, Model, Val, VarKind};
use btx::input::open;
use btx::session::{Moment, Session};
use btx::xml::LoadOptions;
use common::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn session(path: &Path) -> Session {
    match open(path, &LoadOptions::default()) {
        Ok(btx::input::Input::Session(s)) => *s,
        Ok(_) => panic!("{} is not a session", path.display()),
        Err(e) => panic!("{e}"),
    }
}

fn case_study_domain() -> Arc<btx::run::domain::Domain> {
    Arc::new(btx::run::domain::Domain::load(&shipped("case-study.domain.toml")).unwrap())
}

/// Both readings of the case study: our run, and btcm's own log with our
/// domain file. Moments differ: btcm logs no RUNNING or reset transitions.
fn case_studies() -> Vec<(Session, Arc<btx::run::domain::Domain>, [&'static str; 4])> {
    let ours = session(&root("sessions/case-study.jsonl"));
    let d = causal::session_domain(&ours, None).unwrap().unwrap();
    let btcm = session(&fixture("btcm/case_study.json"));
    vec![
        // L0 completes, the Sequence completes, L2 completes, end.
        (ours, d, ["1:3", "1:5", "1:6", "1"]),
        (btcm, case_study_domain(), ["1:1", "1:2", "1:3", "1"]),
    ]
}

fn why(
    s: &Session,
    d: &Arc<btx::run::domain::Domain>,
    target: &str,
    foils: &[&str],
    at: &str,
) -> causal::Why {
    let foils: Vec<String> = foils.iter().map(|f| f.to_string()).collect();
    causal::why(
        s,
        Some(Arc::clone(d)),
        target,
        &foils,
        Some(Moment::parse(at).unwrap()),
        2,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The explanations as (reasons of each merged group, sentence).
fn answers(w: &causal::Why) -> Vec<(Vec<Vec<String>>, String)> {
    english::merge(&w.model, &w.answer)
        .iter()
        .map(|g| {
            let reasons = g
                .iter()
                .map(|&i| {
                    w.answer.explanations[i]
                        .vars
                        .iter()
                        .map(|&v| {
                            format!(
                                "{} = {}",
                                w.model.var_name(v),
                                english::value_text(&w.model.fact[v])
                            )
                        })
                        .collect()
                })
                .collect();
            (
                reasons,
                english::sentence(&w.model, &w.query, &w.answer.explanations[g[0]]),
            )
        })
        .collect()
}

fn strs(v: &[&[&str]]) -> Vec<Vec<String>> {
    v.iter()
        .map(|r| r.iter().map(|s| s.to_string()).collect())
        .collect()
}

#[test]
fn the_case_study_model_has_19_nodes_and_34_edges_and_reproduces_the_run() {
    for (s, d, _) in case_studies() {
        let m = causal::model_at(&s, Some(d), 1).unwrap();
        assert_eq!(
            (m.vars.len(), m.edge_count()),
            (19, 34),
            "{}",
            s.path.display()
        );
        assert_eq!(m.extension_edges, 0);
        assert!(m.unfaithful().is_empty(), "{:?}", m.unfaithful());
        // Fig. 6's copies: X_a^0..1, X_b^0..2, X_c^0, X_d^0.
        let copies: Vec<String> = (0..m.vars.len())
            .filter(|&v| matches!(m.vars[v].kind, VarKind::State { .. }))
            .map(|v| m.var_name(v))
            .collect();
        assert_eq!(
            copies,
            ["X_a^0", "X_b^0", "X_c^0", "X_d^0", "X_a^1", "X_b^1", "X_b^2"]
        );
    }
}

#[test]
fn table_1_why_did_l0_execute() {
    for (s, d, at) in case_studies() {
        let w = why(&s, &d, "executed(L0)", &["false"], at[0]);
        assert_eq!(w.answer.depth, Some(1));
        assert_eq!(
            answers(&w),
            vec![
                (
                    strs(&[&["executed(CaseStudySequence) = true"]]),
                    "L0 executed because CaseStudySequence executed. If CaseStudySequence had not executed, L0 would not have executed.".to_string()
                ),
                (
                    strs(&[&["executed(CaseStudyFallback) = true"]]),
                    "L0 executed because CaseStudyFallback executed. If CaseStudyFallback had not executed, L0 would not have executed.".to_string()
                ),
            ]
        );
    }
}

#[test]
fn table_1_why_did_l1_not_execute() {
    for (s, d, at) in case_studies() {
        let w = why(&s, &d, "executed(L1)", &[], at[1]);
        assert_eq!(
            answers(&w),
            vec![
                (
                    strs(&[&["status(L0) = FAILURE"]]),
                    "L1 did not execute because L0 failed. If L0 had succeeded, L1 would have executed.".to_string()
                ),
                (
                    strs(&[&["X_a^0 = false"]]),
                    "L1 did not execute because X_a was false. If X_a had been true, L1 would have executed.".to_string()
                ),
            ]
        );
    }
}

#[test]
fn table_1_why_did_l2_choose_a2_and_not_a3() {
    for (s, d, at) in case_studies() {
        let w = why(&s, &d, "decision(L2)", &["Action3"], at[2]);
        // btcm's three explanations; the two copies of X_b read alike and are merged.
        assert_eq!(w.answer.explanations.len(), 3);
        assert_eq!(
            answers(&w),
            vec![
                (
                    strs(&[&["X_d^0 = true"]]),
                    "L2 chose Action2 because X_d was true. If X_d had been false, L2 would have chosen Action3.".to_string()
                ),
                (
                    strs(&[&["X_b^1 = false"], &["X_b^0 = false"]]),
                    "L2 chose Action2 because X_b was false. If X_b had been true, L2 would have chosen Action3.".to_string()
                ),
            ]
        );
    }
}

#[test]
fn table_1_why_was_x_c_false_needs_two_variables() {
    for (s, d, at) in case_studies() {
        let w = why(&s, &d, "X_c", &["true"], at[1]);
        assert_eq!(w.answer.depth, Some(2));
        assert_eq!(
            answers(&w),
            vec![(
                strs(&[&["X_a^1 = false", "X_b^0 = false"], &["X_a^0 = false", "X_b^0 = false"]]),
                "X_c was false because X_a was false and X_b was false. If X_a had been true and X_b had been true, X_c would have been true.".to_string()
            )]
        );
    }
}

#[test]
fn the_step_by_step_example_reads_as_the_issue_asks() {
    for (s, d, at) in case_studies() {
        let w = why(&s, &d, "status(L0)", &["SUCCESS"], at[0]);
        assert_eq!(
            answers(&w),
            vec![(
                strs(&[&["X_a^0 = false"]]),
                "L0 failed because X_a was false. If X_a had been true, L0 would have succeeded."
                    .to_string()
            )]
        );
        assert!(w.text().starts_with("Why did L0 fail rather than succeed?"));
    }
}

#[test]
fn a_variable_at_a_moment_is_the_copy_that_holds_its_value_then() {
    for (s, d, at) in case_studies() {
        // Before L2 ran, X_b was false (copy 0); after, true (copy 2): btcm
        // answers about copy 1 at both.
        let before = why(&s, &d, "X_b", &[], at[0]);
        assert_eq!(before.model.var_name(before.query.targets[0]), "X_b^0");
        assert_eq!(
            before.model.fact[before.query.targets[0]],
            Val::Data(false.into())
        );
        let after = why(&s, &d, "X_b", &[], at[2]);
        assert_eq!(after.model.var_name(after.query.targets[0]), "X_b^2");
        assert_eq!(
            after.model.fact[after.query.targets[0]],
            Val::Data(true.into())
        );
        // An earlier copy of the asked variable is named by its copy.
        assert!(
            after
                .text()
                .contains("X_b was true because X_b^1 was false."),
            "{}",
            after.text()
        );
    }
}

#[test]
fn json_carries_the_reason_set_and_the_counterfactual_set() {
    let (s, d, at) = case_studies().remove(0);
    let j = why(&s, &d, "X_c", &["true"], at[1]).json();
    assert_eq!(j["model"]["nodes"], 19);
    assert_eq!(j["depth"], 2);
    let e = &j["explanations"][0];
    assert_eq!(e["R"][0][0]["variable"], "X_a^1");
    assert_eq!(e["R"][0][0]["value"], false);
    assert_eq!(e["C"][0]["J"][1]["variable"], "X_b^0");
    assert_eq!(e["C"][0]["J"][1]["value"], true);
    assert_eq!(e["C"][0]["K"][0]["variable"], "X_c^0");
    assert_eq!(e["C"][0]["K"][0]["value"], true);
}

#[test]
fn without_a_domain_the_structure_still_explains() {
    let s = session(&root("sessions/kitting-nominal.jsonl"));
    assert!(causal::session_domain(&s, None).unwrap().is_none());
    // The tick in which the gear-insertion sequence succeeded.
    let seq = uid_of(&s.tree, "#8");
    let tick = s
        .index
        .transitions
        .iter()
        .find(|t| t.uid == seq && t.status == btx::run::Status::Success)
        .unwrap()
        .tick;
    let w = causal::why(
        &s,
        None,
        "executed(#28)",
        &[],
        Some(Moment { tick, step: None }),
        2,
    )
    .unwrap();
    assert_eq!(
        answers(&w)[0].1,
        // Several nodes read "ask" and "go insert large gear": each carries its uid.
        "Ask (#28) did not execute because go insert large gear (#4) succeeded. If go insert large gear (#4) had failed, ask (#28) would have executed."
    );
    // A state variable needs a domain.
    let e = causal::why(&s, None, "X_a", &[], None, 2)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("no domain"), "{e}");
}

#[test]
fn queries_with_bad_targets_or_foils_are_clear_errors() {
    let (s, d, _) = case_studies().remove(0);
    let err = |t: &str, f: &[&str]| {
        let foils: Vec<String> = f.iter().map(|x| x.to_string()).collect();
        causal::why(&s, Some(Arc::clone(&d)), t, &foils, None, 2)
            .err()
            .unwrap()
            .to_string()
    };
    assert!(err("status(L0)", &["FAILURE"]).contains("a foil must be a value it did not have"));
    assert!(err("status(Nope)", &[]).contains("no node matches"));
    assert!(err("decision(L0)", &[]).contains("takes no decisions"));
    assert!(err("decision(L2)", &["Action9"]).contains("not one of"));
    assert!(err("X_a^7", &[]).contains("copies 0 to 1"));
    assert!(err("launch(L0)", &[]).contains("is not a target"));
}

#[test]
fn every_shipped_run_is_reproduced_by_its_model_at_every_tick() {
    for e in std::fs::read_dir(root("sessions")).unwrap() {
        let p = e.unwrap().path();
        let s = session(&p);
        let d = causal::session_domain(&s, None).unwrap();
        for tick in 1..=s.index.ticks() {
            let m = causal::model_at(&s, d.clone(), tick).unwrap();
            assert!(
                m.unfaithful().is_empty(),
                "{} tick {tick}: {:?}",
                p.display(),
                m.unfaithful()
            );
            identity_changes_nothing(&m);
        }
    }
}

/// Setting any variable to its own value, and recomputing everything else
/// from its parents, changes nothing (btcm fails this for 152 of 168
/// variables of its serial-recall model).
pub fn identity_changes_nothing(m: &Model) {
    for v in 0..m.vars.len() {
        let after = m.evaluate_with(&[(v, m.fact[v].clone())]).unwrap();
        assert_eq!(
            after,
            m.fact,
            "Do({} = its value) changed the model",
            m.var_name(v)
        );
    }
}

#[test]
fn btcm_logs_open_as_sessions() {
    let s = session(&fixture("btcm/case_study.json"));
    assert_eq!(s.index.ticks(), 1);
    assert_eq!(s.tree.len(), 5);
    assert_eq!(s.tree.description(1), "CaseStudyFallback");
    assert_eq!(s.index.transition_decision(2), Some("Action2"));
    let r = session(&fixture(
        "btcm/random_default_seed_0_vars_4_connectivity_0.5_leaves_4.json",
    ));
    assert_eq!(r.index.ticks(), 1);
    // Without its Python leaves the structure still answers.
    let m = causal::model_at(&r, None, 1).unwrap();
    assert!(m.unfaithful().is_empty(), "{:?}", m.unfaithful());
}

#[test]
fn btx_why_answers_in_text_and_json() {
    let (ok, out, err) = btx(&[
        "why",
        "sessions/case-study.jsonl",
        "status(L0)",
        "--not",
        "SUCCESS",
        "--at",
        "1:3",
        "--detail",
        "full",
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "Why did L0 fail rather than succeed?  (tick 1, moment 1:3)\n\
         1. L0 failed because X_a was false. If X_a had been true, L0 would have succeeded.\n   formally: X_a^0 = false\n\
         Checked: running the tree again to tick 1 with each change gives what the explanation says.\n"
    );
    let (ok, out, _) = btx(&[
        "why",
        "sessions/case-study.jsonl",
        "X_c",
        "--at",
        "1:5",
        "--format",
        "json",
    ]);
    assert!(ok);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(j["depth"], 2);
    assert_eq!(j["explanations"].as_array().unwrap().len(), 1);
    // btcm's log with the domain given.
    let f = fixture("btcm/case_study.json").display().to_string();
    let (ok, out, err) = btx(&[
        "why",
        &f,
        "decision(L2)",
        "--at",
        "1:3",
        "--domain",
        "trees/case-study.domain.toml",
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("L2 chose Action2 because X_d was true."),
        "{out}"
    );
    // A depth bound too small for any explanation says so.
    let (ok, out, _) = btx(&[
        "why",
        "sessions/case-study.jsonl",
        "X_c",
        "--at",
        "1:5",
        "--max-depth",
        "1",
    ]);
    assert!(ok);
    assert!(out.contains("No explanation up to depth 1"), "{out}");
}

#[test]
fn btx_why_and_graph_refuse_what_they_cannot_answer() {
    let (ok, _, err) = btx(&["why", "trees/case-study.xml", "status(L0)"]);
    assert!(!ok);
    assert!(
        err.contains("is a tree; a why-question is about a run"),
        "{err}"
    );
    let (ok, _, err) = btx(&[
        "why",
        "sessions/case-study.jsonl",
        "status(L0)",
        "--at",
        "9",
    ]);
    assert!(!ok);
    assert!(err.contains("outside the run"), "{err}");
    let (ok, _, err) = btx(&[
        "why",
        "sessions/case-study.jsonl",
        "status(L0)",
        "--domain",
        "no/such.toml",
    ]);
    assert!(!ok);
    assert!(err.contains("no/such.toml"), "{err}");
}

#[test]
fn btx_graph_prints_the_model() {
    let (ok, out, _) = btx(&[
        "graph",
        "sessions/case-study.jsonl",
        "--at",
        "1",
        "--format",
        "json",
    ]);
    assert!(ok);
    let j: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (j["nodes"].as_u64(), j["edges"].as_u64()),
        (Some(19), Some(34))
    );
    let (ok, out, _) = btx(&["graph", "sessions/case-study.jsonl"]);
    assert!(ok);
    assert!(
        out.starts_with("// explanation model of tick 1: 19 variables, 34 edges\ndigraph model {")
    );
    assert_eq!(out.matches(" -> ").count(), 34);
}

#[test]
fn target_recovery_on_random_domains_is_complete() {
    let rows = btx::causal::eval::recovery_random(1, false).unwrap();
    assert_eq!(rows.len(), 180);
    let differ: Vec<_> = rows.iter().filter(|r| r.found.is_some()).collect();
    assert!(differ.len() > 40, "{}", differ.len());
    assert!(differ.iter().all(|r| r.found == Some(true)));
    let ext = btx::causal::eval::recovery_random(1, true).unwrap();
    assert!(ext.iter().all(|r| r.found != Some(false)));
}

#[test]
fn serial_recall_model_has_177_nodes_and_406_edges_and_is_faithful() {
    let s = session(&root("sessions/serial-recall.jsonl"));
    let d = causal::session_domain(&s, None).unwrap();
    assert!(s.index.ticks() >= 5, "{}", s.index.ticks());
    for tick in 1..=s.index.ticks() {
        let m = causal::model_at(&s, d.clone(), tick).unwrap();
        // btcm's construction with btcm's input and output sets: 33 E, 33 r,
        // 15 d, 96 state copies; no edge beyond the paper's algorithms.
        assert_eq!(
            (m.vars.len(), m.edge_count(), m.extension_edges),
            (177, 406, 0),
            "tick {tick}"
        );
        assert!(
            m.unfaithful().is_empty(),
            "tick {tick}: {:?}",
            m.unfaithful()
        );
        if tick <= 2 {
            identity_changes_nothing(&m);
        }
    }
}

#[test]
fn the_shipped_serial_recall_session_is_what_the_domain_gives() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let (ok, _, err) = btx(&[
        "run",
        "trees/serial-recall.xml",
        "--domain",
        "trees/serial-recall.domain.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let fresh = session(&out);
    let shipped = session(&root("sessions/serial-recall.jsonl"));
    assert_eq!(
        fresh.index.transitions, shipped.index.transitions,
        "regenerate sessions/serial-recall.jsonl (see docs/formats.md)"
    );
}

#[test]
fn target_recovery_on_serial_recall_is_complete() {
    let rows = btx::causal::eval::recovery_serial_recall(3).unwrap();
    assert_eq!(rows.len(), 12);
    for r in &rows {
        assert_eq!(r.found, Some(true), "{} seed {}", r.config, r.seed);
        assert_eq!((r.model_nodes, r.model_edges), (177, 406));
    }
    // The frustrated user: the robot ended the sequence because of it.
    assert!(rows
        .iter()
        .filter(|r| r.config == "frustrated")
        .all(|r| r.explanations == 1));
}
