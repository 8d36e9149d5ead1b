//! Nav2's `behavior_tree_log` recorded in rosbag2 bags (#30 item 1). The
//! runs are the real BehaviorTree.CPP's (`tests/oracle/btcpp_run.py`, with
//! its FileLogger's `.btlog`); the bags are written from them by the PyPI
//! package `rosbags` (`tests/rosbag/write_bag.py`), one message a tick as
//! Nav2's RosTopicLogger publishes. A bag's run must be its `.btlog`,
//! transition for transition, tick for tick.

mod common;
#[path = "common/rechunk.rs"]
mod rechunk;
use btx::session::Session;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A navigator in miniature: two nodes named `FollowPath` (a Fallback
/// and its action, as Nav2's RecoveryNode and its FollowPath), a retry.
const NAV: &str = r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <Sequence name="NavigateWithReplanning">
      <Fallback name="FollowPath">
        <Act name="FollowPath"/>
        <Act name="ClearLocalCostmap"/>
      </Fallback>
      <RetryUntilSuccessful num_attempts="3">
        <Act name="Spin"/>
      </RetryUntilSuccessful>
    </Sequence>
  </BehaviorTree>
  <TreeNodesModel><Action ID="Act"/></TreeNodesModel>
</root>"#;

/// Two goals run by BehaviorTree.CPP: the first recovers (FollowPath
/// fails, the costmap is cleared, Spin is retried), the second goes
/// straight. Their `.btlog` and tick files.
fn goals(dir: &Path) -> Vec<(PathBuf, PathBuf)> {
    let cases = serde_json::json!([
        {"xml": NAV, "plan": "FollowPath = 2RF\nClearLocalCostmap = S\nSpin = 1RF, 1RS\n", "max_ticks": 20},
        {"xml": NAV, "plan": "FollowPath = 1RS\nSpin = S\n", "max_ticks": 20},
    ]);
    let input = dir.join("cases.json");
    std::fs::write(&input, cases.to_string()).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/oracle/btcpp_run.py");
    let out = Command::new(common::oracle_python())
        .arg(script)
        .arg(&input)
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (0..2)
        .map(|i| {
            (
                dir.join(format!("{i}.btlog")),
                dir.join(format!("{i}.json")),
            )
        })
        .collect()
}

/// A bag of `runs` written by `rosbags`.
fn bag(
    dir: &Path,
    name: &str,
    storage: &str,
    release: &str,
    runs: &[(PathBuf, PathBuf)],
) -> PathBuf {
    let out = dir.join(name);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rosbag/write_bag.py");
    let mut c = Command::new(common::oracle_python());
    c.arg(script).arg(&out).arg(storage).arg(release);
    for (log, ticks) in runs {
        c.arg(format!("{}:{}", log.display(), ticks.display()));
    }
    let o = c.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

/// (tick, uid, prev, status) of each transition.
fn rows(s: &Session) -> Vec<(u32, u32, String, String)> {
    s.index
        .transitions
        .iter()
        .map(|t| (t.tick, t.uid, t.prev.to_string(), t.status.to_string()))
        .collect()
}

#[test]
fn a_bag_s_runs_are_the_robot_s_own_logs() {
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let tree = dir.path().join("nav.xml");
    std::fs::write(&tree, NAV).unwrap();
    let tree_s = tree.to_str().unwrap();
    let logged: Vec<Session> = runs
        .iter()
        .map(
            |(log, _)| match btx::input::open(log, &Default::default()).unwrap() {
                btx::input::Input::Session(s) => *s,
                btx::input::Input::Tree { .. } => panic!("a log"),
            },
        )
        .collect();
    assert!(logged.iter().all(|s| s.end.is_some()));
    // Jazzy's messages (with uid) in MCAP; Humble's (names only, no
    // definition in the bag) in SQLite, the storage file given alone.
    let jazzy = bag(dir.path(), "jazzy", "mcap", "jazzy", &runs);
    let humble = bag(dir.path(), "humble", "sqlite3", "humble", &runs);
    let humble_db3 = humble.join("humble.db3");
    // Jazzy's messages and no definition: read by Jazzy's, with uids.
    let bare = bag(dir.path(), "bare", "sqlite3", "jazzy-nodef", &runs);
    for (b, ambiguous) in [
        (&jazzy, false),
        (&humble, true),
        (&humble_db3, true),
        (&bare, false),
    ] {
        let b = b.to_str().unwrap();
        let (ok, list, err) = common::btx(&["log", b, "--runs", "--tree", tree_s]);
        assert!(ok, "{err}");
        let lines: Vec<&str> = list.lines().collect();
        assert_eq!(lines.len(), 3, "{list}");
        assert!(
            lines[1].ends_with("root SUCCESS (root completed)"),
            "{list}"
        );
        assert_eq!(
            err.contains("several nodes are named \"FollowPath\""),
            ambiguous,
            "{err}"
        );
        // Each run, imported, is that goal's .btlog.
        let out = dir.path().join(format!("{}-runs", b.replace('/', "_")));
        let (ok, _, err) = common::btx(&[
            "import",
            b,
            "--tree",
            tree_s,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{err}");
        for (i, want) in logged.iter().enumerate() {
            let got = Session::load(&out.join(format!("run-{}.jsonl", i + 1))).unwrap();
            assert_eq!(rows(&got), rows(want), "{b} run {}", i + 1);
            assert_eq!(got.ending(), want.ending(), "{b} run {}", i + 1);
        }
    }
    // Run 1 by --run and by BAG#1, and what went wrong in it.
    let j = jazzy.to_str().unwrap();
    let (ok, a, err) = common::btx(&[
        "ask",
        j,
        "--run",
        "1",
        "--tree",
        tree_s,
        "--at",
        "end",
        "What went wrong?",
    ]);
    assert!(ok, "{err}");
    let (ok, b, err) = common::btx(&[
        "ask",
        &format!("{j}#1"),
        "--tree",
        tree_s,
        "--at",
        "end",
        "What went wrong?",
    ]);
    assert!(ok, "{err}");
    assert_eq!(a, b);
    // The ticks in which nothing changed are told by timing, which the
    // library's fast ticks make vary: the failures are asserted, not when.
    assert!(
        a.starts_with("Nothing is wrong now. FollowPath failed at tick "),
        "{a}"
    );
    assert!(a.contains("; Spin failed at tick "), "{a}");
    // The bag holds no tree.
    let (ok, _, err) = common::btx(&["log", j]);
    assert!(!ok);
    assert!(
        err.contains("a rosbag holds no tree: give the tree the robot ran with --tree FILE"),
        "{err}"
    );
    // The release that recorded a bag picks how Nav2's nodes are re-run
    // (#39 item 7): Humble's messages (no uids) are Humble's; Jazzy's,
    // with uids, may be Jazzy's or later, and keep the default.
    let opened = |b: &Path| match btx::input::open(
        b,
        &btx::xml::LoadOptions {
            run_tree: Some(PathBuf::from(tree_s)),
            ..Default::default()
        },
    )
    .unwrap()
    {
        btx::input::Input::Session(s) => s.header.nav2,
        btx::input::Input::Tree { .. } => panic!("a bag"),
    };
    assert_eq!(opened(&humble), Some(btx::model::nav2::Release::Humble));
    assert_eq!(opened(&humble_db3), Some(btx::model::nav2::Release::Humble));
    assert_eq!(opened(&jazzy), None);
    // A bag and a SqliteLogger database are told apart by their tables.
    let sqlite_logger = common::fixture("logs/kitting_nominal.db3");
    let (ok, _, err) = common::btx(&["log", sqlite_logger.to_str().unwrap()]);
    assert!(ok, "{err}");
}

#[test]
fn a_run_whose_end_never_reached_the_bag_is_cut_off() {
    // Some Nav2 versions do not flush the tick that ends a run.
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let tree = dir.path().join("nav.xml");
    std::fs::write(&tree, NAV).unwrap();
    let cut = bag(dir.path(), "cut", "sqlite3", "jazzy-cut", &runs);
    let (ok, list, err) = common::btx(&[
        "log",
        cut.to_str().unwrap(),
        "--runs",
        "--tree",
        tree.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let last = list.lines().last().unwrap();
    assert!(last.contains("no end recorded after tick "), "{list}");
    assert!(
        last.ends_with("the run was cut off or is still going"),
        "{list}"
    );
    assert!(!last.contains("root SUCCESS"), "{list}");
}

/// (uid, prev, status) of each transition.
fn changes(s: &Session) -> Vec<(u32, String, String)> {
    rows(s).into_iter().map(|(_, u, p, n)| (u, p, n)).collect()
}

/// The session of run `k` of a bag, read with `tree` (and `topic`).
fn bag_run(b: &Path, tree: &Path, topic: Option<&str>, k: usize) -> Session {
    let opts = btx::xml::LoadOptions {
        run_tree: Some(tree.to_path_buf()),
        run: Some(k),
        topic: topic.map(str::to_string),
        ..Default::default()
    };
    match btx::input::open(b, &opts).unwrap() {
        btx::input::Input::Session(s) => *s,
        btx::input::Input::Tree { .. } => panic!("a bag"),
    }
}

#[test]
fn a_bag_given_another_tree_is_refused_naming_the_node_that_differs() {
    // A Jazzy bag carries each node's name beside its uid: another tree
    // of the same shape was read in its own names (#41 item 4).
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let other = dir.path().join("other.xml");
    std::fs::write(&other, NAV.replace("\"Spin\"", "\"BackUp\"")).unwrap();
    let other = other.to_str().unwrap();
    for (name, storage, release, said) in [
        (
            "j-mcap",
            "mcap",
            "jazzy",
            "is \"Spin\" in the bag but \"BackUp\" in the tree given: is it the tree the robot ran?",
        ),
        (
            "j-db3",
            "sqlite3",
            "jazzy",
            "is \"Spin\" in the bag but \"BackUp\" in the tree given: is it the tree the robot ran?",
        ),
        (
            "h-db3",
            "sqlite3",
            "humble",
            "no node of the tree given is named \"Spin\": is it the tree the robot ran?",
        ),
    ] {
        let b = bag(dir.path(), name, storage, release, &runs);
        for cmd in [&["log"][..], &["ask", "what went wrong"]] {
            let mut args = vec![cmd[0], b.to_str().unwrap()];
            args.extend(&cmd[1..]);
            args.extend(["--tree", other]);
            let (ok, out, err) = common::btx(&args);
            assert!(!ok, "{name} {cmd:?}: {out}");
            assert!(err.contains(said), "{name} {cmd:?}: {err}");
        }
    }
}

#[test]
fn a_bag_of_two_robots_is_refused_unless_a_topic_is_picked() {
    // Two namespaces' logs in one bag were read as the first, the other
    // dropped silently (#41 item 4).
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let tree = dir.path().join("nav.xml");
    std::fs::write(&tree, NAV).unwrap();
    let t = tree.to_str().unwrap();
    let second = bag(dir.path(), "one", "mcap", "jazzy", &runs[1..]);
    let alone = rows(&bag_run(&second, &tree, None, 1));
    for storage in ["mcap", "sqlite3"] {
        let b = bag(
            dir.path(),
            &format!("two-{storage}"),
            storage,
            "jazzy-two",
            &runs,
        );
        let bs = b.to_str().unwrap();
        let (ok, _, err) = common::btx(&["log", bs, "--runs", "--tree", t]);
        let err = common::one_line(&err);
        assert!(!ok, "{storage}");
        assert!(
            err.contains(
                "2 behavior_tree_log topics (/behavior_tree_log, /robot2/behavior_tree_log)"
            ) && err.contains("--topic /behavior_tree_log"),
            "{storage}: {err}"
        );
        for topic in ["/behavior_tree_log", "/robot2/behavior_tree_log"] {
            let (ok, list, err) =
                common::btx(&["log", bs, "--runs", "--tree", t, "--topic", topic]);
            assert!(ok, "{storage} {topic}: {err}");
            assert_eq!(list.lines().count(), 2, "{storage} {topic}: {list}");
        }
        // The second robot's run is that run, as a bag of its own gives it.
        let picked = bag_run(&b, &tree, Some("/robot2/behavior_tree_log"), 1);
        assert_eq!(rows(&picked), alone, "{storage}");
        // A fleet and an import take each topic as a robot of its own.
        let tables = dir.path().join(format!("tables-{storage}"));
        let (ok, report, err) = common::btx(&[
            "fleet",
            bs,
            "--tree",
            t,
            "--format",
            "json",
            "--export",
            tables.to_str().unwrap(),
        ]);
        assert!(ok, "{storage}: {err}");
        let report: serde_json::Value = serde_json::from_str(&report).unwrap();
        let names: Vec<&str> = report["each_run"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["name"].as_str().unwrap())
            .collect();
        assert_eq!(names.len(), 2, "{storage}: {names:?}");
        assert!(
            names[0].ends_with(":/behavior_tree_log")
                && names[1].ends_with(":/robot2/behavior_tree_log"),
            "{storage}: {names:?}"
        );
        assert!(
            tables.join("transitions/robot=robot2").is_dir(),
            "{storage}: {report}"
        );
        let out = dir.path().join(format!("imported-{storage}"));
        let (ok, _, err) =
            common::btx(&["import", bs, "--tree", t, "--out", out.to_str().unwrap()]);
        assert!(ok, "{storage}: {err}");
        let imported = Session::load(&out.join("robot2/run-1.jsonl")).unwrap();
        assert_eq!(rows(&imported), alone, "{storage}");
        assert!(out.join("root/run-1.jsonl").is_file(), "{err}");
        assert!(!out.join("root/run-2.jsonl").exists(), "{err}");
        let (ok, _, err) = common::btx(&[
            "log",
            bs,
            "--tree",
            t,
            "--topic",
            "/robot3/behavior_tree_log",
        ]);
        let err = common::one_line(&err);
        assert!(!ok);
        assert!(
            err.contains("no behavior_tree_log topic \"/robot3/behavior_tree_log\"; its behavior_tree_log topics: /behavior_tree_log, /robot2/behavior_tree_log"),
            "{err}"
        );
    }
}

#[test]
fn an_mcap_cut_short_is_read_up_to_its_last_whole_record() {
    // A recorder killed leaves no summary and half a record: the bag read
    // as nothing, though every message before the cut is whole (#41 item 3).
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let tree = dir.path().join("nav.xml");
    std::fs::write(&tree, NAV).unwrap();
    let t = tree.to_str().unwrap();
    let b = bag(dir.path(), "whole", "mcap", "jazzy", &runs);
    let file = std::fs::read_dir(&b)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "mcap"))
        .unwrap();
    let small = dir.path().join("small.mcap");
    rechunk::rechunked(&file, 400, false, &small);
    let whole_runs: Vec<_> = (1..=2)
        .map(|k| changes(&bag_run(&small, &tree, None, k)))
        .collect();
    let bytes = std::fs::read(&small).unwrap();
    let mut seen_runs = std::collections::BTreeSet::new();
    let mut before_any = 0;
    for pct in (10..100).step_by(3) {
        let cut = dir.path().join(format!("cut{pct}.mcap"));
        std::fs::write(&cut, &bytes[..bytes.len() * pct / 100]).unwrap();
        let cs = cut.to_str().unwrap();
        let (ok, list, err) = common::btx(&["log", cs, "--runs", "--tree", t]);
        let err = common::one_line(&err);
        if !ok {
            // Cut before its first whole message: said as such.
            assert!(
                err.contains("the bag ends in the middle of a record, before any message of Nav2's log was whole: a recorder stopped"),
                "{pct}%: {err}"
            );
            before_any += 1;
            continue;
        }
        let n = list.lines().count() - 1;
        let whole = n - usize::from(list.contains("no end recorded"));
        assert!(
            err.contains(&format!(
                "in the middle of a record: a recorder stopped; {whole} of {n} runs whole"
            )),
            "{pct}%: {err}\n{list}"
        );
        seen_runs.insert(n);
        // What was read is what the whole bag holds, up to the cut (the
        // transitions; ticks are told apart by timing over what was read).
        for k in 1..=n {
            let got = changes(&bag_run(&cut, &tree, None, k));
            assert!(!got.is_empty());
            let full = &whole_runs[k - 1];
            assert_eq!(
                &full[..got.len().min(full.len())],
                &got[..],
                "{pct}% run {k}"
            );
        }
    }
    assert!(before_any > 0);
    assert_eq!(
        seen_runs.len(),
        2,
        "cuts in the first and in the second run"
    );
}

#[test]
fn a_db3_cut_short_is_read_up_to_its_first_page_lost() {
    // SQLite refuses a file shorter than its header says ("database disk
    // image is malformed"), though the pages before the cut are whole: a
    // bag copied from a disk that ran out read as nothing (#41 item 3).
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let tree = dir.path().join("nav.xml");
    std::fs::write(&tree, NAV).unwrap();
    let t = tree.to_str().unwrap();
    let b = bag(dir.path(), "whole", "sqlite3", "jazzy", &runs);
    // Pages of 512 bytes, so that the messages span many and a cut falls
    // between them.
    let small = dir.path().join("small.db3");
    let db = rusqlite::Connection::open(b.join("whole.db3")).unwrap();
    db.execute_batch("PRAGMA page_size = 512;").unwrap();
    db.execute("VACUUM INTO ?1", [small.to_str().unwrap()])
        .unwrap();
    drop(db);
    let whole_runs: Vec<_> = (1..=2)
        .map(|k| changes(&bag_run(&small, &tree, None, k)))
        .collect();
    let bytes = std::fs::read(&small).unwrap();
    assert!(bytes.len() > 12 * 512, "{}", bytes.len());
    let mut seen_runs = std::collections::BTreeSet::new();
    let mut refused = 0;
    for at in (512..bytes.len()).step_by(61) {
        let cut = dir.path().join(format!("cut{at}.db3"));
        std::fs::write(&cut, &bytes[..at]).unwrap();
        let cs = cut.to_str().unwrap();
        let (ok, list, err) = common::btx(&["log", cs, "--runs", "--tree", t]);
        let err = common::one_line(&err);
        let ends = format!("ends at byte {at} of the {}", bytes.len());
        assert!(err.contains(&ends), "{at}: {err}");
        if !ok {
            refused += 1;
            continue;
        }
        let n = list.lines().count() - 1;
        let whole = n - usize::from(list.contains("no end recorded"));
        assert!(
            err.contains("its header says, after the change at ")
                && err.contains(&format!(
                    "the file was cut short; read up to there; {whole} of {n} runs whole"
                )),
            "{at}: {err}\n{list}"
        );
        seen_runs.insert(n);
        for k in 1..=n {
            let got = changes(&bag_run(&cut, &tree, None, k));
            let full = &whole_runs[k - 1];
            assert_eq!(&full[..got.len().min(full.len())], &got[..], "{at} run {k}");
        }
    }
    assert!(refused > 0);
    assert!(
        seen_runs.len() == 2 || seen_runs.contains(&2),
        "{seen_runs:?}"
    );
}

#[test]
fn a_bag_s_metadata_naming_a_file_outside_its_folder_is_refused() {
    // `metadata.yaml` naming ../../etc/passwd, an absolute path or a link
    // out of the bag made btx open it (#41 item 7).
    let dir = tempfile::tempdir().unwrap();
    let runs = goals(dir.path());
    let tree = dir.path().join("nav.xml");
    std::fs::write(&tree, NAV).unwrap();
    let t = tree.to_str().unwrap();
    let b = bag(dir.path(), "b", "sqlite3", "jazzy", &runs);
    let meta = std::fs::read_to_string(b.join("metadata.yaml")).unwrap();
    assert!(meta.contains("- b.db3"), "{meta}");
    // The bag's own file, through a link out of the folder and back.
    std::fs::rename(b.join("b.db3"), dir.path().join("outside.db3")).unwrap();
    std::os::unix::fs::symlink(dir.path().join("outside.db3"), b.join("link.db3")).unwrap();
    for (name, said) in [
        ("../../etc/passwd", "a path out of the bag's folder"),
        ("/etc/passwd", "an absolute path"),
        ("link.db3", "a link out of the bag's folder"),
    ] {
        std::fs::write(
            b.join("metadata.yaml"),
            meta.replace("- b.db3", &format!("- {name}")),
        )
        .unwrap();
        let (ok, _, err) = common::btx(&["log", b.to_str().unwrap(), "--tree", t]);
        let err = common::one_line(&err);
        assert!(!ok, "{name}");
        assert!(
            err.contains(&format!("relative_file_paths names {name:?}, {said}")),
            "{name}: {err}"
        );
    }
    // Inside the folder, by any name, it is read.
    std::fs::rename(dir.path().join("outside.db3"), b.join("renamed.db3")).unwrap();
    std::fs::write(
        b.join("metadata.yaml"),
        meta.replace("- b.db3", "- ./renamed.db3"),
    )
    .unwrap();
    let (ok, _, err) = common::btx(&["log", b.to_str().unwrap(), "--tree", t]);
    assert!(ok, "{err}");
}
