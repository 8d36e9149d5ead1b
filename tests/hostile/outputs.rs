//! The files btx writes under races and faults (#26 items 1 and 2): one
//! writer per output, a destination checked before the work, write errors
//! said with the file and what was kept.

use super::*;
use btx::session::Session;
use std::io::BufRead;
use std::time::{Duration, Instant};

/// `btx serve RUN` on a port the system picks, for `secs`: the port it
/// says, and the server.
pub fn served(run: &str, speed: &str, secs: &str) -> (u16, std::process::Child) {
    served_with(run, speed, secs, &[])
}

/// `served`, with more arguments to `btx serve`.
pub fn served_with(
    run: &str,
    speed: &str,
    secs: &str,
    more: &[&str],
) -> (u16, std::process::Child) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["serve", run, "--port", "0", "--speed", speed, "--for", secs])
        .args(more)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let port = line
        .rsplit_once("127.0.0.1:")
        .and_then(|(_, p)| p.split_whitespace().next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("btx serve said no port: {line}"));
    (port, child)
}

/// What is in a directory, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn run_and_watch_racing_on_one_output_never_lose_a_run() {
    // The run printed "1350001 transitions" and exited 0 while the file
    // held the watch's partial (#26 item 1).
    let (port, mut server) = served("sessions/kitting-nominal.jsonl", "50", "600");
    let dir = tempfile::tempdir().unwrap();
    let tree = fixture("kitting-tree.v4.xml");
    let plan = fixture("plans/kitting_nominal.plan");
    let (mut runs_won, mut watches_won) = (0, 0);
    for i in 0..100 {
        let out = dir.path().join(format!("race{i}.jsonl"));
        let spawn = |args: Vec<String>| {
            Command::new(env!("CARGO_BIN_EXE_btx"))
                .args(args)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let o = out.display().to_string();
        let watch = spawn(
            ["watch", &format!(":{port}"), "--for", "0.05", "--out", &o]
                .map(String::from)
                .to_vec(),
        );
        let run = spawn(
            [
                "run",
                tree.to_str().unwrap(),
                "--plan",
                plan.to_str().unwrap(),
                "--out",
                &o,
            ]
            .map(String::from)
            .to_vec(),
        );
        let (w, r) = (
            watch.wait_with_output().unwrap(),
            run.wait_with_output().unwrap(),
        );
        let (werr, rerr) = (
            String::from_utf8_lossy(&w.stderr).into_owned(),
            String::from_utf8_lossy(&r.stderr).into_owned(),
        );
        let refused = |err: &str| {
            let e = one_line(err);
            e.contains("another btx is writing this session")
                || e.contains("a session already exists here")
        };
        assert!(
            w.status.success() != r.status.success(),
            "race {i}: exactly one writes the session\nwatch: {werr}\nrun: {rerr}"
        );
        let kind = if w.status.success() {
            assert!(
                refused(&rerr),
                "race {i}: the run is refused, saying why: {rerr}"
            );
            watches_won += 1;
            "groot2"
        } else {
            assert!(
                refused(&werr),
                "race {i}: the watch is refused, saying why: {werr}"
            );
            runs_won += 1;
            "plan"
        };
        let text = std::fs::read_to_string(&out).unwrap();
        let header: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
        let src = &header["source"];
        let wrote = if src["kind"] == "plan" {
            "plan"
        } else {
            src["name"].as_str().unwrap_or("")
        };
        assert_eq!(
            wrote, kind,
            "race {i}: the file holds the run of the one that said it wrote it"
        );
        assert!(
            text.lines().last().unwrap().contains("\"end\""),
            "race {i}: whole"
        );
        let mut want: Vec<String> = (0..=i).map(|k| format!("race{k}.jsonl")).collect();
        want.sort();
        assert_eq!(
            listing(dir.path()),
            want,
            "race {i}: no partial, lock or temporary file is left"
        );
    }
    let _ = server.kill();
    // Both orders happened (else the race was not run).
    assert!(
        runs_won > 0 && watches_won > 0,
        "run {runs_won}, watch {watches_won}"
    );
}

#[test]
fn an_output_that_cannot_be_written_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let ro = dir.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    let mut perm = std::fs::metadata(&ro).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perm, 0o555);
    std::fs::set_permissions(&ro, perm).unwrap();
    // Root writes into a mode-555 directory, but not into sysfs's root.
    let root = std::fs::write(ro.join("probe"), "").is_ok();
    let unwritable = if root {
        Path::new("/sys").to_path_buf()
    } else {
        ro
    };
    let tree = fixture("kitting-tree.v4.xml");
    let plan = fixture("plans/kitting_nominal.plan");
    let log = fixture("logs/kitting_lookat_fails_once.btlog");
    let targets = [
        (dir.path().join("missing/s.jsonl"), "does not exist"),
        // Permission denied, or a read-only file system where sysfs is one.
        (unwritable.join("btx-s.jsonl"), "cannot write here: "),
    ];
    for (out, says) in &targets {
        let o = out.to_str().unwrap();
        for args in [
            vec![
                "run",
                tree.to_str().unwrap(),
                "--plan",
                plan.to_str().unwrap(),
                "--out",
                o,
            ],
            vec!["import", log.to_str().unwrap(), "--out", o],
            vec!["watch", ":1", "--out", o],
        ] {
            let started = Instant::now();
            let (code, _, err) = btx_code(&args);
            assert_eq!(code, Some(1), "{args:?}: {err}");
            let e = one_line(&err);
            assert!(
                e.contains("cannot write here") && e.contains(says),
                "{args:?}: {e}"
            );
            // The watch is refused before it tries the robot (none is at :1).
            assert!(!e.contains("connect"), "{args:?}: {e}");
            assert!(started.elapsed() < Duration::from_secs(5));
        }
    }
}

#[test]
fn a_write_past_the_file_size_limit_is_said_with_what_was_kept() {
    // `ulimit -f` killed run and import by SIGXFSZ without a word (#26).
    let dir = tempfile::tempdir().unwrap();
    let tree = fixture("kitting-tree.v4.xml");
    let plan = fixture("plans/kitting_nominal.plan");
    let log = fixture("logs/kitting_lookat_fails_once.btlog");
    let whole = dir.path().join("whole.jsonl");
    let (ok, _, err) = btx(&[
        "import",
        log.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let limit = std::fs::metadata(&whole).unwrap().len() * 2 / 3;
    for (name, args) in [
        (
            "run",
            vec![
                "run",
                tree.to_str().unwrap(),
                "--plan",
                plan.to_str().unwrap(),
            ],
        ),
        ("import", vec!["import", log.to_str().unwrap()]),
    ] {
        let out = dir.path().join(format!("{name}.jsonl"));
        let r = Command::new("prlimit")
            .arg(format!("--fsize={limit}"))
            .arg("--")
            .arg(env!("CARGO_BIN_EXE_btx"))
            .args(&args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let err = one_line(&String::from_utf8_lossy(&r.stderr));
        assert_eq!(
            r.status.code(),
            Some(1),
            "{name}: not killed by SIGXFSZ: {err}"
        );
        assert!(
            err.contains("the file size limit (ulimit -f) is reached")
                && err.contains("this file keeps the run up to tick"),
            "{name}: {err}"
        );
        assert!(err.contains(".partial"), "{name}: names the file: {err}");
        assert!(!out.exists(), "{name}: no whole session is claimed");
    }
}

#[test]
fn a_watch_that_cannot_write_stops_saying_so_and_a_closed_stdout_keeps_recording() {
    // It said "connecting again" at every save and exited having written
    // nothing; `| head -2` stopped the recording without a word (#26 item 2).
    let run = "sessions/kitting-nominal.jsonl";
    let whole = std::fs::metadata(Path::new(env!("CARGO_MANIFEST_DIR")).join(run))
        .unwrap()
        .len();
    let dir = tempfile::tempdir().unwrap();
    let (port, mut server) = served(run, "10", "60");
    let out = dir.path().join("w.jsonl");
    let r = Command::new("prlimit")
        .arg(format!("--fsize={}", whole / 2))
        .arg("--")
        .arg(env!("CARGO_BIN_EXE_btx"))
        .args(["watch", &format!(":{port}"), "--for", "20", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .output()
        .unwrap();
    let err = one_line(&String::from_utf8_lossy(&r.stderr));
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("the file size limit (ulimit -f) is reached")
            && err.contains("w.jsonl.partial")
            && err.contains("this file keeps the run up to tick"),
        "{err}"
    );
    assert!(!err.contains("connecting again"), "{err}");
    let _ = server.kill();

    // Slow enough that rows come after the pipe is closed.
    let (port, mut server) = served(run, "2", "60");
    let out = dir.path().join("piped.jsonl");
    let mut w = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args([
            "watch",
            &format!(":{port}"),
            "--for",
            "3",
            "--transitions",
            "--out",
        ])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // `| head -2`: two lines read, then the pipe closed.
    let mut lines = std::io::BufReader::new(w.stdout.take().unwrap()).lines();
    for _ in 0..2 {
        lines.next().unwrap().unwrap();
    }
    drop(lines);
    let done = w.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "{err}");
    assert!(
        err.contains("standard output was closed; still recording to"),
        "{err}"
    );
    let _ = server.kill();
    let said: usize = err
        .split(" transitions written to")
        .next()
        .and_then(|l| l.rsplit('\n').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    let kept = Session::load(&out).unwrap();
    assert!(kept.end.is_some(), "finished as on Ctrl-C");
    assert_eq!(kept.index.transitions.len(), said);
    assert!(said > 20, "recording went on after the pipe closed: {err}");
}

#[test]
fn a_session_header_past_its_bound_is_refused_before_it_is_parsed() {
    // A 40 MB header line aborted `btx log` (#26 item 5).
    let (mut header, rest) = case_study_header();
    let xml = header["tree"]["xml"].as_str().unwrap().to_string();
    header["tree"]["xml"] = format!("{xml}<!--PAD-->").into();
    let text = header.to_string();
    let (before, after) = text.split_once("PAD").unwrap();
    // Written in pieces: this process's memory counts in the peaks
    // measured here.
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("big.jsonl");
    let mut w = std::io::BufWriter::new(std::fs::File::create(&f).unwrap());
    use std::io::Write;
    w.write_all(before.as_bytes()).unwrap();
    let piece = [b'x'; 1 << 16];
    for _ in 0..(40 << 20) / piece.len() {
        w.write_all(&piece).unwrap();
    }
    w.write_all(after.as_bytes()).unwrap();
    writeln!(w).unwrap();
    w.write_all(rest.as_bytes()).unwrap();
    drop(w);
    let r = btx_run(&["log", f.to_str().unwrap()]);
    assert_eq!(r.code, Some(1), "{}", r.err);
    assert!(
        one_line(&r.err).contains(
            "a header (the tree, its blackboard and the nodes' states) is at most 16 MiB"
        ),
        "{}",
        r.err
    );
    assert!(r.peak_kib < 200 << 10, "{} KiB", r.peak_kib);
}

#[test]
fn follow_says_when_its_file_is_truncated_or_replaced_and_starts_again() {
    // `log --follow` went silent or showed wrong rows (#26 item 9).
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let failing =
        std::fs::read_to_string(root.join("sessions/kitting-lookat-fails-once.jsonl")).unwrap();
    let nominal = std::fs::read_to_string(root.join("sessions/kitting-nominal.jsonl")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("followed.jsonl");
    std::fs::write(&f, &failing).unwrap();
    let (out, err) = (dir.path().join("out"), dir.path().join("err"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["log", "--follow"])
        .arg(&f)
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .unwrap();
    let wait_for = |what: &dyn Fn(&str, &str) -> bool| {
        let started = Instant::now();
        loop {
            let (o, e) = (
                std::fs::read_to_string(&out).unwrap_or_default(),
                std::fs::read_to_string(&err).unwrap_or_default(),
            );
            if what(&o, &e) {
                return (o, e);
            }
            assert!(
                started.elapsed() < Duration::from_secs(15),
                "stdout:\n{o}\nstderr:\n{e}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    };
    let rows = |o: &str| o.lines().filter(|l| l.contains("->")).count();
    let whole = Session::load(&f).unwrap().index.transitions.len();
    let (o, _) = wait_for(&|o, _| rows(o) == whole);
    // Replaced (renamed over) by another run of the same tree.
    let tmp = dir.path().join("next.jsonl");
    std::fs::write(&tmp, &nominal).unwrap();
    std::fs::rename(&tmp, &f).unwrap();
    let (_, e) = wait_for(&|_, e| e.contains("was replaced by another run"));
    assert!(e.contains("following it again from its start"), "{e}");
    let (o2, _) = wait_for(&|o2, _| rows(o2) >= rows(&o) + 20);
    // Truncated to its header and a few records.
    let cut: String = nominal.lines().take(6).map(|l| format!("{l}\n")).collect();
    std::fs::write(&f, &cut).unwrap();
    wait_for(&|_, e| e.contains("was truncated or shrunk"));
    let (o3, _) = wait_for(&|o3, _| rows(o3) > rows(&o2));
    // Shrunk mid-record: said once, not at every poll (#41 item 9).
    std::fs::write(&f, &nominal.as_bytes()[..3000]).unwrap();
    wait_for(&|_, e| e.contains("following: "));
    std::thread::sleep(Duration::from_millis(1500));
    let e = std::fs::read_to_string(&err).unwrap();
    assert_eq!(e.matches("following: ").count(), 1, "{e}");
    let _ = child.kill();
    let _ = child.wait();
    assert!(
        rows(&o3) > rows(&o2),
        "the rows it holds now are printed again: {o3}"
    );
    assert!(!e.contains("panicked"), "{e}");
}

/// Runs `btx ARGS` in a mount namespace of its own where `DIR` is a
/// `KIB`-KiB tmpfs, first filled with `fill` KiB: a full disk made
/// without privileges (`unshare --user --map-root-user --mount`).
fn on_a_small_disk(dir: &Path, kib: u32, fill: u32, args: &str) -> (Option<i32>, String) {
    let script = format!(
        "mount -t tmpfs -o size={kib}k none {d} && \
         {{ [ {fill} -eq 0 ] || dd if=/dev/zero of={d}/filler bs=1k count={fill} 2>/dev/null; true; }} && \
         cd {root} && exec {btx} {args}",
        d = dir.display(),
        root = env!("CARGO_MANIFEST_DIR"),
        btx = env!("CARGO_BIN_EXE_btx"),
    );
    let r = Command::new("unshare")
        .args(["--user", "--map-root-user", "--mount", "sh", "-c", &script])
        .output()
        .expect("unshare (util-linux) makes a small disk for the test");
    let err = one_line(&String::from_utf8_lossy(&r.stderr));
    assert!(
        !err.contains("unshare:"),
        "user namespaces are needed here: {err}"
    );
    (r.status.code(), err)
}

#[test]
fn a_full_disk_is_refused_at_once_and_a_disk_that_fills_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().display().to_string();
    let tree = fixture("kitting-tree.v4.xml");
    let plan = fixture("plans/kitting_nominal.plan");
    let run = format!(
        "run {} --plan {} --out {d}/s.jsonl",
        tree.display(),
        plan.display()
    );
    // Full before the work: refused at once, nothing run.
    let (code, err) = on_a_small_disk(dir.path(), 64, 64, &run);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("cannot write here: the disk is full"), "{err}");
    assert!(!err.contains("ticks"), "nothing was run: {err}");
    // Filling during the work: said with the file and what it keeps.
    let (code, err) = on_a_small_disk(dir.path(), 16, 0, &run);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("s.jsonl.partial: cannot write the session: the disk is full; this file keeps the run up to tick"),
        "{err}"
    );
}

/// `btx log [--follow] FILE`'s peak memory (KiB), once its table is
/// whole (`--follow`: then stopped with SIGINT).
fn log_peak_kib(file: &Path, follow: bool, rows: usize) -> i64 {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut c = Command::new(env!("CARGO_BIN_EXE_btx"));
    c.arg("log");
    if follow {
        c.arg("--follow");
    }
    let child = c
        .arg(file)
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = child.id() as libc::pid_t;
    if follow {
        let started = Instant::now();
        while std::fs::read(&out)
            .unwrap()
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            < rows
        {
            assert!(started.elapsed() < Duration::from_secs(60));
            std::thread::sleep(Duration::from_millis(100));
        }
        // SAFETY: signals our own child.
        unsafe { libc::kill(pid, libc::SIGINT) };
    }
    wait_peak(child).peak_kib
}

#[test]
fn following_a_run_holds_what_logging_it_holds() {
    // `btx log --follow` held about 280 B a transition, 5 times `btx log`
    // (#41 item 6): it built every row, and the whole table as one text.
    let dir = tempfile::tempdir().unwrap();
    let leaves: String = (0..150).map(|_| "<AlwaysSuccess/>").collect();
    let tree = dir.path().join("busy.xml");
    std::fs::write(&tree, format!("<root BTCPP_format=\"4\"><BehaviorTree ID=\"Main\"><ReactiveSequence>{leaves}<Act name=\"wait\"/></ReactiveSequence></BehaviorTree><TreeNodesModel><Action ID=\"Act\"/></TreeNodesModel></root>")).unwrap();
    let plan = dir.path().join("busy.plan");
    std::fs::write(&plan, "wait = 1000RS\n").unwrap();
    let run = dir.path().join("busy.jsonl");
    let (ok, _, err) = btx(&[
        "run",
        tree.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let rows = 1 + Session::load(&run).unwrap().index.transitions.len();
    let log = log_peak_kib(&run, false, rows);
    let follow = log_peak_kib(&run, true, rows);
    assert!(
        follow < log * 3 / 2 + 8 * 1024,
        "follow {follow} KiB, log {log} KiB, {rows} rows"
    );
}
