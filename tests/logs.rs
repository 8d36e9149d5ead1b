//! Logs robots already write, opened as sessions: `.btlog` files of the
//! recorded runs, with their ticks reconstructed exactly.

mod common;
use btx::explain::{answer, Question};
use btx::session::Moment;
use common::*;

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
    for run in [
        "taxi_nominal",
        "kitting_nominal",
        "kitting_lookat_fails_once",
        "kitting_detect_chuck_always_fails",
        "kitting_grasp_check_fails_first",
    ] {
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
    for run in [
        "taxi_nominal_v3",
        "kitting_nominal_v3",
        "kitting_lookat_fails_once_v3",
        "kitting_detect_chuck_always_fails_v3",
        "kitting_grasp_check_fails_first_v3",
    ] {
        assert_same_run(&open_fbl(run), run);
    }
}
