//! #40 item 4: the time of day, kept and shown. A log's per-transition
//! times survive `btx import` (JSON lines and Parquet, either way), `btx
//! log --time` shows them, and a run that has none says so.

mod common;

use common::btx;

#[test]
fn a_logs_times_are_kept_by_import_and_shown_by_log() {
    let dir = tempfile::tempdir().unwrap();
    let log = "tests/fixtures/logs/kitting_lookat_fails_once.btlog";
    let jsonl = dir.path().join("a.jsonl");
    let parquet = dir.path().join("a.parquet");
    let back = dir.path().join("b.jsonl");
    let (ok, _, err) = btx(&["import", log, "--out", jsonl.to_str().unwrap()]);
    assert!(ok, "{err}");
    let (ok, _, err) = btx(&[
        "import",
        jsonl.to_str().unwrap(),
        "--out",
        parquet.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let (ok, _, err) = btx(&[
        "import",
        parquet.to_str().unwrap(),
        "--out",
        back.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let (ok, want, _) = btx(&["log", log, "--time", "utc"]);
    assert!(ok);
    assert!(want.starts_with("     time (UTC)  tick"), "{want}");
    // The fixture's transition at 10:1, as its FileLogger2 timed it.
    assert!(
        want.contains("01:55:41.796157    10     1    18  look at chuck                            RUNNING  -> FAILURE"),
        "{want}"
    );
    for f in [&jsonl, &parquet, &back] {
        let (ok, got, err) = btx(&["log", f.to_str().unwrap(), "--time", "utc"]);
        assert!(ok, "{err}");
        assert_eq!(got, want, "{}", f.display());
    }
    // Relative to the first transition, in seconds: what --time alone gives.
    let (_, rel, _) = btx(&[
        "log",
        back.to_str().unwrap(),
        "--time",
        "relative",
        "--node",
        "#18",
    ]);
    let (_, alone, _) = btx(&["log", back.to_str().unwrap(), "--node", "#18", "--time"]);
    assert_eq!(alone, rel);
    assert!(
        rel.lines()
            .nth(2)
            .unwrap()
            .trim_start()
            .starts_with("0.048 "),
        "{rel}"
    );
    // In the local time zone (a POSIX TZ needs no zone files): UTC+05:30.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["log", log, "--time", "local", "--node", "#18"])
        .env("TZ", "IST-05:30")
        .output()
        .unwrap();
    let local = String::from_utf8_lossy(&out.stdout);
    assert!(local.starts_with("time (UTC+05:30)  tick"), "{local}");
    assert!(
        local.contains(" 07:25:41.796157    10     1    18  look at chuck"),
        "{local}"
    );
    // JSON rows carry the time whatever the text shows.
    let (_, json, _) = btx(&[
        "log",
        back.to_str().unwrap(),
        "--format",
        "json",
        "--node",
        "#18",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["transitions"][1]["time"], "2026-11-22T01:55:41.796157Z");
    assert_eq!(v["transitions"][1]["time_us"], 1_795_312_541_796_157_i64);
}

#[test]
fn a_run_without_times_says_so() {
    let (ok, _, err) = btx(&["log", "sessions/kitting-nominal.jsonl", "--time", "utc"]);
    assert!(!ok);
    assert!(
        err.contains("sessions/kitting-nominal.jsonl: no time is known for its transitions"),
        "{err}"
    );
}

/// `--detail full` says the robot's time of day at each moment named.
#[test]
fn a_full_answer_says_the_time_of_each_moment() {
    let log = "tests/fixtures/logs/kitting_lookat_fails_once.btlog";
    for q in ["why did look at chuck fail", "what went wrong"] {
        let (ok, out, err) = btx(&["ask", log, q, "--detail", "full"]);
        assert!(ok, "{err}");
        let times = out
            .lines()
            .find(|l| l.starts_with("Times (the robot's clock, UTC): "))
            .unwrap_or_else(|| panic!("{q}: {out}"));
        assert!(
            times.contains("10:1 01:55:41.796") || times.contains("tick 10 01:55:41.796"),
            "{q}: {times}"
        );
        assert!(!times.contains("01:55:41 "), "{q}: {times}");
    }
    // Normal detail keeps to the answer; a run with no times says none.
    let (_, out, _) = btx(&["ask", log, "why did look at chuck fail"]);
    assert!(!out.contains("Times ("), "{out}");
    let (_, out, _) = btx(&[
        "ask",
        "sessions/kitting-lookat-fails-once.jsonl",
        "why did look at chuck fail",
        "--detail",
        "full",
    ]);
    assert!(!out.contains("Times ("), "{out}");
}

/// "When" answers say the robot's time of day beside the moment, where
/// the run keeps it.
#[test]
fn when_answers_say_the_time_of_day() {
    let (ok, out, err) = btx(&[
        "ask",
        "tests/fixtures/logs/kitting_lookat_fails_once.btlog",
        "when did look at chuck fail?",
        "when did look at chuck first start",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains(": at 10:1, 01:55:41.796157 UTC."), "{out}");
    assert!(
        out.contains("first started at 9:2, 01:55:41.791002 UTC ("),
        "{out}"
    );
    // A simulated run has no clock: the moment alone.
    let (_, out, _) = btx(&[
        "ask",
        "sessions/kitting-lookat-fails-once.jsonl",
        "when did look at chuck fail?",
    ]);
    assert!(out.contains(": at 10:1."), "{out}");
}

/// `--at` takes a time of day on the robot's clock: the moment after the
/// last transition at or before it.
#[test]
fn at_takes_a_time_of_day() {
    let log = "tests/fixtures/logs/kitting_lookat_fails_once.btlog";
    // 01:55:41.796157 is look at chuck's failure at 10:1.
    for at in ["01:55:41.7962", "01:55:41.796157 UTC", "01:55:41.796157Z"] {
        let (ok, out, err) = btx(&["why", log, "status(#18)", "--at", at]);
        assert!(ok, "{at}: {err}");
        assert!(
            out.starts_with("Why did look at chuck (#18) fail at 10:1?"),
            "{at}: {out}"
        );
    }
    // The time an answer says is the moment it was about: to the
    // microsecond, since look at chuck fails 157 µs into that millisecond
    // and the rest of tick 10 comes within it.
    let (_, said, _) = btx(&["ask", log, "when did look at chuck fail?"]);
    let at = said
        .split("at 10:1, ")
        .nth(1)
        .and_then(|t| t.split(" UTC").next())
        .unwrap_or_else(|| panic!("{said}"));
    assert_eq!(at, "01:55:41.796157");
    for at in [
        at,
        "2026-11-22T01:55:41.796157Z",
        "2026-11-22 01:55:41.796157",
    ] {
        let (ok, out, err) = btx(&["why", log, "status(#18)", "--at", at]);
        assert!(ok, "{at}: {err}");
        assert!(
            out.starts_with("Why did look at chuck (#18) fail at 10:1?"),
            "{at}: {out}"
        );
    }
    let (ok, _, err) = btx(&["why", log, "status(#18)", "--at", "2026-11-23T01:55:41Z"]);
    assert!(!ok);
    assert!(
        err.contains("is after the run's last transition, at 2026-11-22T01:55:4"),
        "{err}"
    );
    let (ok, _, err) = btx(&["why", log, "status(#18)", "--at", "2026-13-01T01:55:41Z"]);
    assert!(!ok && err.contains("is not a time of day"), "{err}");
    let (ok, _, err) = btx(&["why", log, "status(#18)", "--at", "00:00:01"]);
    assert!(!ok);
    assert!(
        err.contains("is before the run's first transition, at 2026-11-22T01:55:41.748"),
        "{err}"
    );
    let (ok, _, err) = btx(&[
        "ask",
        "sessions/kitting-nominal.jsonl",
        "--at",
        "01:00:00",
        "what are you doing",
    ]);
    assert!(!ok);
    assert!(err.contains("keeps no times"), "{err}");
    // Two colons make a time; one is still TICK:STEP.
    let (ok, out, _) = btx(&["why", log, "status(#18)", "--at", "10:1"]);
    assert!(
        ok && out.starts_with("Why did look at chuck (#18) fail at 10:1?"),
        "{out}"
    );
}
