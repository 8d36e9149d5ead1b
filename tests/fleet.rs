//! `btx fleet`: a fleet's runs answered at once (#31 item 4). Each figure
//! is checked against what the commands about one run say of each run
//! (`btx log`, `btx ask`), not against sentences written here.

mod common;

use common::btx;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn json(args: &[&str]) -> Value {
    let (ok, out, err) = btx(args);
    assert!(ok, "{err}");
    serde_json::from_str(&out).unwrap()
}

/// A fleet of ten kitting runs in a directory: three nominal, two where
/// look at chuck fails once, two where detect chuck always fails (the
/// fallback asks for help), two where asking fails too (the run fails),
/// and under `robot/` the real BehaviorTree.CPP 4.10 log of look at chuck
/// failing once (tests/fixtures/logs, from ../shared/fixtures/btcpp). A
/// notes file is not a run; a broken log is said and the rest read.
fn fleet() -> (tempfile::TempDir, Vec<PathBuf>) {
    let dir = tempfile::tempdir().unwrap();
    let failing = dir.path().join("ask-fails.plan");
    std::fs::write(
        &failing,
        "@default_action = 1RS\n@default_condition = S\ndetect chuck = 1RF\nask = 1RF\n",
    )
    .unwrap();
    let mut runs = Vec::new();
    for (plan, copies) in [
        ("trees/plans/kitting-nominal.plan", 3),
        ("trees/plans/kitting-lookat-fails-once.plan", 2),
        ("trees/plans/kitting-detect-chuck-always-fails.plan", 2),
        (failing.to_str().unwrap(), 2),
    ] {
        let stem = Path::new(plan).file_stem().unwrap().to_str().unwrap();
        for k in 1..=copies {
            let out = dir.path().join(format!("{stem}-{k}.jsonl"));
            let (ok, _, err) = btx(&[
                "-q",
                "run",
                "trees/kitting.xml",
                "--plan",
                plan,
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(ok, "{err}");
            runs.push(out);
        }
    }
    std::fs::create_dir(dir.path().join("robot")).unwrap();
    let log = dir.path().join("robot/kitting_lookat_fails_once.btlog");
    std::fs::copy(
        common::fixture("logs/kitting_lookat_fails_once.btlog"),
        &log,
    )
    .unwrap();
    runs.push(log);
    std::fs::write(dir.path().join("notes.txt"), "not a run").unwrap();
    std::fs::write(dir.path().join("broken.btlog"), b"BTX\0not a log").unwrap();
    (dir, runs)
}

/// A run's transitions as `btx log` gives them: (tick, uid, prev, status).
fn transitions(run: &Path) -> Vec<(u64, u64, String, String)> {
    let v = json(&["log", run.to_str().unwrap(), "--format", "json"]);
    v["transitions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            (
                t["tick"].as_u64().unwrap(),
                t["uid"].as_u64().unwrap(),
                t["prev"].as_str().unwrap().to_string(),
                t["status"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

fn node<'a>(v: &'a Value, name: &str) -> &'a Value {
    v["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"] == name)
        .unwrap_or_else(|| panic!("no node {name}"))
}

#[test]
fn a_fleets_figures_are_what_each_run_says() {
    let (dir, runs) = fleet();
    let d = dir.path().to_str().unwrap();
    let v = json(&["fleet", d, "--format", "json"]);
    assert_eq!(v["runs"], runs.len(), "{v}");
    assert_eq!(v["errors"].as_array().unwrap().len(), 1, "{v}");
    assert!(v["errors"][0]["file"]
        .as_str()
        .unwrap()
        .ends_with("broken.btlog"));
    // How each run ended is the root's last completion in `btx log`.
    for r in v["each_run"].as_array().unwrap() {
        let name = r["name"].as_str().unwrap();
        let ts = transitions(Path::new(name));
        let root = ts
            .iter()
            .rev()
            .find(|t| t.1 == 1 && (t.3 == "SUCCESS" || t.3 == "FAILURE"))
            .unwrap();
        assert_eq!(r["outcome"], root.3.as_str(), "{name}");
    }
    assert_eq!(v["outcomes"]["FAILURE"], 2);
    assert_eq!(v["outcomes"]["SUCCESS"], runs.len() - 2);
    // The failed runs, grouped by what `btx ask RUN "What went wrong?"`
    // answers for each.
    let causes = v["causes"].as_array().unwrap();
    assert_eq!(causes.len(), 1, "{v}");
    for r in causes[0]["runs"].as_array().unwrap() {
        let (ok, out, _) = btx(&["ask", r.as_str().unwrap(), "What went wrong?"]);
        assert!(ok);
        assert_eq!(out.trim_end(), causes[0]["what_went_wrong"], "{r}");
    }
    // A leaf's failures and RUNNING spells, counted from each run's log.
    for (name, uid) in [
        ("look at chuck #18", 18),
        ("detect chuck #12", 12),
        ("move to see chuck #6", 6),
    ] {
        let n = node(&v, name);
        let (mut ran_in, mut failed_in, mut failures, mut spells) = (0, 0, 0, Vec::new());
        for r in &runs {
            let ts = transitions(r);
            let mine: Vec<_> = ts.iter().filter(|t| t.1 == uid).collect();
            ran_in += usize::from(mine.iter().any(|t| t.3 != "IDLE"));
            let f = mine.iter().filter(|t| t.3 == "FAILURE").count();
            failed_in += usize::from(f > 0);
            failures += f;
            let mut since = None;
            for t in &mine {
                match (t.3.as_str(), since) {
                    ("RUNNING", None) => since = Some(t.0),
                    ("RUNNING", Some(_)) => {}
                    (_, Some(s)) => {
                        spells.push(t.0 - s);
                        since = None;
                    }
                    _ => {}
                }
            }
        }
        assert_eq!(n["ran_in"], ran_in, "{name}");
        assert_eq!(n["failed_in"], failed_in, "{name}");
        assert_eq!(n["failures"], failures, "{name}");
        spells.sort_unstable();
        assert_eq!(n["running_ticks"]["spells"], spells.len(), "{name}");
        assert_eq!(
            n["running_ticks"]["max"],
            spells.last().copied().unwrap_or(0),
            "{name}"
        );
    }
    // Look at chuck's failures were each recovered by the retry above it,
    // as `btx ask … "How was the failure handled?"` says of one of them at
    // the run's end.
    let look = node(&v, "look at chuck #18");
    assert_eq!(look["recovered"][0]["by"], "RetryUntilSuccessful #7");
    assert_eq!(look["recovered"][0]["failures"], look["failures"]);
    let (ok, out, _) = btx(&[
        "ask",
        runs[3].to_str().unwrap(),
        "--node",
        "#18",
        "How was the failure handled?",
    ]);
    assert!(ok);
    assert!(
        out.contains("RetryUntilSuccessful (#7) tried again and succeeded"),
        "{out}"
    );
    // Detect chuck's: by the fallback asking for help where asking
    // worked, not at all where it failed too.
    let detect = node(&v, "detect chuck #12");
    assert_eq!(detect["recovered"][0]["by"], "go insert large gear #3");
    assert_eq!(detect["recovered"][0]["failures"], 6);
    assert_eq!(detect["unrecovered"], 6);
}

#[test]
fn a_fleet_reads_as_text_with_its_causes_first_in_words() {
    let (dir, runs) = fleet();
    let d = dir.path().to_str().unwrap();
    let (ok, out, err) = btx(&["fleet", d]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with(&format!(
            "{} runs of 1 tree (build a gearbox kit): {} SUCCESS, 2 FAILURE;",
            runs.len(),
            runs.len() - 2
        )),
        "{out}"
    );
    assert!(out.contains("not read: "), "{out}");
    let v = json(&["fleet", d, "--format", "json"]);
    let look = node(&v, "look at chuck #18");
    assert!(
        out.contains(&format!(
            "  look at chuck #18 failed in 3 of the {} runs it ran in (3 failures); 3 recovered by RetryUntilSuccessful #7.\n",
            look["ran_in"]
        )),
        "{out}"
    );
    assert!(
        out.contains("Failed runs, by what went wrong:\n  2 runs: The task failed: go insert large gear stopped because ask failed.\n"),
        "{out}"
    );
    // A pattern the shell did not expand is expanded as it would be.
    let pattern = format!("{d}/*.jsonl");
    let v = json(&["fleet", &pattern, "--format", "json"]);
    assert_eq!(v["runs"], runs.len() - 1);
    let (ok, _, err) = btx(&["fleet", &format!("{d}/*.nothing")]);
    assert!(!ok);
    assert!(err.contains("no file matches this pattern"), "{err}");
}

#[test]
fn a_fleet_against_a_reference_says_where_each_run_diverges() {
    let (dir, runs) = fleet();
    let reference = runs[0].to_str().unwrap();
    let v = json(&[
        "fleet",
        dir.path().to_str().unwrap(),
        "--reference",
        reference,
        "--format",
        "json",
    ]);
    let table = &v["reference"]["runs"];
    assert_eq!(table.as_array().unwrap().len(), runs.len());
    // Each run's verdict is `btx diff REF RUN`'s.
    for r in table.as_array().unwrap() {
        let name = r["name"].as_str().unwrap();
        let d = json(&["diff", reference, name, "--format", "json"]);
        assert_eq!(r["identical"], d["identical"], "{name}");
    }
}

#[test]
fn duckdb_reads_the_export_of_a_thousand_runs_to_the_same_figures() {
    // #31 item 5: ten robots of a hundred runs each (the shipped kitting
    // sessions and a real BehaviorTree.CPP log, in turn), exported as
    // Parquet; DuckDB (the PyPI package, not btx) reads the tables as
    // they are, and its figures are `btx fleet`'s.
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let sources: Vec<PathBuf> = common::kitting_fleet()
        .iter()
        .map(|p| root.join(p))
        .collect();
    let fleet = dir.path().join("fleet");
    for i in 0..1000 {
        let robot = fleet.join(format!("robot-{}", i / 100));
        std::fs::create_dir_all(&robot).unwrap();
        let src = &sources[i % sources.len()];
        let ext = src.extension().unwrap().to_str().unwrap();
        std::fs::copy(src, robot.join(format!("run-{i:04}.{ext}"))).unwrap();
    }
    let out = dir.path().join("export");
    let v = json(&[
        "fleet",
        fleet.to_str().unwrap(),
        "--export",
        out.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert_eq!(v["runs"], 1000);
    // Every file written beside its place is named once all are synced:
    // none is left as `.part`, and every table's files are there.
    let mut dirs = vec![out.clone()];
    let mut files = 0;
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else {
                assert!(
                    p.extension().is_some_and(|x| x == "parquet"),
                    "{}",
                    p.display()
                );
                files += 1;
            }
        }
    }
    // A file a partition and core for each run's rows, not a file a run
    // (2,000 and more files for 1,000 runs made a quarter of the time).
    let partitions = std::fs::read_dir(out.join("runs"))
        .unwrap()
        .flatten()
        .flat_map(|robot| std::fs::read_dir(robot.path()).unwrap().flatten())
        .count();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert!(partitions >= 1, "no partition");
    assert!(
        files >= 3 * partitions && files <= partitions * (1 + 2 * cores),
        "{files} files for {partitions} partitions"
    );
    let py = std::process::Command::new(common::oracle_python())
        .arg(root.join("tests/fleet/duckdb_figures.py"))
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        py.status.success(),
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );
    let d: Value = serde_json::from_slice(&py.stdout).unwrap();
    assert_eq!(d["runs"], 1000);
    assert_eq!(d["robots"], 10);
    assert_eq!(d["transitions"], v["transitions"]);
    for o in ["SUCCESS", "FAILURE"] {
        assert_eq!(d["outcomes"][o], v["outcomes"][o], "{o}");
    }
    for n in v["nodes"].as_array().unwrap() {
        let uid = n["uid"].to_string();
        let q = &d["nodes"][&uid];
        for k in ["ran_in", "failed_in", "failures", "unrecovered"] {
            assert_eq!(q[k], n[k], "#{uid} {k}");
        }
        let recovered: u64 = n["recovered"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["failures"].as_u64().unwrap())
            .sum();
        assert_eq!(q["recovered"], recovered, "#{uid}");
        let from_transitions = d["failed_in_from_transitions"][&uid].as_u64().unwrap_or(0);
        assert_eq!(n["failed_in"], from_transitions, "#{uid}");
    }
    // The ticks, steps, times, nodes and statuses of the runs a .btlog
    // timed, row for row as `btx log` gives them.
    let logs = d["log_rows"].as_object().unwrap();
    assert_eq!(logs.len(), 1000 / sources.len());
    for (run, rows) in logs {
        let log = json(&["log", run, "--format", "json"]);
        let want: Vec<Value> = log["transitions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| serde_json::json!([t["tick"], t["step"], t["uid"], t["time_us"]]))
            .collect();
        assert!(want.len() > 10, "{run}");
        assert_eq!(rows["numbers"].as_array().unwrap(), &want, "{run}");
        // The text columns, written by their places in each row group's
        // dictionaries (`table::Columns::indexed`), read as `btx log`
        // names them.
        let texts: Vec<Value> = log["transitions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| serde_json::json!([t["node"], t["prev"], t["status"]]))
            .collect();
        assert_eq!(rows["texts"].as_array().unwrap(), &texts, "{run}");
    }
    for c in v["causes"].as_array().unwrap() {
        let why = c["what_went_wrong"].as_str().unwrap();
        assert_eq!(
            d["causes"][why],
            c["runs"].as_array().unwrap().len(),
            "{why}"
        );
    }
    // The export is refused where one already is.
    let (ok, _, err) = btx(&[
        "fleet",
        fleet.to_str().unwrap(),
        "--export",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("already holds files"), "{err}");
}

#[test]
fn a_directory_that_links_back_to_itself_is_read_once() {
    let (dir, runs) = fleet();
    std::os::unix::fs::symlink(dir.path(), dir.path().join("robot/loop")).unwrap();
    let v = json(&["fleet", dir.path().to_str().unwrap(), "--format", "json"]);
    assert_eq!(v["runs"], runs.len());
}

#[test]
fn robots_whose_names_differ_by_what_a_path_cannot_hold_stay_apart() {
    // `r:1` and `r?1` were both `robot=r_1` in --export, one robot to
    // every reader (#41 item 7): escaped as Spark escapes Hive paths, they
    // are two, under their own names, to DuckDB (the PyPI package).
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let fleet = dir.path().join("fleet");
    std::fs::create_dir_all(&fleet).unwrap();
    for (robot, src) in [
        ("r:1", "sessions/kitting-nominal.jsonl"),
        ("r?1", "sessions/kitting-lookat-fails-once.jsonl"),
        ("r\nforged", "sessions/kitting-nominal.jsonl"),
    ] {
        std::fs::copy(root.join(src), fleet.join(format!("{robot}.jsonl"))).unwrap();
    }
    // A file not read is named in the report: its name starts no line.
    std::fs::write(
        fleet.join("bad\nforged: every run SUCCESS.jsonl"),
        "garbage",
    )
    .unwrap();
    let out = dir.path().join("export");
    let (ok, report, err) = btx(&[
        "fleet",
        fleet.to_str().unwrap(),
        "--export",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let all = format!("{report}{err}");
    assert!(
        all.contains("bad\\nforged: every run SUCCESS.jsonl"),
        "{all}"
    );
    assert!(!all.lines().any(|l| l.starts_with("forged")), "{all}");
    let py = std::process::Command::new(common::oracle_python())
        .arg("-c")
        .arg("import duckdb, sys, json; print(json.dumps(duckdb.sql(\"select robot, count(*) from read_parquet('\" + sys.argv[1] + \"/transitions/**/*.parquet', hive_partitioning=true) group by robot order by robot\").fetchall()))")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        py.status.success(),
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );
    let got: Value = serde_json::from_slice(&py.stdout).unwrap();
    assert_eq!(
        got,
        serde_json::json!([["r\nforged", 209], ["r:1", 209], ["r?1", 248]])
    );
}

/// `btx fleet DIR`'s peak memory (KiB), from its own rusage.
fn fleet_peak_kib(dir: &Path) -> i64 {
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .arg("fleet")
        .arg(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let ended = common::wait_peak(child);
    assert_eq!(ended.code, Some(0));
    ended.peak_kib
}

#[test]
fn a_fleet_keeps_its_runs_summaries_not_their_nodes() {
    // `btx fleet` kept about 31 KB a run, every node's every spell (50,000
    // runs: 1.55 GB) (#41 item 6): each run's nodes are counted into the
    // fleet's as they are read. Measured as the growth from 1,000 to 5,000
    // runs (links to one failing run), in one test.
    let dir = tempfile::tempdir().unwrap();
    let run =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/kitting-lookat-fails-once.jsonl");
    let mut peaks = Vec::new();
    for n in [1000, 5000] {
        let d = dir.path().join(n.to_string());
        std::fs::create_dir_all(&d).unwrap();
        for i in 0..n {
            std::fs::hard_link(&run, d.join(format!("r{i:05}.jsonl"))).unwrap();
        }
        peaks.push(fleet_peak_kib(&d));
    }
    let per_run = (peaks[1] - peaks[0]) as f64 * 1024.0 / 4000.0;
    assert!(per_run < 2048.0, "{per_run:.0} bytes a run ({peaks:?} KiB)");
}
