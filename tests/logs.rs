//! Logs robots already write, opened as sessions: `.btlog` files of the
//! recorded runs, with their ticks reconstructed exactly.

mod common;
use btx::explain::{answer, Question};
use btx::session::Moment;
use common::*;

/// The five recorded runs (each as `.btlog`, `.db3` and, with `_v3`, `.fbl`).
const RUNS: [&str; 5] = [
    "taxi_nominal",
    "kitting_nominal",
    "kitting_lookat_fails_once",
    "kitting_detect_chuck_always_fails",
    "kitting_grasp_check_fails_first",
];

/// The session's transitions equal the recorded run's, ticks included.
fn assert_same_run(s: &btx::session::Session, run: &str) {
    assert!(s.warnings.is_empty(), "{run}: {:?}", s.warnings);
    let ours: Vec<(u32, u32, String, String)> = s
        .index
        .transitions
        .iter()
        .map(|t| (t.tick, t.uid, t.prev.to_string(), t.status.to_string()))
        .collect();
    let want = logged(run);
    for (i, (a, b)) in ours.iter().zip(&want).enumerate() {
        assert_eq!(a, b, "{run}: record {i}");
    }
    assert_eq!(ours.len(), want.len(), "{run}");
}

fn open(run: &str) -> btx::session::Session {
    let p = fixture(&format!("logs/{run}.btlog"));
    btx::logs::open_btlog(&p, &std::fs::read(&p).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn ticks_are_reconstructed_exactly() {
    for run in RUNS {
        assert_same_run(&open(run), run);
    }
}

#[test]
fn what_went_wrong_in_the_log_is_what_went_wrong_in_our_run() {
    let s = open("kitting_lookat_fails_once");
    let ask = |m: &str, q: &str| {
        let at = s.at(Moment::parse(m).unwrap()).unwrap();
        answer(
            &s.tree,
            Some(&at),
            at.current().unwrap(),
            &Question::parse(q).unwrap(),
        )
        .unwrap()
        .text
    };
    assert_eq!(
        ask("10", "What went wrong?"),
        "I could not insert large gear because look at chuck failed."
    );
    assert_eq!(
        ask("11", "What went wrong?"),
        "I am retrying for attempt 1 to go insert large gear. I could not insert large gear because look at chuck failed."
    );
}

#[test]
fn broken_logs_name_the_byte_offset() {
    let p = fixture("logs/taxi_nominal.btlog");
    let good = std::fs::read(&p).unwrap();
    let e = btx::logs::open_btlog(&p, b"BTCPP4-FileLoggerX")
        .err()
        .expect("should fail")
        .to_string();
    assert!(e.contains("byte offset 0"), "{e}");
    let mut long = good.clone();
    long[19..23].copy_from_slice(&1_000_000i32.to_le_bytes());
    let e = btx::logs::open_btlog(&p, &long)
        .err()
        .expect("should fail")
        .to_string();
    assert!(
        e.contains("byte offset 19: the XML length 1000000 runs past the end"),
        "{e}"
    );
    let mut bad = good.clone();
    let last = bad.len() - 1;
    bad[last] = 9;
    let e = btx::logs::open_btlog(&p, &bad)
        .err()
        .expect("should fail")
        .to_string();
    assert!(
        e.contains(&format!("byte offset {last}: status byte 9")),
        "{e}"
    );
    let mut uid = good.clone();
    let l = uid.len();
    uid[l - 3..l - 1].copy_from_slice(&999u16.to_le_bytes());
    let e = btx::logs::open_btlog(&p, &uid)
        .err()
        .expect("should fail")
        .to_string();
    assert!(e.contains("uid 999 is not a node"), "{e}");
    // Timestamps that jump by 2^40 µs twenty times: each jump claims a
    // million empty ticks, more than a session keeps in all, so the count
    // stops, with a warning, instead of filling memory.
    let k = fixture("logs/kitting_nominal.btlog");
    let mut gaps = std::fs::read(&k).unwrap();
    let xml_len = i32::from_le_bytes(gaps[19..23].try_into().unwrap()) as usize;
    let offsets: Vec<usize> = (31 + xml_len..gaps.len() - 8).step_by(9).collect();
    let stair = offsets.len() / 20;
    for (i, &r) in offsets.iter().enumerate() {
        let mut dt = [0u8; 8];
        dt[..6].copy_from_slice(&gaps[r..r + 6]);
        let dt = u64::from_le_bytes(dt) + ((i / stair) as u64) * (1 << 40);
        gaps[r..r + 6].copy_from_slice(&dt.to_le_bytes()[..6]);
    }
    let s = btx::logs::open_btlog(&k, &gaps).unwrap();
    let real = btx::logs::open_btlog(&k, &std::fs::read(&k).unwrap()).unwrap();
    assert!(s.index.ticks() > btx::session::EMPTY_TICKS_MAX);
    assert!(s.index.ticks() <= btx::session::EMPTY_TICKS_MAX + real.index.ticks());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.message.contains("from here a gap counts as one tick")),
        "{:?}",
        s.warnings
    );
    let cut = &good[..good.len() - 4];
    let s = btx::logs::open_btlog(&p, cut).unwrap();
    assert!(s
        .warnings
        .iter()
        .any(|w| w.message.contains("not a whole record")));
    let e = btx::logs::open_btlog(&p, &good[..10])
        .err()
        .expect("should fail")
        .to_string();
    assert!(e.contains("byte offset"), "{e}");
}

#[test]
fn the_cli_reads_logs_and_imports_them() {
    let bin = env!("CARGO_BIN_EXE_btx");
    let log = fixture("logs/kitting_lookat_fails_once.btlog");
    let out = std::process::Command::new(bin)
        .args(["ask", log.to_str().unwrap(), "--at", "10", "wrong"])
        .output()
        .unwrap();
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "I could not insert large gear because look at chuck failed.\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("s.jsonl");
    let out = std::process::Command::new(bin)
        .args([
            "import",
            log.to_str().unwrap(),
            "--out",
            s.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let imported = btx::session::Session::load(&s).unwrap();
    assert_eq!(
        imported.index.transitions,
        open("kitting_lookat_fails_once").index.transitions
    );
}

fn open_fbl(run: &str) -> btx::session::Session {
    let p = fixture(&format!("logs/{run}.fbl"));
    btx::logs::open_fbl(&p, &std::fs::read(&p).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn v3_fbl_ticks_are_reconstructed_exactly() {
    for run in RUNS.map(|r| format!("{r}_v3")) {
        assert_same_run(&open_fbl(&run), &run);
    }
}

fn open_db3(run: &str) -> btx::session::Session {
    btx::logs::open_db3(&fixture(&format!("logs/{run}.db3")), None)
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn db3_ticks_are_reconstructed_exactly() {
    for run in RUNS {
        assert_same_run(&open_db3(run), run);
    }
    // Recognised by content, as every command opens it.
    let (ok, out, err) = btx(&[
        "ask",
        "tests/fixtures/logs/kitting_lookat_fails_once.db3",
        "--at",
        "11",
        "wrong",
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "I am retrying for attempt 1 to go insert large gear. I could not insert large gear because look at chuck failed.\n"
    );
}

/// A copy of a fixture database, changed by `sql`.
fn db3_with(sql: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("log.db3");
    std::fs::copy(fixture("logs/taxi_nominal.db3"), &p).unwrap();
    let c = rusqlite::Connection::open(&p).unwrap();
    c.execute_batch(sql).unwrap();
    drop(c);
    (dir, p)
}

#[test]
fn every_session_of_a_database_opens() {
    let (_d, p) = db3_with(
        "INSERT INTO Definitions(session_id, date, xml_tree) SELECT 2, '2026-11-22 09:00:00', xml_tree FROM Definitions WHERE session_id = 1;
         INSERT INTO Nodes SELECT 2, fullpath, node_uid FROM Nodes WHERE session_id = 1;
         INSERT INTO Transitions SELECT timestamp + 100000000, 2, node_uid, duration, state, extra_data FROM Transitions WHERE session_id = 1 AND timestamp < (SELECT min(timestamp) FROM Transitions) + 30000;",
    );
    let last = btx::logs::open_db3(&p, None).unwrap();
    let first = btx::logs::open_db3(&p, Some(1)).unwrap();
    assert_eq!(first.index.transitions.len(), 63);
    assert!(last.index.transitions.len() < 63);
    assert_eq!(
        last.index.transitions[..],
        first.index.transitions[..last.index.transitions.len()]
    );
    assert!(
        last.warnings[0].message.starts_with("the database holds sessions 1, 2; this is session 2 (2026-11-22 09:00:00); open another as "),
        "{:?}",
        last.warnings
    );
    // FILE#N on the command line.
    let one = format!("{}#1", p.display());
    let (ok, out, err) = btx(&["log", &one, "--format", "json"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["transitions"].as_array().unwrap().len(), 63);
    let (ok, _, err) = btx(&["log", &format!("{}#7", p.display())]);
    assert!(!ok);
    assert!(
        err.contains("no session 7 in table Definitions; it has 1, 2"),
        "{err}"
    );
}

#[test]
fn broken_databases_name_the_table_and_row() {
    let msg = |sql: &str| {
        let (_d, p) = db3_with(sql);
        btx::logs::open_db3(&p, None)
            .err()
            .expect("should fail")
            .to_string()
    };
    let e = msg("UPDATE Transitions SET state = 9 WHERE rowid = (SELECT rowid FROM Transitions ORDER BY timestamp LIMIT 1 OFFSET 4);");
    assert!(
        e.contains("table Transitions, session 1, row 5 (timestamp "),
        "{e}"
    );
    assert!(e.contains("state 9 is not a status (0-4)"), "{e}");
    let e = msg("UPDATE Transitions SET node_uid = 999 WHERE rowid = (SELECT rowid FROM Transitions ORDER BY timestamp LIMIT 1 OFFSET 2);");
    assert!(
        e.contains("table Transitions, session 1, row 3: uid 999 is not a node"),
        "{e}"
    );
    let e = msg("DELETE FROM Transitions; DELETE FROM Nodes; DELETE FROM Definitions;");
    assert!(
        e.contains("the database has no session (table Definitions is empty)"),
        "{e}"
    );
    let e = msg("DROP TABLE Nodes;");
    assert!(e.contains("it has no table Nodes"), "{e}");
    // A database cut short: the header is there, the pages are not.
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.db3");
    let bytes = std::fs::read(fixture("logs/taxi_nominal.db3")).unwrap();
    std::fs::write(&p, &bytes[..200]).unwrap();
    let (ok, _, err) = btx(&["log", p.to_str().unwrap()]);
    assert!(!ok);
    assert!(err.contains("cut.db3"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_database_is_read_without_taking_a_lock() {
    // The robot's logger holds the database; a locking reader would make
    // it wait (SQLITE_BUSY), which aborts the library's writer.
    let (_d, p) = db3_with("");
    let writer = rusqlite::Connection::open(&p).unwrap();
    writer.execute_batch("BEGIN EXCLUSIVE;").unwrap();
    let s = btx::logs::open_db3(&p, None).unwrap();
    assert_eq!(s.index.transitions.len(), 63);
    // And it leaves nothing behind: no journal, no change to the file.
    writer.execute_batch("COMMIT;").unwrap();
    let before = std::fs::read(&p).unwrap();
    btx::logs::open_db3(&p, None).unwrap();
    assert_eq!(std::fs::read(&p).unwrap(), before);
    let names: Vec<String> = std::fs::read_dir(p.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["log.db3"]);
}

/// The fixture's header and its first `records` records (plus `extra`
/// bytes of the next one, a record half written).
fn live_log(p: &std::path::Path, records: usize, extra: usize) {
    let src = std::fs::read(fixture("logs/kitting_lookat_fails_once.btlog")).unwrap();
    let n = i32::from_le_bytes(src[19..23].try_into().unwrap()) as usize;
    let end = (31 + n + 9 * records + extra).min(src.len());
    std::fs::write(p, &src[..end]).unwrap();
}

#[test]
fn a_growing_log_is_followed() {
    use std::io::Read;
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("live.btlog");
    live_log(&p, 20, 4);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["log", "--follow", p.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stdout.read_to_string(&mut s);
        s
    });
    let wait = || std::thread::sleep(std::time::Duration::from_millis(800));
    wait();
    live_log(&p, 100, 5);
    wait();
    live_log(&p, 248, 0);
    // Polls come every 250 ms; leave a loaded machine time for several.
    for _ in 0..4 {
        wait();
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let followed = reader.join().unwrap();
    let (ok, whole, err) = btx(&["log", p.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert_eq!(
        followed, whole,
        "following prints what reading the whole log prints"
    );
    assert_eq!(whole.lines().count(), 249);
}

#[test]
fn rows_printed_before_the_tick_period_was_known_are_said_to_change() {
    // The log's first 10 records span 2 ticks and an empty one, which only
    // more of the log shows (ticks in which nothing changed are counted
    // from the time between ticks). Printed after 2 s of waiting for more,
    // they are renumbered later, and btx says so.
    use std::io::Read;
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("live.btlog");
    live_log(&p, 10, 0);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["log", "--follow", p.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let (out, err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let read = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = r.read_to_string(&mut s);
            s
        })
    };
    let (out, err) = (read(Box::new(out)), read(Box::new(err)));
    std::thread::sleep(std::time::Duration::from_millis(3000));
    live_log(&p, 248, 0);
    std::thread::sleep(std::time::Duration::from_millis(1500));
    child.kill().unwrap();
    child.wait().unwrap();
    let (followed, err) = (out.join().unwrap(), err.join().unwrap());
    assert!(
        err.contains("note: tick 2 of the rows printed (from row 7) is tick 3 now"),
        "{err}"
    );
    let (ok, whole, _) = btx(&["log", p.to_str().unwrap()]);
    assert!(ok);
    let tick_of = |l: &str| l.get(..6).unwrap_or("").trim().to_string();
    let rest = |l: &str| l.get(6..).unwrap_or("").to_string();
    let (f, w): (Vec<&str>, Vec<&str>) = (followed.lines().collect(), whole.lines().collect());
    assert_eq!(f.len(), w.len());
    assert_eq!(tick_of(f[7]), "2");
    assert_eq!(tick_of(w[7]), "3");
    assert_eq!(
        f[11..],
        w[11..],
        "rows printed after the change have the new ticks"
    );
    assert!(f.iter().zip(&w).all(|(a, b)| rest(a) == rest(b)));
}

#[test]
fn the_explorer_follows_a_log_and_keeps_the_moment() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("live.btlog");
    live_log(&p, 30, 0);
    let mut app = btx::tui::open(&p, None, &Default::default()).unwrap();
    let mut f = btx::input::Follow::new(&p);
    assert!(f.poll().unwrap().is_some());
    assert!(f.poll().unwrap().is_none(), "unchanged: nothing to read");
    app.shared.follow = Some(f);
    app.update(btx::tui::Action::End);
    assert_eq!(app.shared.pos, 30);
    // At the end, the moment keeps to the end as the log grows.
    live_log(&p, 60, 3);
    app.follow_poll();
    assert_eq!(app.shared.pos, 60);
    // Elsewhere, it stays where the person put it.
    app.update(btx::tui::Action::Start);
    let here = app.shared.pos;
    live_log(&p, 248, 0);
    app.follow_poll();
    assert_eq!(app.shared.pos, here);
    assert_eq!(
        app.shared.session.as_ref().unwrap().index.transitions.len(),
        248
    );
}

#[test]
fn a_tree_file_that_is_not_the_logs_tree_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let log = "tests/fixtures/logs/kitting_nominal.btlog";
    // The shipped kitting tree renamed two subgoals ("first" is gone).
    let (ok, _, err) = btx(&[
        "import",
        log,
        "--tree",
        "trees/kitting.xml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("kitting_nominal.btlog: not a log of trees/kitting.xml (--tree):"),
        "{err}"
    );
    assert!(
        err.contains("#29: trees/kitting.xml:17:7 has SubTree \"go pick screw\", the log SubTree \"go pick first screw\""),
        "{err}"
    );
    assert!(!out.exists());
    // The tree file the robot ran matches, and the session keeps it.
    let tree = "tests/fixtures/kitting-tree.v4.xml";
    let (ok, _, err) = btx(&[
        "import",
        log,
        "--tree",
        tree,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let s = btx::session::Session::load(&out).unwrap();
    assert_eq!(s.header.tree.path.as_deref(), Some(tree));
    // The explorer checks a tree and a log given together.
    let e = btx::tui::open(
        std::path::Path::new(&format!("{}/trees/taxi.xml", env!("CARGO_MANIFEST_DIR"))),
        Some(&fixture("logs/kitting_nominal.btlog")),
        &Default::default(),
    )
    .err()
    .expect("not a run of the taxi tree")
    .to_string();
    assert!(
        e.contains("the tree file has 21 nodes and the log's tree 79"),
        "{e}"
    );
}

/// Inputs the fuzzers found a panic with (in `fixtures/fuzz/`), and the
/// located error each now gives.
const FUZZ_FINDINGS: &[(&str, &str)] = &[(
    "fuzz/fbl-vtable-before-buffer.fbl",
    "byte offset 4864: a table's vtable lies before the flatbuffer",
)];

#[test]
fn fuzzer_findings_are_errors() {
    for (file, expect) in FUZZ_FINDINGS {
        let p = fixture(file);
        let e = btx::input::open(&p, &Default::default())
            .err()
            .unwrap_or_else(|| panic!("{file} opened"))
            .to_string();
        assert!(e.contains(expect), "{file}: {e}");
    }
}

#[test]
fn a_log_whose_root_completed_is_a_finished_run_everywhere() {
    // The explorer called a robot's whole `.btlog` "no end recorded … cut
    // off or is still going", while `ask` said the task finished (#30
    // item 5). Every log kind of every recorded run ends with its root.
    for run in RUNS {
        for s in [open(run), open_db3(run), open_fbl(&format!("{run}_v3"))] {
            let (_, root, _) = s.end.clone().unwrap_or_else(|| panic!("{run}: no end"));
            let last = s
                .index
                .transitions
                .iter()
                .rev()
                .find(|t| t.uid == 1)
                .unwrap();
            assert_eq!(root, last.prev, "{run}: completed, then reset to IDLE");
            assert_eq!(
                s.ending(),
                format!(
                    "ended at tick {}: root {} (root completed)",
                    s.index.ticks(),
                    root.as_str()
                )
            );
        }
    }
    // Imported, the session says the same, and so does what reads it.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let log = fixture("logs/kitting_nominal.btlog");
    let (ok, _, err) = btx(&[
        "import",
        log.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let imported = btx::session::Session::load(&out).unwrap();
    assert_eq!(imported.ending(), open("kitting_nominal").ending());
}

#[test]
fn only_a_log_that_stops_while_the_root_runs_is_cut_off() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.btlog");
    live_log(&p, 100, 0);
    let s = btx::logs::open_btlog(&p, &std::fs::read(&p).unwrap()).unwrap();
    assert_eq!(s.end, None);
    assert_eq!(
        s.ending(),
        format!(
            "no end recorded after tick {}: the run was cut off or is still going",
            s.index.ticks()
        )
    );
    // Imported, it is not made to end: the session has no end record,
    // where it had one saying "root SUCCESS" from an earlier completion.
    let out = dir.path().join("cut.jsonl");
    let (ok, _, err) = btx(&[
        "import",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let imported = btx::session::Session::load(&out).unwrap();
    assert_eq!(imported.end, None);
    assert_eq!(imported.index.transitions, s.index.transitions);
    assert!(!std::fs::read_to_string(&out)
        .unwrap()
        .contains("\"k\":\"end\""));
}

/// A `.btlog` of a robot that ran its tree twice (the real BehaviorTree.CPP
/// 4.8, 0.3 s apart): two runs, as `btx watch` told them, each with its
/// ticks from 1; the pause between them is no ticks (the tree was reset,
/// not ticked); `--faults` numbers the runs and gives the times asked for.
#[test]
fn a_log_of_two_runs_lists_each_and_opens_either() {
    let log = "tests/fixtures/logs/kitting_twice.btlog";
    let (ok, out, err) = btx(&["log", log, "--runs"]);
    assert!(ok, "{err}");
    let rows: Vec<&str> = out.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{out}");
    assert!(
        rows[0].contains(" 54          248  ended at tick 54: root SUCCESS"),
        "{out}"
    );
    assert!(
        rows[1].contains(" 46          209  ended at tick 46: root SUCCESS"),
        "{out}"
    );
    // The whole log, said so: run 2 follows run 1 at the next tick.
    let (_, whole, err) = btx(&["log", log]);
    assert!(
        err.contains(
            "the log holds 2 runs (the root started again after it completed), read whole"
        ),
        "{err}"
    );
    let runs_err = btx(&["log", log, "--runs"]).2;
    assert!(!runs_err.contains("read whole"), "{runs_err}");
    let last = whole.lines().last().unwrap();
    assert!(
        last.starts_with("  100    29     1  build a gearbox kit"),
        "{last}"
    );
    // Run 2 alone: its ticks from 1, said.
    let (ok, second, err) = btx(&["log", log, "--run", "2"]);
    assert!(ok, "{err}");
    assert!(err.contains("the log holds 2 runs"), "{err}");
    assert_eq!(second.lines().count(), 1 + 209);
    assert!(
        second
            .lines()
            .nth(1)
            .unwrap()
            .starts_with("    1     1     1"),
        "{second}"
    );
    let (ok, faults, _) = btx(&["log", log, "--faults", "--time", "utc"]);
    assert!(ok);
    let faults: Vec<&str> = faults.lines().collect();
    assert_eq!(faults.len(), 4, "{faults:?}");
    assert!(faults[0].ends_with(" 10:1 look at chuck failed; insert large gear failed; RetryUntilSuccessful (#7) tries again, attempt 2 of 3"), "{faults:?}");
    assert!(faults[0].starts_with("03:20:58."), "{faults:?}");
    assert!(
        faults[3].ends_with("run 2 ended at tick 100: SUCCESS"),
        "{faults:?}"
    );
    let (_, faults, _) = btx(&["log", log, "--run", "2", "--faults"]);
    assert_eq!(faults, "run 2 ended at tick 46: SUCCESS\n");
    let (ok, out, err) = btx(&["log", log, "--run", "3", "--runs"]);
    assert!(!ok && out.is_empty(), "{out}");
    assert!(
        one_line(&err).contains("the log holds runs 1 to 2; there is no run 3"),
        "{err}"
    );
}

/// A `.btlog` cut inside its magic is said as a log cut short, not as "not
/// a tree"; a broken record of a session names its own line and column
/// (serde's "line 1" is the record's, not the file's).
#[test]
fn a_cut_log_and_a_broken_record_say_where() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("cut.btlog");
    std::fs::write(&log, b"BTCPP4-File").unwrap();
    let (ok, _, err) = btx(&["log", log.to_str().unwrap()]);
    assert!(!ok);
    let err = one_line(&err);
    assert!(
        err.contains("byte offset 11: the file ends inside the .btlog's magic (BTCPP4-FileLogger2): a log cut short"),
        "{err}"
    );
    let good = std::fs::read_to_string("sessions/kitting-nominal.jsonl").unwrap();
    let mut lines: Vec<&str> = good.lines().collect();
    lines[3] = r#"{"k":"t","tick":1,"#;
    let broken = dir.path().join("broken.jsonl");
    std::fs::write(&broken, lines.join("\n") + "\n").unwrap();
    let (ok, _, err) = btx(&["log", broken.to_str().unwrap()]);
    assert!(!ok);
    let err = one_line(&err);
    assert!(err.contains("broken.jsonl:4:"), "{err}");
    assert!(
        err.contains("(column 18)") && !err.contains("at line 1"),
        "{err}"
    );
}

/// One node's rows of a log, read by following that node alone, are its
/// rows among every row: the same ticks, steps, statuses changed from and
/// times, for every node of every fixture log, with and without IDLE.
#[test]
fn one_nodes_rows_are_its_rows_among_all() {
    use btx::export::Table;
    for name in [
        "kitting_lookat_fails_once.btlog",
        "kitting_twice.btlog",
        "patrol_battery_drops.btlog",
        "counted_runs.btlog",
    ] {
        let path = fixture("logs").join(name);
        let log = btx::logs::number_btlog(&path, std::fs::read(&path).unwrap(), None).unwrap();
        for no_idle in [false, true] {
            let mut all = Vec::new();
            log.each_row(None, no_idle, &mut |r| all.push(r));
            for u in 1..=log.tree().len() as u32 {
                let mut one = Vec::new();
                log.each_row(Some(u), no_idle, &mut |r| one.push(r));
                let want: Vec<_> = all.iter().filter(|r| r.uid == u).cloned().collect();
                assert_eq!(one, want, "{name} #{u} no_idle {no_idle}");
            }
        }
    }
}
