//! Watching a BehaviorTree.CPP 3 robot (Nav2 Humble) over Groot 1's
//! protocol, `PublisherZMQ`: the tree on the server port, statuses and
//! transitions on the port below. Two publishers btx did not write:
//! `tests/live/groot1_robot.py`, which sends the real library's recorded
//! runs (the v3 `.fbl` fixtures, from ../shared/fixtures/btcpp, recorded
//! with BehaviorTree.CPP 3.8.8) in the publisher's message layout through
//! libzmq; and btview's v3 mock (PyPI btview 0.2.0), with its own count of
//! what it sent.

mod common;

use btx::input::{open, Input};
use btx::session::Session;
use btx::xml::LoadOptions;
use common::{fixture, oracle_python};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

fn free_port() -> u16 {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    l.local_addr().unwrap().port()
}

/// A server port with the port below it free too (the publisher's).
fn free_pair() -> u16 {
    loop {
        let p = free_port();
        if p > 1 && TcpListener::bind(("127.0.0.1", p - 1)).is_ok() {
            return p;
        }
    }
}

fn session(p: &Path) -> Session {
    match open(p, &LoadOptions::default()).unwrap() {
        Input::Session(s) => *s,
        Input::Tree { .. } => panic!("{} is a run", p.display()),
    }
}

fn script(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/live")
        .join(name)
}

/// A publisher started from `args`, once it said READY.
struct Publisher {
    child: Child,
    said: std::io::Lines<BufReader<ChildStdout>>,
}

impl Publisher {
    fn start(args: &[&std::ffi::OsStr]) -> Publisher {
        let mut child = Command::new(oracle_python())
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("the publisher starts");
        let mut said = BufReader::new(child.stdout.take().unwrap()).lines();
        assert_eq!(said.next().unwrap().unwrap(), "READY");
        Publisher { child, said }
    }

    /// `groot1_robot.py`: the `.fbl` fixture `run` replayed with its server
    /// on `server`, its publisher on `publisher`, batches `gap_ms` apart.
    fn replaying(run: &str, server: u16, publisher: u16, gap_ms: u32) -> Publisher {
        let fbl = fixture(&format!("logs/{run}"));
        Publisher::start(&[
            script("groot1_robot.py").as_os_str(),
            fbl.as_os_str(),
            server.to_string().as_ref(),
            publisher.to_string().as_ref(),
            gap_ms.to_string().as_ref(),
        ])
    }

    fn go(&mut self) {
        writeln!(self.child.stdin.as_mut().unwrap(), "go").unwrap();
    }

    /// "DONE N": how many transitions it sent.
    fn done(mut self) -> usize {
        let line = self.said.next().unwrap().unwrap();
        let _ = self.child.wait();
        line.strip_prefix("DONE ").unwrap().parse().unwrap()
    }
}

/// `btx watch` with `args`, started once it said it watches; its exit
/// status and standard error, after `then` ran.
fn watch(args: &[&str], then: impl FnOnce()) -> (bool, String) {
    let mut w = Command::new(env!("CARGO_BIN_EXE_btx"))
        .arg("watch")
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(w.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert!(first.starts_with("watching "), "{first}");
    then();
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    let ok = w.wait().unwrap().success();
    (ok, first + rest.as_str())
}

/// The real library's recorded run, watched as its publisher would have
/// sent it: the session btx keeps is the `.fbl`'s, tick for tick.
fn a_recorded_run_is_watched_whole(run: &str) {
    let fbl = fixture(&format!("logs/{run}"));
    let port = free_pair();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("watched.jsonl");
    let mut robot = Publisher::replaying(run, port, port - 1, 5);
    let (ok, err) = watch(
        &[&format!(":{port}"), "--out", out.to_str().unwrap()],
        || robot.go(),
    );
    let sent = robot.done();
    assert!(ok, "{err}");
    // The robot exits once its run is over: the end, not a gap.
    assert!(
        err.contains(
            "the robot's run finished (root SUCCESS), then the robot closed the connection"
        ),
        "{err}"
    );
    assert!(!err.contains("gap"), "{err}");
    assert_eq!(
        err.matches("does not send the blackboard").count(),
        1,
        "said once: {err}"
    );
    let (logged, watched) = (session(&fbl), session(&out));
    assert_eq!(watched.index.transitions.len(), sent);
    assert_eq!(watched.index.transitions, logged.index.transitions, "{run}");
    assert_eq!(watched.index.ticks(), logged.index.ticks(), "{run}");
    assert!(watched
        .warnings
        .iter()
        .all(|w| !w.message.contains("dropped")));
    // Both ended by the root's last transition, at the same tick.
    let end = |s: &Session| s.ending().split(" (").next().unwrap().to_string();
    assert_eq!(end(&watched), end(&logged), "{run}");
}

#[test]
fn the_kitting_run_with_a_failed_look_is_watched_whole() {
    a_recorded_run_is_watched_whole("kitting_lookat_fails_once_v3.fbl");
}

#[test]
fn the_taxi_run_is_watched_whole() {
    a_recorded_run_is_watched_whole("taxi_nominal_v3.fbl");
}

#[test]
fn a_publisher_on_another_port_is_given_or_named() {
    let fbl = fixture("logs/kitting_grasp_check_fails_first_v3.fbl");
    let (server, publisher) = (free_port(), free_port());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("watched.jsonl");
    let mut robot = Publisher::replaying(
        "kitting_grasp_check_fails_first_v3.fbl",
        server,
        publisher,
        5,
    );
    // Not the port below: said within two seconds, naming the option
    // (unless that port happens to serve something else).
    if publisher != server - 1 && TcpListener::bind(("127.0.0.1", server - 1)).is_ok() {
        let start = Instant::now();
        let (ok, _, err) = common::btx(&["watch", &format!(":{server}")]);
        assert!(!ok);
        assert!(start.elapsed() < Duration::from_secs(3));
        assert!(err.contains("nothing is listening"), "{err}");
        assert!(err.contains("give it with --publisher-port"), "{err}");
    }
    let (ok, err) = watch(
        &[
            &format!(":{server}"),
            "--publisher-port",
            &publisher.to_string(),
            "--out",
            out.to_str().unwrap(),
        ],
        || robot.go(),
    );
    robot.done();
    assert!(ok, "{err}");
    assert_eq!(
        session(&out).index.transitions,
        session(&fbl).index.transitions
    );
    // One option, one robot.
    let (ok, _, err) = common::btx(&[
        "watch",
        ":1",
        ":2",
        "--publisher-port",
        &publisher.to_string(),
    ]);
    assert!(!ok);
    assert!(err.contains("with several robots"), "{err}");
}

#[test]
fn attached_to_a_running_robot_btx_takes_each_nodes_state_from_its_message() {
    // The run's 7 batches 400 ms apart; btx attaches after the second.
    let fbl = fixture("logs/kitting_lookat_fails_once_v3.fbl");
    let port = free_pair();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("late.jsonl");
    let mut robot = Publisher::replaying("kitting_lookat_fails_once_v3.fbl", port, port - 1, 400);
    robot.go();
    std::thread::sleep(Duration::from_millis(600));
    let (ok, err) = watch(
        &[
            &format!(":{port}"),
            "--for",
            "8",
            "--out",
            out.to_str().unwrap(),
        ],
        || {},
    );
    robot.done();
    assert!(ok, "{err}");
    assert!(
        err.contains("btx attached to a robot that had been running"),
        "{err}"
    );
    let logged = session(&fbl);
    let watched = session(&out);
    // What btx kept is the end of the run, each transition from the
    // status the robot's record says it left: the states btx took when
    // it attached were the robot's.
    let key = |t: &btx::session::Transition| (t.uid, t.prev, t.status);
    let (l, w): (Vec<_>, Vec<_>) = (
        logged.index.transitions.iter().map(key).collect(),
        watched.index.transitions.iter().map(key).collect(),
    );
    assert!(
        !w.is_empty() && w.len() < l.len(),
        "{} of {}",
        w.len(),
        l.len()
    );
    assert_eq!(w[..], l[l.len() - w.len()..]);
}

#[test]
fn btviews_v3_mock_is_watched_with_every_transition_it_sent() {
    let port = free_pair();
    let dir = tempfile::tempdir().unwrap();
    let (out, sent) = (dir.path().join("mock.jsonl"), dir.path().join("sent.json"));
    let mut mock = Publisher::start(&[
        script("btview_v3.py").as_os_str(),
        port.to_string().as_ref(),
        (port - 1).to_string().as_ref(),
        "50".as_ref(),
        "60".as_ref(),
        sent.as_os_str(),
    ]);
    // 60 ticks at 50 Hz take 1.2 s; the mock stays until btx is done.
    let (ok, err) = watch(
        &[
            &format!(":{port}"),
            "--for",
            "5",
            "--out",
            out.to_str().unwrap(),
        ],
        || mock.go(),
    );
    mock.go();
    let n = mock.done();
    assert!(ok, "{err}");
    assert!(!err.contains("gap"), "{err}");
    let sent: Vec<(u32, u8, u8)> =
        serde_json::from_str(&std::fs::read_to_string(&sent).unwrap()).unwrap();
    assert_eq!(sent.len(), n);
    assert!(n > 50, "the mock sent {n}");
    // The mock ticks its tree again after each run: each run is a
    // session of its own (`OUT`, `OUT-2.jsonl`, …), every transition kept.
    let runs: Vec<_> = (1..)
        .map(|k| btx::live::recorder::run_path(&out, k))
        .take_while(|p| p.exists())
        .collect();
    assert!(runs.len() > 1, "{err}");
    let got: Vec<(u32, u8, u8)> = runs
        .iter()
        .flat_map(|p| session(p).index.transitions)
        .map(|t| (t.uid, t.prev.code(), t.status.code()))
        .collect();
    assert_eq!(got, sent);
}

#[test]
fn ask_live_reads_a_groot1_robot_at_this_moment() {
    let port = free_pair();
    let mut robot = Publisher::replaying("kitting_lookat_fails_once_v3.fbl", port, port - 1, 400);
    let ep = format!(":{port}");
    // Before it ticks the robot publishes nothing: its states are not
    // known, and that is said.
    let (ok, text, err) = common::btx(&["ask", "--live", &ep, "--node", "#1", "q1"]);
    assert!(ok, "{err}");
    assert!(err.contains("published nothing within 0.6 s"), "{err}");
    assert_eq!(text, "I have not started yet.\n");
    // The run's 7 batches 400 ms apart: asked while the robot runs.
    robot.go();
    std::thread::sleep(Duration::from_millis(600));
    let (ok, text, err) = common::btx(&["ask", "--live", &ep, "q1"]);
    robot.done();
    assert!(ok, "{err}");
    assert!(
        text.starts_with("I ") && !text.contains("not started"),
        "{text}"
    );
    // Nothing asked reads the blackboard: its absence goes unsaid.
    assert!(err.is_empty(), "{err}");
}

/// #40: the faults of a BehaviorTree.CPP 3 robot are said as they come
/// over Groot 1's protocol, as they are of a Groot2 server's.
#[test]
fn a_groot1_robots_fault_and_its_recovery_are_said() {
    let port = free_pair();
    let mut robot = Publisher::replaying("kitting_lookat_fails_once_v3.fbl", port, port - 1, 5);
    let mut w = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["watch", &format!(":{port}"), "--for", "60"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(w.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert!(first.starts_with("watching "), "{first}");
    robot.go();
    robot.done();
    let out = w.wait_with_output().unwrap();
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    assert!(out.status.success(), "{first}{rest}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = stdout
        .lines()
        .map(|l| l.split_once(" UTC  ").map_or(l, |x| x.1))
        .collect();
    assert_eq!(lines.len(), 3, "{stdout}");
    assert!(
        // BehaviorTree.CPP 3 spells it RetryUntilSuccesful.
        lines[0]
            .starts_with("10:1 look at chuck failed; insert large gear failed; RetryUntilSucces"),
        "{stdout}"
    );
    assert!(
        lines[0].ends_with("tries again, attempt 2 of 3"),
        "{stdout}"
    );
    assert!(
        lines[1].contains(" recovered: RetryUntilSucces"),
        "{stdout}"
    );
    assert_eq!(lines[2], "run 1 ended at tick 54: SUCCESS");
}

#[test]
fn a_flooding_publisher_is_watched_in_bounded_memory() {
    // A BehaviorTree.CPP 3 publisher flooding one tick that never ends
    // aborted `btx watch` at 2.7 GB within 7 s, its session holding only
    // its header (#41 item 1).
    let server = free_pair();
    let mut robot = Publisher::start(&[
        script("groot1_robot.py").as_os_str(),
        fixture("logs/taxi_nominal_v3.fbl").as_os_str(),
        server.to_string().as_ref(),
        (server - 1).to_string().as_ref(),
        "flood:6".as_ref(),
    ]);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("flood.jsonl");
    let mut w = Command::new("prlimit")
        .arg("--as=2147483648")
        .arg("--")
        .arg(env!("CARGO_BIN_EXE_btx"))
        .args(["watch", &format!(":{server}"), "--for", "5", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(w.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert!(first.starts_with("watching "), "{first}");
    robot.go();
    let mut rest = String::new();
    err.read_to_string(&mut rest).unwrap();
    let ended = common::wait_peak(w);
    let sent = robot.done();
    // The recorded run's timestamps are days old: no latency is said.
    assert!(
        rest.contains("from the robot to here: unknown (the robot's timestamps are"),
        "{rest}"
    );
    assert_eq!(ended.code, Some(0), "{rest}");
    assert!(
        rest.contains("transitions with no tick's end: that tick is closed there"),
        "{rest}"
    );
    assert!(
        ended.peak_kib < 200 << 10,
        "peak {} MiB",
        ended.peak_kib >> 10
    );
    let kept = session(&out);
    assert!(
        kept.index.transitions.len() > 1_000_000,
        "{} of {sent}: {rest}",
        kept.index.transitions.len()
    );
}
