//! Hostile input and the data btx writes (issue "Hostile input and big
//! runs"): nothing btx writes is unreadable by btx, data never drives the
//! terminal, a closed pipe ends btx quietly, a loop within a tick stops,
//! and a located error past column 65,535 is an error, not a panic.

mod common;
use common::*;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// The address space every btx run here gets (`prlimit --as`): what the
/// issue's hostile inputs were tried under, halved. It holds btx's 256 MiB
/// stack reservation, the allocator's arenas and the heap.
const AS_MAX: u64 = 1 << 30;

/// What a run of btx under `AS_MAX` did.
struct Run {
    code: Option<i32>,
    out: String,
    err: String,
    /// The length of standard output (kept only up to 16 MiB in `out`).
    out_len: u64,
    /// Peak resident memory, KiB: btx's, or this test process's at the
    /// fork if that was more (Linux keeps the larger across exec), so a
    /// check that it is small never passes wrongly. Tests here keep their
    /// own memory small (outputs past 16 MiB are not read) for that reason.
    peak_kib: i64,
}

/// Runs btx under `prlimit --as=AS_MAX` and measures its peak memory (the
/// child's own rusage, through wait4: per child, even with tests running in
/// parallel). Output goes through files so no pipe fills.
fn btx_run(args: &[&str]) -> Run {
    let dir = tempfile::tempdir().unwrap();
    let (o, e) = (dir.path().join("out"), dir.path().join("err"));
    let child = Command::new("prlimit")
        .arg(format!("--as={AS_MAX}"))
        .arg("--")
        .arg(env!("CARGO_BIN_EXE_btx"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&o).unwrap())
        .stderr(std::fs::File::create(&e).unwrap())
        .spawn()
        .expect("prlimit (util-linux) runs btx under a memory ceiling");
    let Ended {
        code,
        status,
        peak_kib,
    } = wait_peak(child);
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
    let err = read(&e);
    let out_len = std::fs::metadata(&o).unwrap().len();
    assert!(
        code.is_some() && code != Some(101) && code != Some(134),
        "btx {args:?} ended by a signal or a panic ({status:#x}): {err}"
    );
    Run {
        code,
        out: if out_len <= 16 << 20 {
            read(&o)
        } else {
            String::new()
        },
        err,
        out_len,
        peak_kib,
    }
}

/// Runs btx and returns (exit code, stdout, stderr).
fn btx_code(args: &[&str]) -> (Option<i32>, String, String) {
    let r = btx_run(args);
    (r.code, r.out, r.err)
}

/// The shipped case-study session's header, to edit, and its records.
fn case_study_header() -> (serde_json::Value, String) {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/case-study.jsonl"),
    )
    .unwrap();
    let (header, rest) = text.split_once('\n').unwrap();
    (serde_json::from_str(header).unwrap(), rest.to_string())
}

#[test]
fn infinity_and_nan_round_trip_through_a_session() {
    let dir = tempfile::tempdir().unwrap();
    let tree = write(
        dir.path(),
        "inf.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><Sequence><Script code="k := 9e307 * 10"/><ScriptCondition code="k &gt; 5"/><Script code="n := k - k"/><Script code="m := 0 - k"/></Sequence></BehaviorTree></root>"#,
    );
    let plan = write(dir.path(), "inf.plan", "");
    let out = dir.path().join("inf.jsonl").display().to_string();
    let (ok, _, err) = btx(&["run", &tree, "--plan", &plan, "--out", &out]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    for v in [r#""value":"inf""#, r#""value":"nan""#, r#""value":"-inf""#] {
        assert!(text.contains(v), "{v} in {text}");
    }
    assert!(!text.contains(r#""value":null"#), "{text}");
    // Every command reads what btx wrote.
    for args in [
        vec!["log", out.as_str()],
        vec!["ask", out.as_str(), "q1"],
        vec!["tree", out.as_str()],
        vec!["why", out.as_str(), "status(#3)"],
    ] {
        let (ok, _, err) = btx(&args);
        assert!(ok, "{args:?}: {err}");
    }
    // And the script read infinity back as a number: k > 5 held.
    let s = btx::session::Session::load(Path::new(&out)).unwrap();
    assert!(s
        .index
        .transitions
        .iter()
        .any(|t| t.uid == 3 && t.status == btx::run::Status::Success));
}

#[test]
fn data_never_drives_the_terminal() {
    let dir = tempfile::tempdir().unwrap();
    // A window-title (OSC 0), a clear-screen and an OSC 52 clipboard write.
    let tree = write(
        dir.path(),
        "esc.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence name="a&#x1b;]0;pwned&#x07;b"><AlwaysSuccess name="x&#x1b;[2Jy"/><AlwaysFailure name="&#x1b;]52;c;ZXZpbA==&#x07;"/></Sequence></BehaviorTree></root>"#,
    );
    for args in [
        vec!["tree", tree.as_str()],
        vec!["tree", tree.as_str(), "--framed"],
        vec!["tree", tree.as_str(), "--format", "dot"],
        vec!["ask", tree.as_str(), "--node", "#2", "q1", "q2"],
    ] {
        let (code, out, err) = btx_code(&args);
        assert_eq!(code, Some(0), "{args:?}: {err}");
        assert!(
            !out.contains('\u{1b}') && !out.contains('\u{7}'),
            "{args:?}: {out:?}"
        );
        assert!(out.contains("\\x1b"), "{args:?}: {out:?}");
    }
    // Error messages too (the closest nodes of a bad pick name them).
    let (code, _, err) = btx_code(&["ask", &tree, "--node", "nothing like it", "q1"]);
    assert_eq!(code, Some(1));
    assert!(!err.contains('\u{1b}'), "{err:?}");
    // JSON stays exact, escaped by JSON's rules.
    let (code, out, _) = btx_code(&["tree", &tree, "--format", "json"]);
    assert_eq!(code, Some(0));
    assert!(out.contains("\\u001b"), "{out}");
}

#[test]
fn a_closed_pipe_ends_btx_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["log", "sessions/serial-recall.jsonl"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read a little, then close the pipe, as `| head -c1` does.
    let mut stdout = child.stdout.take().unwrap();
    let mut one = [0u8; 1];
    stdout.read_exact(&mut one).unwrap();
    drop(stdout);
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
}

#[test]
fn a_loop_within_a_tick_is_stopped_with_the_node_and_tick() {
    let dir = tempfile::tempdir().unwrap();
    // v3 has no wake-up path: Repeat -1 over an action that succeeds at once
    // would tick forever within tick 1.
    let tree = write(
        dir.path(),
        "loop.xml",
        r#"<root BTCPP_format="3" main_tree_to_execute="M"><BehaviorTree ID="M"><Repeat num_cycles="-1"><go name="go"/></Repeat></BehaviorTree></root>"#,
    );
    let plan = write(dir.path(), "loop.plan", "go = S\n");
    let out = dir.path().join("loop.jsonl").display().to_string();
    let (code, _, err) = btx_code(&["run", &tree, "--plan", &plan, "--out", &out]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("tick 1: Repeat #1: ticked its child go 100000 times within tick 1"),
        "{err}"
    );
    // In v4 the wake-up path ends each tick after one cycle.
    let tree = write(
        dir.path(),
        "loop4.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><Repeat num_cycles="-1"><go name="go"/></Repeat></BehaviorTree></root>"#,
    );
    let out4 = dir.path().join("loop4.jsonl").display().to_string();
    let (code, _, err) = btx_code(&[
        "run",
        &tree,
        "--plan",
        &plan,
        "--max-ticks",
        "5",
        "--out",
        &out4,
    ]);
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn an_error_past_column_65535_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    // One line: n leaves, then an Inverter without a child (the error).
    let one_line = |name: &str, n: usize| {
        write(
            dir.path(),
            name,
            &format!(
                r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>{}<Inverter/></Sequence></BehaviorTree></root>"#,
                "<AlwaysSuccess/>".repeat(n)
            ),
        )
    };
    let tree = one_line("long.xml", 5000);
    let (code, _, err) = btx_code(&["tree", &tree]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("long.xml:1:80055"), "{err}");
    assert!(err.contains("Decorator \"Inverter\" must have"), "{err}");
    // A line of a few hundred bytes is shown; a longer one is not quoted.
    for (n, shown) in [(10, true), (60, false)] {
        let tree = one_line("mid.xml", n);
        let (code, _, err) = btx_code(&["tree", &tree]);
        assert_eq!(code, Some(1), "{err}");
        assert_eq!(
            err.contains("<AlwaysSuccess/><AlwaysSuccess/>"),
            shown,
            "{err}"
        );
        assert!(err.len() < 1500, "{}", err.len());
    }
}

#[test]
fn trees_in_logs_and_sessions_read_no_other_file() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, rest) = case_study_header();
    let xml = h["tree"]["xml"].as_str().unwrap().to_string();
    let i = xml.find("<BehaviorTree").unwrap();
    h["tree"]["xml"] = serde_json::Value::from(format!(
        "{}<include path=\"/etc/passwd\"/>{}",
        &xml[..i],
        &xml[i..]
    ));
    let path = dir.path().join("evil.jsonl");
    std::fs::write(&path, format!("{h}\n{rest}")).unwrap();
    let (code, _, err) = btx_code(&["log", path.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{err}");
    let e = match btx::session::Session::load(&path) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("the session opened"),
    };
    assert!(
        e.ends_with("an <include> in a tree embedded in a log or a session is not followed: BehaviorTree.CPP's instantiated XML never has one"),
        "{e}"
    );
}

#[test]
fn devices_and_fifos_are_refused_at_once() {
    let (code, _, err) = btx_code(&["tree", "/dev/zero"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("not a regular file"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let (code, _, err) = btx_code(&["tree", fifo.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(err.contains("not a regular file"), "{err}");
}

#[test]
fn numbers_taken_from_files_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    // A session whose blackboard names a scope its tree does not have.
    let (mut h, rest) = case_study_header();
    h["blackboard"] = serde_json::json!([[{"scope": 999, "key": "X_a"}, true]]);
    let path = dir.path().join("scope.jsonl");
    std::fs::write(&path, format!("{h}\n{rest}")).unwrap();
    for cmd in ["why", "log"] {
        let mut args = vec![cmd, path.to_str().unwrap()];
        if cmd == "why" {
            args.push("X_a");
        }
        let (code, _, err) = btx_code(&args);
        assert_eq!(code, Some(1), "{cmd}: {err}");
        assert!(err.contains("scope 999"), "{err}");
    }
    // A float grid of 2^64 - 1 values.
    let domain = write(
        dir.path(),
        "grid.domain.toml",
        "btx_domain = 1\nname = \"g\"\n[state.x]\ntype = \"float\"\nmin = 0.0\nmax = 1.0\ngrid = 18446744073709551615\n[leaf.\"@default_action\"]\nstatus = \"SUCCESS\"\n",
    );
    let (code, _, err) = btx_code(&[
        "run",
        "trees/taxi.xml",
        "--domain",
        &domain,
        "--out",
        dir.path().join("g.jsonl").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("grid 18446744073709551615 is more"), "{err}");
    // Sizes from the command line.
    let (code, _, err) = btx_code(&["eval", "recovery", "random", "--seeds", "4294967295"]);
    assert_eq!(code, Some(2), "{err}");
    let (code, _, err) = btx_code(&[
        "screenshot",
        "--demo",
        "main",
        "--out",
        dir.path().join("s.svg").to_str().unwrap(),
        "--width",
        "60000",
    ]);
    assert_eq!(code, Some(2), "{err}");
}

/// A tree of `n` Inverters nested over one leaf.
fn inverters(n: usize) -> String {
    format!(
        r#"<root BTCPP_format="4"><BehaviorTree ID="M">{}<AlwaysSuccess/>{}</BehaviorTree></root>"#,
        "<Inverter>".repeat(n),
        "</Inverter>".repeat(n)
    )
}

#[test]
fn deep_wide_and_nested_inputs_are_refused_with_their_limit() {
    let dir = tempfile::tempdir().unwrap();
    // 100,000 levels of nesting: refused by the reader, as tinyxml2 does.
    let deep = write(dir.path(), "deep.xml", &inverters(100_000));
    let (code, _, err) = btx_code(&["tree", &deep]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("deeper than 500 levels"), "{err}");
    // 450 levels load, and print.
    let ok = write(dir.path(), "ok.xml", &inverters(450));
    let (code, _, err) = btx_code(&["tree", &ok]);
    assert_eq!(code, Some(0), "{err}");
    // 40 trees, each calling the next twice: 2^40 instances.
    let mut xml = String::from(r#"<root BTCPP_format="4" main_tree_to_execute="T0">"#);
    for i in 0..40 {
        xml.push_str(&format!(
            r#"<BehaviorTree ID="T{i}"><Sequence><SubTree ID="T{j}" name="a"/><SubTree ID="T{j}" name="b"/></Sequence></BehaviorTree>"#,
            j = i + 1
        ));
    }
    xml.push_str(r#"<BehaviorTree ID="T40"><AlwaysSuccess/></BehaviorTree></root>"#);
    let fan = write(dir.path(), "fan.xml", &xml);
    let (code, _, err) = btx_code(&["tree", &fan]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("250000 nodes"), "{err}");
    // A script with 4,000 nested parentheses: an error, quoted short.
    let script = write(
        dir.path(),
        "script.xml",
        &format!(
            r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><Script code="k := {}1{}"/></BehaviorTree></root>"#,
            "(".repeat(4000),
            ")".repeat(4000)
        ),
    );
    let plan = write(dir.path(), "empty.plan", "");
    let out = dir.path().join("s.jsonl").display().to_string();
    let (code, _, err) = btx_code(&["run", &script, "--plan", &plan, "--out", &out]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("nests deeper than 200 levels"), "{err}");
    assert!(err.contains("(8006 bytes in all)"), "{err}");
    assert!(err.len() < 2000, "{}", err.len());
}

#[test]
fn a_wal_mode_database_is_read_with_the_rows_in_its_wal() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("w.db3");
    std::fs::copy(fixture("logs/kitting_nominal.db3"), &db).unwrap();
    // A writer in WAL mode that has not checkpointed: a second session
    // lives in `w.db3-wal` only, while the writer stays connected.
    let c = rusqlite::Connection::open(&db).unwrap();
    let mode: String = c
        .query_row("PRAGMA journal_mode=WAL", [], |r| r.get(0))
        .unwrap();
    assert_eq!(mode, "wal");
    c.execute_batch(
        "PRAGMA wal_autocheckpoint=0;
         INSERT INTO Definitions(session_id, date, xml_tree) SELECT 99, date, xml_tree FROM Definitions LIMIT 1;
         INSERT INTO Nodes(session_id, fullpath, node_uid) SELECT 99, fullpath, node_uid FROM Nodes WHERE session_id = 1;
         INSERT INTO Transitions(timestamp, session_id, node_uid, duration, state, extra_data)
           SELECT timestamp + 100000000000, 99, node_uid, duration, state, extra_data FROM Transitions WHERE session_id = 1;",
    )
    .unwrap();
    assert!(dir.path().join("w.db3-wal").exists());
    let before = std::fs::read(&db).unwrap();
    let (code, out, err) = btx_code(&["log", db.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("this is session 99"), "{err}");
    assert_eq!(out.lines().count(), 1 + 209, "every row of the WAL is read");
    // The database was not touched, and the writer goes on.
    assert_eq!(std::fs::read(&db).unwrap(), before);
    // A sparse 3 GB `-wal` (its frames, then a hole) was copied whole into
    // the temporary folder (#41 item 3): its data only is, so it reads in
    // a temporary folder of 4 MiB, the same rows.
    let wal = std::fs::OpenOptions::new()
        .write(true)
        .open(dir.path().join("w.db3-wal"))
        .unwrap();
    wal.set_len(3 << 30).unwrap();
    let small = tempfile::tempdir().unwrap();
    let script = format!(
        "mount -t tmpfs -o size=4096k none {t} && cd {root} && TMPDIR={t} exec {btx} log {db}",
        t = small.path().display(),
        root = env!("CARGO_MANIFEST_DIR"),
        btx = env!("CARGO_BIN_EXE_btx"),
        db = db.display(),
    );
    let r = Command::new("unshare")
        .args(["--user", "--map-root-user", "--mount", "sh", "-c", &script])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{err}");
    assert!(err.contains("this is session 99"), "{err}");
    assert_eq!(String::from_utf8_lossy(&r.stdout).lines().count(), 1 + 209);
    c.execute("DELETE FROM Transitions WHERE session_id = 99", [])
        .unwrap();
}

#[test]
fn warnings_past_fifty_are_counted_not_listed() {
    let dir = tempfile::tempdir().unwrap();
    // 5,000 uses of 60 IDs: one warning per ID, 50 shown, the hint, a count.
    let leaves: String = (0..5000).map(|i| format!("<U{}/>", i % 60)).collect();
    let tree = write(
        dir.path(),
        "u.xml",
        &format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>{leaves}</Sequence></BehaviorTree></root>"#
        ),
    );
    let (code, _, err) = btx_code(&["tree", &tree]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(err.lines().count(), 52, "{err}");
    assert!(
        err.contains("unknown node \"U0\" has no model in <TreeNodesModel>; treated as an Action (84 uses; this is the first)"),
        "{err}"
    );
    assert!(err.contains("60 node IDs have no model"), "{err}");
    assert!(
        err.ends_with("10 more warnings are not shown (the first 50 are)\n"),
        "{err}"
    );
}

#[test]
fn unclear_or_silent_cases_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let (code, _, err) = btx_code(&["ask", "trees/kitting.xml", "--node", "#99999", "q1"]);
    assert_eq!(code, Some(1));
    assert_eq!(
        err,
        "  × there is no node #99999: the tree's uids are 1 to 79\n"
    );
    let sub = dir.path().join("dir");
    std::fs::create_dir(&sub).unwrap();
    let log = dir.path().join("x.btlog");
    std::fs::copy(fixture("logs/kitting_nominal.btlog"), &log).unwrap();
    for (out, says) in [
        (sub.to_str().unwrap(), "a directory is here"),
        ("/dev/null", "this is a device, a FIFO or a link"),
        (
            log.to_str().unwrap(),
            "a file that is not a btx session is here",
        ),
    ] {
        let (code, _, err) = btx_code(&[
            "run",
            "trees/kitting.xml",
            "--world",
            "kitting",
            "--out",
            out,
        ]);
        assert_eq!(code, Some(1), "{out}");
        assert!(err.contains(says), "{out}: {err}");
    }
    let plan = write(dir.path(), "p.plan", "@default_actoin = 1RS\n");
    let (code, _, err) = btx_code(&[
        "run",
        "trees/kitting.xml",
        "--plan",
        &plan,
        "--out",
        dir.path().join("s.jsonl").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("\"@default_actoin\" is not a plan directive"),
        "{err}"
    );
}

#[test]
fn a_script_cannot_grow_a_string_without_bound() {
    let dir = tempfile::tempdir().unwrap();
    let scripts = r#"<Script code="x := x .. x"/>"#.repeat(64);
    let tree = write(
        dir.path(),
        "s.xml",
        &format!(
            r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><Sequence><Script code="x := 'ab'"/>{scripts}</Sequence></BehaviorTree></root>"#
        ),
    );
    let plan = write(dir.path(), "s.plan", "");
    let out = dir.path().join("s.jsonl").display().to_string();
    let (code, _, err) = btx_code(&["run", &tree, "--plan", &plan, "--out", &out]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("more than the 1048576 a script may make"),
        "{err}"
    );
}

#[test]
fn long_runs_with_little_in_common_align_in_bounded_time() {
    use btx::diff::align::edits_bounded;
    // Nothing in common: exact at once.
    let a: Vec<u32> = (0..50_000).collect();
    let b: Vec<u32> = (50_000..100_000).collect();
    let (e, exact) = edits_bounded(&a, &b);
    assert!(exact);
    assert_eq!(btx::diff::align::distance(&e), 100_000);
    // A little in common: the time bound may be reached; the script is
    // then an upper bound, never wrong: it turns a into b.
    let a: Vec<u32> = (0..50_000)
        .map(|i| if i % 100 == 0 { 0 } else { i + 1 })
        .collect();
    let b: Vec<u32> = (0..50_000)
        .map(|i| if i % 100 == 0 { 0 } else { i + 100_000 })
        .collect();
    let (e, _) = edits_bounded(&a, &b);
    let mut out = Vec::new();
    for x in &e {
        if let Some(j) = x.b {
            out.push(b[j]);
        }
    }
    assert_eq!(out, b);
    assert_eq!(e.iter().filter_map(|x| x.a).count(), a.len());
}

#[path = "common/trees.rs"]
mod trees;

#[path = "hostile/outputs.rs"]
mod outputs;
#[path = "hostile/peers.rs"]
mod peers;

/// Nothing btx writes is unreadable by btx: generated trees (every
/// built-in node kind, scripts, the blackboard, SubTrees) run from random
/// plans, and every command reads the session the run wrote.
#[test]
fn every_command_reads_every_session_btx_writes() {
    let dir = tempfile::tempdir().unwrap();
    let mut ran = 0;
    for seed in 0..24u64 {
        let case = trees::generate(seed * 7919 + 3);
        let tree = write(dir.path(), &format!("{seed}.xml"), &case.xml);
        let plan = write(dir.path(), &format!("{seed}.plan"), &case.plan);
        let out = dir
            .path()
            .join(format!("{seed}.jsonl"))
            .display()
            .to_string();
        let (code, _, err) = btx_code(&[
            "run",
            &tree,
            "--plan",
            &plan,
            "--max-ticks",
            "24",
            "--out",
            &out,
            "-q",
        ]);
        // A run may stop on an error the library would throw too; the
        // session up to there is kept, and read like any other.
        assert!(matches!(code, Some(0 | 1)), "{err}");
        if !Path::new(&out).exists() {
            continue;
        }
        ran += 1;
        for args in [
            vec!["log", out.as_str()],
            vec!["log", out.as_str(), "--format", "json"],
            vec!["tree", out.as_str()],
            vec![
                "ask",
                out.as_str(),
                "--node",
                "#1",
                "q1",
                "q2",
                "wrong",
                "handled",
            ],
            vec!["why", out.as_str(), "status(#1)"],
            vec!["graph", out.as_str()],
            vec!["diff", out.as_str(), out.as_str()],
        ] {
            let (code, _, err) = btx_code(&args);
            assert_eq!(code, Some(0), "seed {seed}: {args:?}: {err}");
        }
    }
    assert!(ran >= 20, "{ran} runs wrote a session");
}

#[test]
fn silent_cases_now_speak() {
    let dir = tempfile::tempdir().unwrap();
    // --set with a world would change nothing (with a plan it seeds the
    // blackboard: tests/cli.rs).
    for source in [["--world", "kitting"], ["--world", "taxi"]] {
        let out = dir.path().join("set.jsonl");
        let mut args = vec!["run", "trees/kitting.xml", "--set", "x=1", "--out"];
        args.push(out.to_str().unwrap());
        args.extend(source);
        let (code, _, err) = btx_code(&args);
        assert_eq!(code, Some(1), "{err}");
        assert!(
            err.contains("--set starts a domain's state variable or a plan's blackboard entry, and a world has neither"),
            "{err}"
        );
        assert!(!out.exists());
    }
    // --ask-at past the end of the run.
    let (code, _, err) = btx_code(&[
        "run",
        "trees/kitting.xml",
        "--world",
        "kitting",
        "--ask-at",
        "500",
        "Can you insert large gear?",
        "--out",
        dir.path().join("a.jsonl").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("the run ended at tick 46, before tick 500 where --ask-at was to ask"),
        "{err}"
    );
    // end_after naming no leaf.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("trees/serial-recall.domain.toml"),
    )
    .unwrap()
    .replace("end_after = [\"EndGame\"]", "end_after = [\"EndGmae\"]");
    let domain = write(dir.path(), "d.toml", &text);
    let (code, _, err) = btx_code(&[
        "run",
        "trees/serial-recall.xml",
        "--domain",
        &domain,
        "--out",
        dir.path().join("b.jsonl").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("end_after names \"EndGmae\""), "{err}");
}

#[test]
fn a_utf16_file_is_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("u16.xml");
    let mut bytes = vec![0xFF, 0xFE];
    for u in "<root BTCPP_format=\"4\"/>".encode_utf16() {
        bytes.extend(u.to_le_bytes());
    }
    std::fs::write(&p, bytes).unwrap();
    let (code, _, err) = btx_code(&["tree", p.to_str().unwrap()]);
    assert_eq!(code, Some(1));
    assert!(err.contains("UTF-16"), "{err}");
}

#[test]
fn following_a_partial_session_ends_when_it_is_finalised() {
    let dir = tempfile::tempdir().unwrap();
    let fin = dir.path().join("run.jsonl");
    let partial = dir.path().join("run.jsonl.partial");
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/case-study.jsonl"),
    )
    .unwrap();
    // The run so far: every line but the end record.
    let (so_far, _) = text.trim_end().rsplit_once('\n').unwrap();
    std::fs::write(&partial, format!("{so_far}\n")).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["log", "--follow", partial.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(600));
    // The run ends: the session is written whole and renamed.
    std::fs::write(&partial, &text).unwrap();
    std::fs::rename(&partial, &fin).unwrap();
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > std::time::Duration::from_secs(10) {
            let _ = child.kill();
            panic!("btx log --follow kept polling a finalised session");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert_eq!(status.code(), Some(0), "{err}");
    assert_eq!(out.lines().count(), 1 + 10, "{out}");
    assert!(err.contains("the run ended: the session is now"), "{err}");
}

/// A chain of `n` trees, each `per` levels (XML itself nests at most 500):
/// ForceSuccess nested in each, a SubTree to the next, and at the end a
/// Sequence whose last child fails.
fn chain(n: usize, per: usize) -> String {
    let mut x = String::from(r#"<root BTCPP_format="4" main_tree_to_execute="T0">"#);
    for i in 0..n {
        let inner = if i + 1 < n {
            format!(r#"<SubTree ID="T{}"/>"#, i + 1)
        } else {
            r#"<Sequence name="s"><AlwaysSuccess/><Script code="x := 1"/><AlwaysFailure/></Sequence>"#.to_string()
        };
        x.push_str(&format!(
            r#"<BehaviorTree ID="T{i}">{}{inner}{}</BehaviorTree>"#,
            "<ForceSuccess>".repeat(per - 1),
            "</ForceSuccess>".repeat(per - 1)
        ));
    }
    x + "</root>"
}

#[test]
fn a_ten_thousand_deep_chain_loads_runs_and_answers_in_little_memory() {
    let dir = tempfile::tempdir().unwrap();
    // 24 × 416 levels, the Sequence and its leaves: 9,986 levels.
    let deep = write(dir.path(), "deep.xml", &chain(24, 416));
    // Its indentation stops at 40 levels, each line past them saying its
    // level: 2 MB of text, where it was 150 MB.
    let r = btx_run(&["tree", &deep]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(r.out_len < 3_000_000, "{}", r.out_len);
    assert!(r.peak_kib < 100 * 1024, "{} KiB", r.peak_kib);
    let r = btx_run(&["tree", &deep, "--format", "json"]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(r.peak_kib < 200 * 1024, "{} KiB", r.peak_kib);
    let plan = write(dir.path(), "empty.plan", "");
    let session = dir.path().join("s.jsonl").display().to_string();
    let r = btx_run(&["run", &deep, "--plan", &plan, "--out", &session]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(
        one_line(&r.err).contains("1 ticks, 29958 transitions, root SUCCESS"),
        "{}",
        r.err
    );
    // A node halfway down has one cause of each kind below it; the root's
    // search would take 10^9 evaluations and says so instead of guessing.
    let r = btx_run(&["why", &session, "status(#5000)", "--max-depth", "1"]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(
        r.out
            .contains("1. ForceSuccess (#5000) succeeded because ForceSuccess (#5001) succeeded."),
        "{}",
        r.out
    );
    assert!(r.out.contains("more explanations of this size, farther from status(ForceSuccess (#5000)): not shown or checked (btx keeps the nearest 50)."), "{}", r.out);
    let r = btx_run(&["why", &session, "status(#1)"]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(
        // Past the model's bound at depth 1, the nearest single changes
        // are searched (#42 item 2), and what was not is said.
        r.out.contains("1. ForceSuccess (#1) succeeded because ForceSuccess (#2) succeeded. If ForceSuccess (#2) had been running, ForceSuccess (#1) would have been running."),
        "{}",
        r.out
    );
    assert!(r.out.contains("the 200 variables nearest status(ForceSuccess (#1)) were searched, the 19773 farther ones not"), "{}", r.out);
    let r = btx_run(&[
        "ask", &session, "--node", "#9987", "q1", "q2", "q3", "wrong",
    ]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(r.out.contains("My subgoal is to run T23."), "{}", r.out);
    // A chain of 10,000 SubTrees, each a Sequence holding the next (20,001
    // levels, past the 13,900 BehaviorTree.CPP 4.8 loads on an 8 MiB stack):
    // the loader kept a copy of the path of SubTrees above each node
    // waiting to be read (471 MB at 4,000), and checked each SubTree for a
    // cycle by walking that path; the plan's leaves were matched by every
    // scope's path written out (648 MB for one tick at 10,000); the graph
    // named each variable by scanning the tree. Each now costs what the
    // tree holds.
    // Linear, whatever the build: the peaks at 10,000 SubTrees are at most
    // 2.2 times those at 5,000 (each was 3.5 times or more before; the
    // stack's depth counts too, and a debug build's frames are larger).
    let chain_of = |n: usize| {
        let mut x = String::from(r#"<root BTCPP_format="4" main_tree_to_execute="T0">"#);
        for i in 0..n {
            x.push_str(&format!(
                r#"<BehaviorTree ID="T{i}"><Sequence><SubTree ID="T{}"/><AlwaysSuccess/></Sequence></BehaviorTree>"#,
                i + 1
            ));
        }
        x.push_str(&format!(
            r#"<BehaviorTree ID="T{n}"><AlwaysSuccess/></BehaviorTree></root>"#
        ));
        write(dir.path(), &format!("subtrees{n}.xml"), &x)
    };
    let mut peaks: Vec<[i64; 3]> = Vec::new();
    let mut chained = String::new();
    for n in [5_000, 10_000] {
        let subtrees = chain_of(n);
        let r = btx_run(&["tree", &subtrees]);
        assert_eq!(r.code, Some(0), "{}", r.err);
        let deepest = format!("[level {}]", 2 * n);
        assert!(r.out.contains(&deepest), "{}", &r.out[r.out.len() - 400..]);
        let tree = r.peak_kib;
        chained = dir.path().join(format!("c{n}.jsonl")).display().to_string();
        let r = btx_run(&["run", &subtrees, "--plan", &plan, "--out", &chained]);
        assert_eq!(r.code, Some(0), "{}", r.err);
        let run = r.peak_kib;
        let r = btx_run(&["graph", &chained]);
        assert_eq!(r.code, Some(0), "{}", r.err);
        peaks.push([tree, run, r.peak_kib]);
    }
    for (what, (small, large)) in ["tree", "run", "graph"]
        .iter()
        .zip(peaks[0].iter().zip(&peaks[1]))
    {
        assert!(
            (*large as f64) < 2.2 * *small as f64,
            "{what}: {small} KiB at 5,000 SubTrees, {large} KiB at 10,000"
        );
    }
    assert!(peaks[1][0] < 64 * 1024, "{:?}", peaks[1]);
    // Its root's why: every one of the 60,001 variables below is a single
    // change, 3.6·10^9 evaluations, past the bound; it answered nothing at
    // depth 1. The nearest are searched, and the rest said not to be.
    let r = btx_run(&["why", &chained, "status(#1)", "--at", "last"]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(
        r.out.contains("2. Sequence (#1) succeeded because T1 succeeded. If T1 had failed, Sequence (#1) would have failed."),
        "{}",
        r.out
    );
    assert!(r.out.contains("the 200 variables nearest status(Sequence (#1)) were searched, the 59801 farther ones not"), "{}", r.out);
    assert!(r.peak_kib < 400 * 1024, "{} KiB", r.peak_kib);
    // A chain of 1,000: its 6,001 single changes would cost 3.6·10^7
    // evaluations, the square of the chain; past 2·10^7 the nearest are
    // searched, so the search grows with the chain.
    let thousand = dir.path().join("c1000.jsonl").display().to_string();
    let r = btx_run(&["run", &chain_of(1_000), "--plan", &plan, "--out", &thousand]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    let r = btx_run(&["why", &thousand, "status(#1)", "--at", "last"]);
    assert_eq!(r.code, Some(0), "{}", r.err);
    assert!(r.out.contains("the 200 variables nearest status(Sequence (#1)) were searched, the 5801 farther ones not"), "{}", r.out);
    // 100,000 levels: refused, with the limit.
    let deeper = write(dir.path(), "deeper.xml", &chain(250, 400));
    let r = btx_run(&["tree", &deeper]);
    assert_eq!(r.code, Some(1), "{}", r.err);
    assert!(one_line(&r.err).contains("25000 levels deep"), "{}", r.err);
    // With what BehaviorTree.CPP itself does (docs/limits.md).
    assert!(
        one_line(&r.err).contains("crashes past about 13,900 levels"),
        "{}",
        r.err
    );
    assert!(r.peak_kib < 100 * 1024, "{} KiB", r.peak_kib);
}

#[test]
fn names_attributes_and_records_have_a_stated_length() {
    let dir = tempfile::tempdir().unwrap();
    let long = |key: &str, n: usize| {
        format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess {key}="{}"/></BehaviorTree></root>"#,
            "n".repeat(n)
        )
    };
    for (key, n, says) in [
        (
            "name",
            4097,
            "attribute name is 4097 bytes long, more than the 4096 bytes btx reads",
        ),
        (
            "_description",
            (1 << 20) + 1,
            "attribute _description is 1048577 bytes long, more than the 1048576 bytes btx reads",
        ),
    ] {
        let f = write(dir.path(), "long.xml", &long(key, n));
        let r = btx_run(&["tree", &f]);
        assert_eq!(r.code, Some(1), "{}", r.err);
        assert!(one_line(&r.err).contains("long.xml:1:"), "{}", r.err);
        assert!(one_line(&r.err).contains(says), "{}", r.err);
        assert!(r.err.len() < 2000, "{}", r.err.len());
    }
    let f = write(dir.path(), "ok.xml", &long("name", 4096));
    assert_eq!(btx_run(&["tree", &f]).code, Some(0));
    // A session record past 8 MiB: an array of 4 million numbers would cost
    // 60 times its size once read.
    let (header, rest) = case_study_header();
    let big = format!(
        r#"{{"k":"w","tick":1,"step":0,"uid":2,"entry":{{"scope":0,"key":"X_a"}},"value":[{}0]}}"#,
        "0,".repeat(4_500_000)
    );
    let f = write(dir.path(), "big.jsonl", &format!("{header}\n{big}\n{rest}"));
    let r = btx_run(&["log", &f]);
    assert_eq!(r.code, Some(1), "{}", r.err);
    assert!(one_line(&r.err).contains("big.jsonl:2:1: a record of 9000079 bytes: a session's records (after the header) are at most 8 MiB"), "{}", r.err);
    assert!(r.peak_kib < 200 * 1024, "{} KiB", r.peak_kib);
}

#[test]
fn a_second_btcm_root_and_a_corrupt_fbl_size_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixture("btcm/case_study.json")).unwrap();
    let mut log: serde_json::Value = serde_json::from_str(&text).unwrap();
    let tree = log["tree"].as_object_mut().unwrap();
    let leaf = tree.values().next_back().unwrap().clone();
    tree.insert("stray".into(), leaf);
    let f = write(dir.path(), "two.json", &log.to_string());
    let r = btx_run(&["log", &f]);
    assert_eq!(r.code, Some(1), "{}", r.err);
    assert!(
        one_line(&r.err).contains("tree.stray: the node is not under the root"),
        "{}",
        r.err
    );
    assert!(
        one_line(&r.err).contains("a btcm tree has one root"),
        "{}",
        r.err
    );

    let mut bytes = std::fs::read(fixture("logs/taxi_nominal_v3.fbl")).unwrap();
    bytes[..4].copy_from_slice(&0x7fff_ffffu32.to_le_bytes());
    let p = dir.path().join("cut.fbl");
    std::fs::write(&p, &bytes).unwrap();
    let r = btx_run(&["log", p.to_str().unwrap()]);
    assert_eq!(r.code, Some(1), "{}", r.err);
    assert!(
        one_line(&r.err).contains(&format!("cut.fbl: byte offset 0: not an .fbl, or a corrupt one: its size field says the tree takes 2147483647 bytes, but the file has {} after the field", bytes.len() - 4)),
        "{}",
        r.err
    );
}

#[test]
fn format_characters_never_make_a_name_read_as_another() {
    // A zero-width space inside "ask", a right-to-left override, an isolate
    // and a line separator: each is shown as an escape, on the command line
    // and in the explorer (#26 item 7).
    let dir = tempfile::tempdir().unwrap();
    let tree = write(
        dir.path(),
        "fmt.xml",
        "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><Sequence name=\"go\u{2066}home\u{2069}\"><AlwaysSuccess name=\"as\u{200b}k\"/><AlwaysSuccess name=\"\u{202e}evil\u{2028}\"/></Sequence></BehaviorTree></root>",
    );
    let (code, out, err) = btx_code(&["tree", &tree]);
    assert_eq!(code, Some(0), "{err}");
    for c in ['\u{200b}', '\u{202e}', '\u{2066}', '\u{2069}', '\u{2028}'] {
        assert!(!out.contains(c), "{c:?} reached the terminal: {out:?}");
    }
    assert!(out.contains("as\\u{200b}k"), "{out}");
    assert!(out.contains("\\u{202e}evil"), "{out}");
    // The explorer's screen: tests/tui.rs (it would swell this binary's
    // memory, which the children's measured peaks here inherit).
}

#[test]
fn number_options_refuse_nan_infinities_and_negatives() {
    // `--for nan` panicked watch and serve (#26 item 6).
    for args in [
        vec!["watch", ":1", "--for", "nan"],
        vec!["watch", ":1", "--for", "inf"],
        vec!["watch", ":1", "--for=-1"],
        vec!["serve", "sessions/taxi.jsonl", "--for", "nan"],
        vec!["serve", "sessions/taxi.jsonl", "--speed", "inf"],
        vec!["serve", "sessions/taxi.jsonl", "--speed", "0"],
    ] {
        let (code, _, err) = btx_code(&args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains("invalid value"), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // With --port 0 the system picks the port, and btx says which.
    let (code, _, err) = btx_code(&[
        "serve",
        "sessions/taxi.jsonl",
        "--port",
        "0",
        "--for",
        "0.2",
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains(":0 with"), "{err}");
    assert!(err.contains("on 127.0.0.1:"), "{err}");
}

#[test]
fn domain_ranges_are_finite_and_domain_comparisons_exact() {
    // `min = -inf, max = inf` gave "If X had been null, …" ten times, and
    // `1e-30 > 0.0` was false in a domain script (#26 item 8).
    let dir = tempfile::tempdir().unwrap();
    let tree = write(
        dir.path(),
        "t.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><L0/></Sequence></BehaviorTree>
<TreeNodesModel><Condition ID="L0"/></TreeNodesModel></root>"#,
    );
    let domain = |range: &str, test: &str| {
        format!(
            "btx_domain = 1\nname = \"tiny\"\n[state.X]\ntype = \"float\"\n{range}\ninitial = 1e-30\n[leaf.L0]\ninputs = [\"X\"]\nstatus = \"if {test} {{ SUCCESS }} else {{ FAILURE }}\"\n"
        )
    };
    let d = write(
        dir.path(),
        "inf.toml",
        &domain("min = -inf\nmax = inf", "X > 0.0"),
    );
    let out = dir.path().join("inf.jsonl");
    let (code, _, err) = btx_code(&["run", &tree, "--domain", &d, "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        one_line(&err).contains("X: min is -inf; a range's bounds are finite numbers"),
        "{err}"
    );
    for (i, test) in ["X > 0.0", "1e-30 > 0.0", "X != 0.0", "X > 0", "0.0 < X"]
        .iter()
        .enumerate()
    {
        let d = write(
            dir.path(),
            &format!("d{i}.toml"),
            &domain("min = 0.0\nmax = 1.0", test),
        );
        let out = dir.path().join(format!("s{i}.jsonl"));
        let (code, _, err) = btx_code(&[
            "run",
            &tree,
            "--domain",
            &d,
            "--max-ticks",
            "1",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{test}: {err}");
        assert!(
            err.contains("root SUCCESS"),
            "{test} is true of 1e-30: {err}"
        );
    }
}

/// An MCAP record: opcode, length, body.
fn mcap_record(op: u8, body: &[u8]) -> Vec<u8> {
    let mut r = vec![op];
    r.extend((body.len() as u64).to_le_bytes());
    r.extend(body);
    r
}

fn mcap_string(s: &str) -> Vec<u8> {
    let mut b = (s.len() as u32).to_le_bytes().to_vec();
    b.extend(s.as_bytes());
    b
}

#[test]
fn an_mcap_chunk_claiming_gigabytes_is_refused_before_it_is_decompressed() {
    // 527 KB of chunks decompressing to 4 GiB of zeros took 94 s (#41 item 3).
    let mut chunk = Vec::new();
    chunk.extend(0u64.to_le_bytes());
    chunk.extend(0u64.to_le_bytes());
    chunk.extend((4u64 << 30).to_le_bytes());
    chunk.extend(0u32.to_le_bytes());
    chunk.extend(mcap_string("zstd"));
    chunk.extend(16u64.to_le_bytes());
    chunk.extend([0u8; 16]);
    let mut file = b"\x89MCAP0\r\n".to_vec();
    let mut header = mcap_string("ros2");
    header.extend(mcap_string("hostile"));
    file.extend(mcap_record(0x01, &header));
    file.extend(mcap_record(0x06, &chunk));
    file.extend(mcap_record(0x0F, &0u32.to_le_bytes()));
    file.extend(mcap_record(0x02, &[0u8; 20]));
    file.extend(b"\x89MCAP0\r\n");
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("zeros.mcap");
    std::fs::write(&bag, &file).unwrap();
    let tree = fixture("kitting-tree.v4.xml");
    let r = btx_run(&[
        "log",
        bag.to_str().unwrap(),
        "--tree",
        tree.to_str().unwrap(),
    ]);
    assert_eq!(r.code, Some(1), "{}", r.err);
    assert!(
        one_line(&r.err).contains("an MCAP chunk claims 4294967296 bytes decompressed, more than the 256 MiB btx reads in one chunk"),
        "{}",
        r.err
    );
}

#[test]
fn a_lock_that_is_not_a_regular_file_is_refused_at_once() {
    // A FIFO at OUT.btx-lock hung btx for ever (#41 item 7).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.jsonl");
    let lock = dir.path().join("o.jsonl.btx-lock");
    let tree = fixture("kitting-tree.v4.xml");
    let plan = fixture("plans/kitting_nominal.plan");
    let run = |said: &str| {
        let started = std::time::Instant::now();
        let (code, _, err) = btx_code(&[
            "run",
            tree.to_str().unwrap(),
            "--plan",
            plan.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(1), "{err}");
        assert!(one_line(&err).contains(said), "{err}");
        assert!(started.elapsed() < std::time::Duration::from_secs(5));
        assert!(!out.exists());
    };
    let made = Command::new("mkfifo").arg(&lock).status().unwrap();
    assert!(made.success());
    run("something that is not a regular file (a FIFO, a device, a directory) is here, where btx keeps the lock of this output");
    std::fs::remove_file(&lock).unwrap();
    std::os::unix::fs::symlink("/etc/passwd", &lock).unwrap();
    run("a link is here, where btx keeps the lock of this output");
}
#[path = "support/flood_peer.rs"]
mod flood_peer;
