//! Nav2's `behavior_tree_log` recorded in rosbag2 bags (#30 item 1). The
//! runs are the real BehaviorTree.CPP's (`tests/oracle/btcpp_run.py`, with
//! its FileLogger's `.btlog`); the bags are written from them by the PyPI
//! package `rosbags` (`tests/rosbag/write_bag.py`), one message a tick as
//! Nav2's RosTopicLogger publishes. A bag's run must be its `.btlog`,
//! transition for transition, tick for tick.

mod common;
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
