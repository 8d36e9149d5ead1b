//! Runs recorded as sessions, and questions at moments of them (Han §6.3,
//! §7.1.2, §7.1.3).

mod common;
use btx::explain::{answer, Question};
use btx::run::plan::{Plan, PlanLeaves};
use btx::run::{RunOptions, Status};
use btx::session::record::{record, RunRequest};
use btx::session::{Moment, Session, Source};
use common::*;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn run_plan(
    tree: &Path,
    plan: &Path,
    out: &Path,
    ask: Option<(u32, &str)>,
) -> btx::session::record::RunSummary {
    let t = load(tree);
    let plan = Plan::load(plan).unwrap();
    let req = RunRequest {
        tree: &t,
        tree_file: None,
        source: Source {
            kind: "plan".into(),
            path: None,
            text: Some(plan.text.clone()),
            name: None,
        },
        seed: None,
        max_ticks: 1000,
        options: RunOptions::default(),
        ask: ask.map(|(t, q)| btx::explain::insert::asked_during_run(t, q)),
        out,
    };
    let leaves = PlanLeaves::new(plan, &t);
    record(req, leaves).unwrap_or_else(|e| panic!("{e:?}"))
}

fn ask(s: &Session, at: &str, q: &str) -> String {
    let view = s.at(Moment::parse(at).unwrap()).unwrap();
    let n = view.current().unwrap();
    answer(&s.tree, Some(&view), n, &Question::parse(q).unwrap())
        .unwrap()
        .text
}

#[test]
fn what_went_wrong_when_look_at_chuck_failed() {
    // The issue's required sentences, on the released tree's v4 conversion.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let tree = fixture("kitting-tree.v4.xml");
    let plan = fixture("plans/kitting_lookat_fails_once.plan");
    let (ok, _, err) = btx(&[
        "run",
        tree.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let s = out.to_str().unwrap();
    let (ok, a, _) = btx(&[
        "ask",
        s,
        "--at",
        "10",
        "What are you doing?",
        "What went wrong?",
    ]);
    assert!(ok);
    assert_eq!(
        a,
        "I retreat arm.\nI could not insert large gear because look at chuck failed.\n"
    );
    let (ok, a, _) = btx(&["ask", s, "--at", "11", "q1", "wrong"]);
    assert!(ok);
    assert_eq!(
        a,
        "I lift torso.\nI am retrying for attempt 1 to go insert large gear. I could not insert large gear because look at chuck failed.\n"
    );
    let (ok, a, _) = btx(&["ask", s, "--at", "9", "anything-wrong", "wrong", "handled"]);
    assert!(ok);
    assert_eq!(
        a,
        "Nothing went wrong.\nNothing went wrong.\nNothing went wrong.\n"
    );
    let (ok, a, _) = btx(&[
        "ask",
        s,
        "--at",
        "10",
        "Was there anything wrong?",
        "How was the failure handled?",
    ]);
    assert!(ok);
    assert_eq!(
        a,
        "Yes. I could not insert large gear because look at chuck failed.\nWhen insert large gear failed, I fell back to reset arm.\n"
    );
}

#[test]
fn navigation_and_lift_torso_failures_of_section_7_1_3() {
    let dir = tempfile::tempdir().unwrap();
    let tree = shipped("kitting.xml");
    let nav = dir.path().join("nav.jsonl");
    run_plan(
        &tree,
        &root().join("trees/plans/kitting-navigation-fails-once.plan"),
        &nav,
        None,
    );
    let s = Session::load(&nav).unwrap();
    assert_eq!(ask(&s, "2", "q1"), "I move to see chuck.");
    assert_eq!(
        ask(&s, "2", "wrong"),
        "I am retrying for attempt 1 to go insert large gear. I could not go insert large gear because move to see chuck failed."
    );
    let lift = dir.path().join("lift.jsonl");
    run_plan(
        &tree,
        &root().join("trees/plans/kitting-lift-torso-fails-once.plan"),
        &lift,
        None,
    );
    let s = Session::load(&lift).unwrap();
    assert_eq!(ask(&s, "4", "q1"), "I lift torso.");
    assert_eq!(
        ask(&s, "4", "wrong"),
        "I am retrying for attempt 1 to go insert large gear. I could not detect chuck because lift torso failed."
    );
    assert_eq!(
        ask(&s, "4", "handled"),
        "I am retrying to go insert large gear: 1 attempt failed, this is attempt 2 of 3."
    );
}

#[test]
fn han_questions_work_at_any_moment() {
    let s = Session::load(&root().join("sessions/kitting-lookat-fails-once.jsonl")).unwrap();
    assert_eq!(ask(&s, "3", "q2"), "I lift torso in order to detect chuck.");
    assert_eq!(ask(&s, "10:8", "q1"), "I retreat arm.");
    // Nothing runs between look at chuck failing and retreat arm starting.
    assert_eq!(
        ask(&s, "10:3", "q1"),
        "I am between actions at this moment. The last thing I did was look at chuck, which failed."
    );
    assert_eq!(ask(&s, "30", "q3"), "My subgoal is to go pick screw.");
}

#[test]
fn can_you_insert_large_gear_inserts_the_unnamed_sequence() {
    let s = Session::load(&root().join("sessions/kitting-lookat-fails-once.jsonl")).unwrap();
    let view = s.at(Moment::parse("10").unwrap()).unwrap();
    let a = answer(
        &s.tree,
        Some(&view),
        27,
        &Question::parse("Can you insert large gear?").unwrap(),
    )
    .unwrap();
    assert_eq!(
        a.text,
        "Yes. I will insert large gear after go insert large gear."
    );
    let ins = a.insertion.unwrap();
    assert_eq!(
        (ins.named, ins.copy_of, ins.after),
        (14, 8, 2),
        "paper §7.1.2, Fig. 11"
    );
    assert_eq!(s.tree.description(8), "Sequence");
    let refusal = answer(
        &s.tree,
        Some(&view),
        27,
        &Question::parse("Can you fly?").unwrap(),
    )
    .unwrap();
    assert_eq!(
        refusal.text,
        "Sorry. I cannot redo \"fly\": no subgoal, sequence or step of mine is called that."
    );
}

#[test]
fn a_run_asked_can_you_executes_the_inserted_subgoal() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ins.jsonl");
    let sum = run_plan(
        &shipped("kitting.xml"),
        &root().join("trees/plans/kitting-lookat-fails-once.plan"),
        &out,
        Some((10, "Can you insert large gear?")),
    );
    assert_eq!(
        sum.answer.as_deref(),
        Some("Yes. I will insert large gear after go insert large gear.")
    );
    assert_eq!(sum.root, Status::Success);
    let s = Session::load(&out).unwrap();
    assert_eq!(s.tree.len(), 79 + 20);
    assert_eq!(s.tree.node(1).children, vec![2, 80, 29, 56]);
    // The copy ran after the subgoal, before go pick screw.
    let first_copy = s
        .index
        .transitions
        .iter()
        .position(|t| t.uid == 80)
        .unwrap();
    let subgoal_done = s
        .index
        .transitions
        .iter()
        .position(|t| t.uid == 2 && t.status == Status::Success)
        .unwrap();
    let next_subgoal = s
        .index
        .transitions
        .iter()
        .position(|t| t.uid == 29)
        .unwrap();
    assert!(subgoal_done < first_copy && first_copy < next_subgoal);
    assert!(
        s.index
            .transitions
            .iter()
            .any(|t| t.uid == 97 && t.status == Status::Success),
        "the copy's retreat arm ran"
    );
    // The modified tree writes as v4 XML with the unnamed Sequence after the subgoal (Fig. 11).
    let xml = btx::xml::to_v4_xml(&s.tree);
    let i = xml.find("<SubTree ID=\"GoInsertLargeGear\"").unwrap();
    assert!(
        xml[i..].lines().nth(1).unwrap().trim() == "<Sequence>",
        "{xml}"
    );
}

#[test]
fn shipped_sessions_are_what_their_plans_give() {
    for (tree, plan) in [
        ("kitting.xml", "kitting-nominal"),
        ("kitting.xml", "kitting-lookat-fails-once"),
        ("kitting.xml", "kitting-detect-chuck-always-fails"),
        ("kitting.xml", "kitting-grasp-check-fails-first"),
        ("kitting.xml", "kitting-navigation-fails-once"),
        ("kitting.xml", "kitting-lift-torso-fails-once"),
        ("kitting.xml", "kitting-help-fails"),
        ("taxi.xml", "taxi-nominal"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("s.jsonl");
        run_plan(
            &shipped(tree),
            &root().join(format!("trees/plans/{plan}.plan")),
            &out,
            None,
        );
        let fresh = Session::load(&out).unwrap();
        let shipped = Session::load(&root().join(format!("sessions/{plan}.jsonl"))).unwrap();
        assert!(
            shipped.warnings.is_empty(),
            "{plan}: {:?}",
            shipped.warnings
        );
        assert_eq!(
            fresh.index.transitions, shipped.index.transitions,
            "{plan}: regenerate sessions/ (see docs/formats.md)"
        );
        assert_eq!(fresh.tree.len(), shipped.tree.len());
    }
}

#[test]
fn sessions_are_never_clobbered_and_a_cut_session_still_reads() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let plan = root().join("trees/plans/taxi-nominal.plan");
    run_plan(&shipped("taxi.xml"), &plan, &out, None);
    let before = std::fs::read_to_string(&out).unwrap();
    let (ok, _, err) = btx(&[
        "run",
        shipped("taxi.xml").to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("already exists"), "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), before);
    assert!(!dir.path().join("s.jsonl.partial").exists());

    // A run killed half way: the file ends in the middle of a record.
    let cut = &before[..before.len() * 2 / 3];
    let cut_path = dir.path().join("cut.jsonl.partial");
    std::fs::write(&cut_path, cut).unwrap();
    let s = Session::load(&cut_path).unwrap();
    assert!(s.end.is_none());
    assert!(
        s.warnings.iter().any(|w| w.message.contains("cut off")),
        "{:?}",
        s.warnings
    );
    assert!(s
        .warnings
        .iter()
        .any(|w| w.message.contains("no end record")));
    assert!(s.index.ticks() > 5);
    let (ok, a, _) = btx(&["ask", cut_path.to_str().unwrap(), "q1"]);
    assert!(ok);
    assert!(a.starts_with("I ") && a.ends_with(".\n"), "{a}");
}

#[test]
fn broken_sessions_are_located_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(root().join("sessions/taxi-nominal.jsonl")).unwrap();
    let mut lines: Vec<&str> = good.lines().collect();
    lines[3] =
        "{\"k\":\"t\",\"tick\":1,\"step\":3,\"uid\":999,\"from\":\"IDLE\",\"to\":\"RUNNING\"}";
    let p = dir.path().join("bad.jsonl");
    std::fs::write(&p, lines.join("\n") + "\n").unwrap();
    let e = Session::load(&p).err().unwrap().to_string();
    assert!(e.contains("bad.jsonl:4:1: uid 999 is not a node"), "{e}");
    lines[3] = "{\"k\":\"t\",\"tick\":1,\"step\":3,\"uid\":3,\"from\":\"IDLE\",\"to\":\"BORED\"}";
    std::fs::write(&p, lines.join("\n") + "\n").unwrap();
    let e = Session::load(&p).err().unwrap().to_string();
    assert!(e.contains("bad.jsonl:4:1: not a session record"), "{e}");
    // A tick number far ahead of the records is refused, not indexed.
    lines[3] =
        "{\"k\":\"t\",\"tick\":4000000000,\"step\":3,\"uid\":3,\"from\":\"IDLE\",\"to\":\"RUNNING\"}";
    std::fs::write(&p, lines.join("\n") + "\n").unwrap();
    let e = Session::load(&p).err().unwrap().to_string();
    assert!(
        e.contains("bad.jsonl:4:1: tick 4000000000 leaves more than 10000000 ticks"),
        "{e}"
    );
    std::fs::write(&p, "{\"hello\": 1}\n").unwrap();
    let e = Session::load(&p).err().unwrap().to_string();
    assert!(e.contains("bad.jsonl:1:1: not a btx session header"), "{e}");
}

#[test]
fn moments_outside_the_run_are_refused() {
    let s = Session::load(&root().join("sessions/taxi-nominal.jsonl")).unwrap();
    assert!(s
        .at(Moment::parse("16").unwrap())
        .err()
        .unwrap()
        .contains("ticks 1 to 15"));
    assert!(s
        .at(Moment::parse("1:99").unwrap())
        .err()
        .unwrap()
        .contains("tick 1 has 5 transitions"));
    let (ok, _, err) = btx(&[
        "ask",
        root().join("sessions/taxi-nominal.jsonl").to_str().unwrap(),
        "--at",
        "x",
        "q1",
    ]);
    assert!(!ok);
    assert!(err.contains("not a moment"), "{err}");
}

#[test]
fn the_index_agrees_with_a_replay_at_every_position() {
    let s = Session::load(&root().join("sessions/kitting-grasp-check-fails-first.jsonl")).unwrap();
    let mut status = vec![Status::Idle; s.tree.len()];
    let mut last_done: Vec<Option<Status>> = vec![None; s.tree.len()];
    for (i, t) in s.index.transitions.iter().enumerate() {
        status[(t.uid - 1) as usize] = t.status;
        if t.status.is_completed() {
            last_done[(t.uid - 1) as usize] = Some(t.status);
        }
        let at = s.index.at(i as u32 + 1);
        for u in 1..=s.tree.len() as u32 {
            assert_eq!(
                at.status(u),
                status[(u - 1) as usize],
                "#{u} at position {}",
                i + 1
            );
            assert_eq!(at.last_completed(u), last_done[(u - 1) as usize]);
        }
    }
    // Retry attempts: the pick retry counts one failure after tick 31.
    let at = s.at(Moment::parse("32").unwrap()).unwrap();
    assert_eq!(at.attempts(34), 1);
    assert_eq!(s.at(Moment::parse("30").unwrap()).unwrap().attempts(34), 0);
}

#[test]
fn log_lists_filters_and_writes_json() {
    let p = root().join("sessions/kitting-lookat-fails-once.jsonl");
    let (ok, out, _) = btx(&[
        "log",
        p.to_str().unwrap(),
        "--node",
        "go insert large gear/look at chuck",
    ]);
    assert!(ok);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 7);
    assert!(
        lines[2].split_whitespace().collect::<Vec<_>>()
            == ["10", "1", "18", "look", "at", "chuck", "RUNNING", "->", "FAILURE"],
        "{out}"
    );
    let (ok, out, _) = btx(&["log", p.to_str().unwrap(), "--no-idle", "--format", "json"]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["schema"], "btx.log/1");
    let rows = v["transitions"].as_array().unwrap();
    assert!(rows.iter().all(|r| r["status"] != "IDLE"));
    assert_eq!(rows[0]["node"], "build a gearbox kit");
}

#[test]
fn log_marks_halts() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, err, out) = run_planned(
        dir.path(),
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><ReactiveSequence name="r"><check name="c"/><act name="a"/></ReactiveSequence></BehaviorTree><TreeNodesModel><Condition ID="check"/></TreeNodesModel></root>"#,
        "c = S, F\na = 3RS\n",
    );
    assert!(ok, "{err}");
    let (ok, text, _) = btx(&["log", out.to_str().unwrap(), "--node", "a"]);
    assert!(ok);
    assert!(
        text.lines()
            .last()
            .unwrap()
            .ends_with("RUNNING  -> IDLE     (halted)"),
        "{text}"
    );
    let (_, json, _) = btx(&["log", out.to_str().unwrap(), "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let halted: Vec<&serde_json::Value> = v["transitions"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["halted"] == true)
        .collect();
    assert_eq!(halted.len(), 1);
    assert_eq!(halted[0]["node"], "a");
}

/// Runs a tree of `tests/fixtures/answers/` with its plan into `dir`.
fn answers_run(dir: &Path, name: &str) -> Session {
    let out = dir.join(format!("{name}.jsonl"));
    run_plan(
        &fixture(&format!("answers/{name}.xml")),
        &fixture(&format!("answers/{name}.plan")),
        &out,
        None,
    );
    Session::load(&out).unwrap()
}

fn ask_at(s: &Session, at: &str, q: &str) -> String {
    let view = s.at(Moment::parse(at).unwrap()).unwrap();
    let n = view.current().unwrap_or(1);
    answer(&s.tree, Some(&view), n, &Question::parse(q).unwrap())
        .unwrap()
        .text
}

#[test]
fn what_are_you_doing_names_what_runs_then() {
    let dir = tempfile::tempdir().unwrap();
    let s = answers_run(dir.path(), "patrol");
    // Both children of the Parallel run in tick 1; in tick 2 look around
    // has finished and only walk runs (the most recent leaf is look around).
    assert_eq!(ask_at(&s, "1", "q1"), "I walk and look around.");
    assert_eq!(ask_at(&s, "2", "q1"), "I walk.");
    assert_eq!(ask_at(&s, "4", "q1"), "I drive.");
    // Past tense once the root's run is over.
    assert_eq!(
        ask_at(&s, "5", "q1"),
        "I have finished: patrol failed. The last thing I did was path clear, which failed."
    );
    let s = answers_run(dir.path(), "timeout");
    assert_eq!(
        ask_at(&s, "4", "q1"),
        "I have finished: deliver part failed. The last thing I did was move part, which was halted."
    );
}

#[test]
fn a_failed_root_says_what_ended_the_task() {
    let dir = tempfile::tempdir().unwrap();
    let s = answers_run(dir.path(), "patrol");
    assert_eq!(ask_at(&s, "4", "wrong"), "Nothing went wrong.");
    assert_eq!(
        ask_at(&s, "5", "wrong"),
        "The task failed: guarded drive stopped because path clear failed."
    );
    assert_eq!(
        ask_at(&s, "5", "handled"),
        "The task failed: guarded drive stopped because path clear failed. Nothing handled the failure."
    );
    let s = answers_run(dir.path(), "timeout");
    assert_eq!(
        ask_at(&s, "4", "wrong"),
        "The task failed: move part in time stopped because its time ran out."
    );
}

#[test]
fn what_went_wrong_looks_at_the_current_run_only() {
    // Serial recall restarts the root every tick: tick 1's failed check is
    // history by tick 8, where nothing has failed.
    let s = Session::load(&root().join("sessions/serial-recall.jsonl")).unwrap();
    assert_eq!(ask(&s, "8:3", "wrong"), "Nothing went wrong.");
    // While a Retry retries, its cause stays in the answer, even after the
    // leaf that failed has succeeded on the next attempt (tick 18).
    let s = Session::load(&root().join("sessions/kitting-lookat-fails-once.jsonl")).unwrap();
    for t in ["11", "15", "18", "25"] {
        assert_eq!(
            ask(&s, t, "wrong"),
            "I am retrying for attempt 1 to go insert large gear. I could not insert large gear because look at chuck failed.",
            "tick {t}"
        );
    }
    // Once the Retry has succeeded nothing is wrong, and the failure it
    // recovered from is told as history.
    assert_eq!(
        ask(&s, "26", "wrong"),
        "Nothing is wrong now. Look at chuck failed at tick 10; the insert large gear fallback (#13) first fell back (retreat arm) and failed; RetryUntilSuccessful (#7) tried again and succeeded at tick 26."
    );
    // At every step in between: the Fallback resets insert large gear, then
    // fails and is reset itself, before the Retry starts attempt 2 (tick
    // 11's steps 4 to 10, which said "Nothing went wrong.").
    for step in 1..=13 {
        let said = ask(&s, &format!("11:{step}"), "wrong");
        assert!(
            said.contains("I could not insert large gear because look at chuck failed."),
            "11:{step}: {said}"
        );
    }
}

#[test]
fn what_went_wrong_under_a_control_node_btx_does_not_know() {
    // The look-at-chuck log with its Fallback renamed MyFallback, a custom
    // control node: the failure below it is said, and that what it did
    // about it btx cannot tell (it said "Nothing went wrong.").
    let dir = tempfile::tempdir().unwrap();
    let log =
        std::fs::read(root().join("tests/fixtures/logs/kitting_lookat_fails_once.btlog")).unwrap();
    let n = i32::from_le_bytes(log[19..23].try_into().unwrap()) as usize;
    let xml = std::str::from_utf8(&log[23..23 + n]).unwrap();
    let open = xml.find("<Fallback name=\"insert large gear\"").unwrap();
    let close = open + xml[open..].find("</Fallback>").unwrap();
    let xml = format!(
        "{}<MyFallback{}</MyFallback>{}",
        &xml[..open],
        &xml[open + "<Fallback".len()..close],
        &xml[close + "</Fallback>".len()..]
    );
    let mut bytes = log[..19].to_vec();
    bytes.extend((xml.len() as i32).to_le_bytes());
    bytes.extend(xml.as_bytes());
    bytes.extend(&log[23 + n..]);
    let path = dir.path().join("custom.btlog");
    let s = btx::logs::open_btlog(&path, &bytes).unwrap();
    let at = s.at(Moment::parse("10").unwrap()).unwrap();
    let n = at.current().unwrap();
    assert_eq!(
        answer(&s.tree, Some(&at), n, &Question::parse("wrong").unwrap()).unwrap().text,
        "I could not insert large gear because look at chuck failed. What insert large gear (#13) did about it, btx cannot tell: it does not know how a MyFallback handles a failure."
    );
}

#[test]
fn can_you_finds_every_behaviour_of_that_name() {
    let s = Session::load(&root().join("sessions/kitting-lookat-fails-once.jsonl")).unwrap();
    // #41 "pick screw" is in another subgoal: it is found and inserted.
    assert_eq!(
        ask(&s, "10", "Can you pick screw?"),
        "Yes. I will pick screw after go insert large gear."
    );
    // Asked while that subgoal runs, Han §7.2 inserts it after itself.
    assert_eq!(
        ask(&s, "10", "Can you go insert large gear?"),
        "Yes. I will go insert large gear after go insert large gear."
    );
    // A refusal names the node it means, with a true reason.
    assert_eq!(
        ask(&s, "10", "Can you build a gearbox kit?"),
        "Sorry. I cannot redo \"build a gearbox kit\" (#1): it contains what I am doing now."
    );
    let s = Session::load(&root().join("sessions/taxi.jsonl")).unwrap();
    assert_eq!(
        ask(&s, "3", "Can you go pick up passenger?"),
        "Yes. I will go pick up passenger after go pick up passenger."
    );
}
