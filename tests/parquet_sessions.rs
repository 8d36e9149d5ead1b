//! Parquet sessions (#31 item 3): `--out RUN.parquet` on run, import and
//! watch (tests/live.rs), read by every command as any session, and
//! converted either way without loss.

mod common;

use btx::session::format::{parse_record, Record};
use btx::session::Session;
use common::{btx, fixture};
use std::path::{Path, PathBuf};

fn import(from: &Path, out: &Path) {
    let (ok, _, err) = btx(&[
        "-q",
        "import",
        from.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        ok,
        "import {} --out {}: {err}",
        from.display(),
        out.display()
    );
}

/// A JSON-lines session's header line and records.
fn records(path: &Path) -> (String, Vec<Record>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    (header, lines.map(|l| parse_record(l).unwrap()).collect())
}

/// `btx run` of the kitting world (`args` after the world's): whether it
/// succeeded, and its stderr.
fn run_kitting(args: &[&str], out: &Path) -> (bool, String) {
    let mut all = vec!["-q", "run", "trees/kitting.xml", "--world", "kitting"];
    all.extend_from_slice(args);
    all.extend(["--out", out.to_str().unwrap()]);
    let (ok, _, err) = btx(&all);
    (ok, err)
}

fn shipped_sessions() -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "jsonl"))
            .collect();
    all.sort();
    assert!(all.len() >= 10, "{all:?}");
    all
}

/// A session with every kind of record: a shipped one with decisions and
/// writes, and a gap, a re-read of the states and an inserted subgoal
/// (`btx run --ask-at`) put in.
fn every_record_kind(dir: &Path) -> PathBuf {
    let out = dir.join("asked.jsonl");
    let (ok, err) = run_kitting(
        &[
            "--seed",
            "1",
            "--ask-at",
            "10",
            "Can you insert large gear?",
        ],
        &out,
    );
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let at = lines.len() / 2;
    let tick = match parse_record(lines[at]).unwrap() {
        Record::Transition { tick, step, .. } => format!("\"tick\":{tick},\"step\":{step}"),
        other => panic!("{other:?}"),
    };
    let gap = format!("{{\"k\":\"g\",{tick},\"reason\":\"the server's buffer was full\"}}");
    let resync =
        format!("{{\"k\":\"s\",{tick},\"states\":[{{\"uid\":1,\"status\":\"RUNNING\"}}]}}");
    let decision = format!("{{\"k\":\"d\",{tick},\"uid\":18,\"decision\":\"look left\"}}");
    lines.insert(at + 1, &decision);
    lines.insert(at + 1, &resync);
    lines.insert(at + 1, &gap);
    let all = dir.join("every-kind.jsonl");
    std::fs::write(&all, lines.join("\n") + "\n").unwrap();
    let kinds = records(&all).1;
    for k in ["Gap", "Resync", "Decision", "Insert", "End"] {
        let has = |r: &Record| format!("{r:?}").starts_with(k);
        assert!(kinds.iter().any(has), "no {k} record");
    }
    all
}

#[test]
fn sessions_go_to_parquet_and_back_without_loss() {
    let dir = tempfile::tempdir().unwrap();
    let mut all = shipped_sessions();
    all.push(every_record_kind(dir.path()));
    for (i, jsonl) in all.iter().enumerate() {
        let pq = dir.path().join(format!("{i}.parquet"));
        let back = dir.path().join(format!("{i}.back.jsonl"));
        import(jsonl, &pq);
        import(&pq, &back);
        let (h1, r1) = records(jsonl);
        let (h2, r2) = records(&back);
        assert_eq!(h1, h2, "{}: the header changed", jsonl.display());
        assert_eq!(r1, r2, "{}: the records changed", jsonl.display());
        // Written again, each format gives the very same bytes.
        let pq2 = dir.path().join(format!("{i}.2.parquet"));
        let back2 = dir.path().join(format!("{i}.2.jsonl"));
        import(&back, &pq2);
        import(&pq2, &back2);
        assert_eq!(std::fs::read(&pq).unwrap(), std::fs::read(&pq2).unwrap());
        assert_eq!(
            std::fs::read(&back).unwrap(),
            std::fs::read(&back2).unwrap()
        );
        // And every command reads both alike.
        for args in [
            vec!["log"],
            vec!["ask", "What went wrong?"],
            vec!["ask", "What are you doing?", "--at", "5"],
        ] {
            let run = |f: &Path| {
                let mut a = args.clone();
                a.insert(1, f.to_str().unwrap());
                let (ok, out, err) = btx(&a);
                (ok, out, err.replace(f.to_str().unwrap(), "FILE"))
            };
            assert_eq!(run(jsonl).1, run(&pq).1, "{} {args:?}", jsonl.display());
        }
    }
}

#[test]
fn a_logs_parquet_session_is_the_log_at_a_fraction_of_its_size() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "kitting_lookat_fails_once.btlog",
        "kitting_nominal.btlog",
        "kitting_grasp_check_fails_first.btlog",
        "kitting_detect_chuck_always_fails.btlog",
        "taxi_nominal.btlog",
    ] {
        let log = fixture(&format!("logs/{name}"));
        let pq = dir.path().join(name).with_extension("parquet");
        import(&log, &pq);
        let a = Session::load(&pq).unwrap();
        let (ok, from_log, _) = btx(&["log", log.to_str().unwrap()]);
        assert!(ok);
        let (ok, from_pq, _) = btx(&["log", pq.to_str().unwrap()]);
        assert!(ok);
        assert_eq!(from_log, from_pq, "{name}");
        let b = match btx::input::open(&log, &Default::default()).unwrap() {
            btx::input::Input::Session(s) => s,
            _ => unreachable!(),
        };
        assert_eq!(a.index.transitions, b.index.transitions, "{name}");
        assert_eq!(a.index.ticks(), b.index.ticks(), "{name}");
        assert_eq!(a.end, b.end, "{name}");
        let (pq_size, log_size) = (
            std::fs::metadata(&pq).unwrap().len(),
            std::fs::metadata(&log).unwrap().len(),
        );
        // The bound is 1.5 times; these runs come to about a third.
        assert!(
            pq_size * 2 < log_size,
            "{name}: {pq_size} bytes against the log's {log_size}"
        );
    }
}

#[test]
fn run_writes_the_same_session_as_parquet() {
    let dir = tempfile::tempdir().unwrap();
    let [pq, jsonl, back] = ["r.parquet", "r.jsonl", "back.jsonl"].map(|n| dir.path().join(n));
    for out in [&pq, &jsonl] {
        let (ok, err) = run_kitting(&["--seed", "3"], out);
        assert!(ok, "{err}");
    }
    import(&pq, &back);
    assert_eq!(records(&jsonl), records(&back));
    // Nothing else is left beside it.
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["back.jsonl", "r.jsonl", "r.parquet"]);
    // A second run to the same name is refused: a session is there.
    let (ok, err) = run_kitting(&[], &pq);
    assert!(!ok);
    assert!(err.contains("a session already exists here"), "{err}");
}

#[test]
fn a_broken_parquet_session_is_an_error_naming_the_file_never_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let pq = dir.path().join("s.parquet");
    import(
        &common::fixture("logs/kitting_lookat_fails_once.btlog"),
        &pq,
    );
    let bytes = std::fs::read(&pq).unwrap();
    let bad = dir.path().join("bad.parquet");
    let mut refused = 0;
    let cuts = (12..bytes.len()).step_by(97).map(|n| bytes[..n].to_vec());
    let flips = (0..bytes.len()).step_by(13).map(|i| {
        let mut b = bytes.clone();
        b[i] ^= 0x5a;
        b
    });
    for b in cuts.chain(flips) {
        std::fs::write(&bad, &b).unwrap();
        if let Err(e) = Session::load(&bad) {
            assert!(e.to_string().contains("bad.parquet"), "{e}");
            refused += 1;
        }
    }
    assert!(refused > 50, "{refused}");
    // A Parquet file that is not a session: a fleet's exported table.
    let fleet = dir.path().join("fleet");
    std::fs::create_dir(&fleet).unwrap();
    std::fs::copy(&pq, fleet.join("a.parquet")).unwrap();
    std::fs::copy(&pq, fleet.join("b.parquet")).unwrap();
    let tables = fleet.join("tables");
    let (ok, out, err) = btx(&[
        "-q",
        "fleet",
        fleet.to_str().unwrap(),
        "--export",
        tables.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("2 runs"), "{out}");
    let table = std::fs::read_dir(tables.join("transitions/robot=a"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let table = std::fs::read_dir(table)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let (ok, _, err) = btx(&["log", table.to_str().unwrap()]);
    assert!(!ok);
    assert!(err.contains("not a btx session"), "{err}");
    // The tables now beside the sessions are not taken for runs.
    let (ok, out, err) = btx(&["-q", "fleet", fleet.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(out.contains("2 runs"), "{out}");
}

#[test]
fn duckdb_reads_a_parquet_session_as_it_is() {
    // The PyPI package, not btx: every transition as `btx log` gives it.
    let dir = tempfile::tempdir().unwrap();
    let pq = dir.path().join("s.parquet");
    import(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/serial-recall.jsonl"),
        &pq,
    );
    let py = std::process::Command::new(common::oracle_python())
        .args([
            "-c",
            "import duckdb, json, sys
codes = ['IDLE', 'RUNNING', 'SUCCESS', 'FAILURE', 'SKIPPED']
rows = duckdb.sql(f\"select tick, step, uid, prev, status, decision from '{sys.argv[1]}' where uid is not null\").fetchall()
header = duckdb.sql(f\"select record from '{sys.argv[1]}' limit 1\").fetchall()[0][0]
print(json.dumps({'header': json.loads(header)['btx_session'],
  'rows': [[t, s, u, codes[p], codes[q], d] for t, s, u, p, q, d in rows]}))",
        ])
        .arg(&pq)
        .output()
        .unwrap();
    assert!(
        py.status.success(),
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );
    let d: serde_json::Value = serde_json::from_slice(&py.stdout).unwrap();
    assert_eq!(d["header"], 1);
    let (ok, log, _) = btx(&["log", pq.to_str().unwrap(), "--format", "json"]);
    assert!(ok);
    let log: serde_json::Value = serde_json::from_str(&log).unwrap();
    let want: Vec<serde_json::Value> = log["transitions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            serde_json::json!([
                t["tick"],
                t["step"],
                t["uid"],
                t["prev"],
                t["status"],
                t["decision"]
            ])
        })
        .collect();
    assert!(want.len() > 400);
    assert_eq!(d["rows"].as_array().unwrap(), &want);
}

#[test]
fn a_long_session_spans_row_groups_and_comes_back_whole() {
    // 65,536 rows a row group: the kitting run 330 times over is about
    // 70,000 records, so two row groups and a boundary inside a tick.
    let dir = tempfile::tempdir().unwrap();
    let (header, recs) =
        records(&Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/kitting-nominal.jsonl"));
    let ticks = match recs.last() {
        Some(Record::End { ticks, .. }) => *ticks,
        other => panic!("{other:?}"),
    };
    let mut lines = vec![header];
    let mut transitions = 0;
    for k in 0..330 {
        for r in &recs {
            let r = match r.clone() {
                Record::Transition {
                    tick,
                    step,
                    uid,
                    from,
                    to,
                    decision,
                    ..
                } => {
                    transitions += 1;
                    // Times too, so that the row groups carry them.
                    Record::Transition {
                        tick: tick + k * ticks,
                        step,
                        uid,
                        from,
                        to,
                        decision,
                        time_us: Some(1_795_312_541_000_000 + transitions as i64),
                    }
                }
                Record::Write {
                    tick,
                    step,
                    uid,
                    entry,
                    value,
                } => Record::Write {
                    tick: tick + k * ticks,
                    step,
                    uid,
                    entry,
                    value,
                },
                Record::End { .. } => continue,
                other => panic!("{other:?}"),
            };
            lines.push(serde_json::to_string(&r).unwrap());
        }
    }
    let end = Record::End {
        ticks: 330 * ticks,
        root: btx::run::Status::Success,
        transitions,
        reason: "root completed".into(),
    };
    lines.push(serde_json::to_string(&end).unwrap());
    assert!(lines.len() > 65_536 + 1000, "{}", lines.len());
    let long = dir.path().join("long.jsonl");
    std::fs::write(&long, lines.join("\n") + "\n").unwrap();
    let [pq, back] = ["long.parquet", "back.jsonl"].map(|n| dir.path().join(n));
    import(&long, &pq);
    import(&pq, &back);
    assert_eq!(std::fs::read(&long).unwrap(), std::fs::read(&back).unwrap());
    let (a, b) = (Session::load(&long).unwrap(), Session::load(&pq).unwrap());
    assert_eq!(a.index.transitions, b.index.transitions);
    assert_eq!(b.index.ticks(), 330 * ticks);
}

/// `sql` run by DuckDB (the PyPI package) with `$S` as the session's
/// path and `$KV` as its btx.session metadata value.
fn duckdb(session: &Path, sql: &str) {
    let script = format!(
        "import duckdb, sys\ns = sys.argv[1]\nkv = duckdb.sql(f\"select value from parquet_kv_metadata('{{s}}') where key='btx.session'\").fetchall()[0][0].decode()\nduckdb.execute({sql:?}.replace('$S', s).replace('$KV', kv))\n"
    );
    let o = std::process::Command::new(common::oracle_python())
        .arg("-c")
        .arg(script)
        .arg(session)
        .current_dir(session.parent().unwrap())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn a_session_written_again_by_duckdb_in_any_codec_reads_the_same() {
    // Only Snappy was read (#41 item 5): DuckDB, Spark and Polars write
    // zstd, gzip or LZ4 when asked; Brotli is refused with what to do.
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("s.parquet");
    let (ok, err) = run_kitting(&[], &s);
    assert!(ok, "{err}");
    let (ok, want, err) = btx(&["log", s.to_str().unwrap()]);
    assert!(ok, "{err}");
    for codec in ["zstd", "gzip", "lz4_raw", "brotli"] {
        let to = dir.path().join(format!("{codec}.parquet"));
        duckdb(
            &s,
            &format!("COPY (SELECT * FROM read_parquet('$S')) TO '{}' (FORMAT parquet, COMPRESSION {codec}, KV_METADATA {{'btx.session': '$KV'}})", to.display()),
        );
        let (ok, got, err) = btx(&["log", to.to_str().unwrap()]);
        if codec == "brotli" {
            assert!(!ok);
            assert!(
                common::one_line(&err).contains("compressed with brotli, which btx does not read (it reads Snappy, zstd, gzip and LZ4)"),
                "{err}"
            );
        } else {
            assert!(ok, "{codec}: {err}");
            assert_eq!(got, want, "{codec}");
        }
    }
}

#[test]
fn a_value_past_the_record_bound_is_refused_with_its_row() {
    // The 8 MiB bound of a JSON line was not applied to Parquet: a 1 GiB
    // decision aborted btx at 3.2 GB (#41 item 5).
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("s.parquet");
    let (ok, err) = run_kitting(&[], &s);
    assert!(ok, "{err}");
    let big = dir.path().join("big.parquet");
    duckdb(
        &s,
        &format!("COPY (SELECT * REPLACE (CASE WHEN row_number() OVER () = 5 THEN repeat('x', 9 * 1024 * 1024) ELSE decision END AS decision) FROM read_parquet('$S')) TO '{}' (FORMAT parquet, KV_METADATA {{'btx.session': '$KV'}})", big.display()),
    );
    let (ok, _, err) = btx(&["log", big.to_str().unwrap()]);
    assert!(!ok);
    let err = common::one_line(&err);
    assert!(
        err.contains("row 5: its decision is 9437184 bytes, more than a record may be (8 MiB)"),
        "{err}"
    );
}
