//! The README's command examples are tests: every `$ btx …` line in a
//! ```` ```console ```` block is run (through `sh`, so pipes work), in
//! order, in a scratch copy of the project's trees, sessions and fixtures,
//! and what it prints (stdout and stderr) must be the lines under it. A
//! line `...` stands for any lines, and durations (`0.17 s`) are not
//! compared. The explorer (`btx open`) is drawn, not
//! printed, and is left out.

use std::path::Path;
use std::process::Command;

struct Example {
    line: usize,
    command: String,
    expected: Vec<String>,
}

fn examples(readme: &str) -> Vec<Example> {
    let mut out: Vec<Example> = Vec::new();
    let mut inside = false;
    for (i, l) in readme.lines().enumerate() {
        if l.starts_with("```") {
            inside = l == "```console";
            continue;
        }
        if !inside {
            continue;
        }
        match l.strip_prefix("$ ") {
            Some(cmd) => out.push(Example {
                line: i + 1,
                command: cmd.to_string(),
                expected: Vec::new(),
            }),
            None => {
                if let Some(e) = out.last_mut() {
                    e.expected.push(l.trim_end().to_string());
                }
            }
        }
    }
    out
}

/// A line with its durations (`0.17 s`) as `T s`: how long a command took
/// is not what an example shows.
fn timeless(line: &str) -> String {
    let words: Vec<&str> = line.split(' ').collect();
    let mut out = Vec::with_capacity(words.len());
    for (i, w) in words.iter().enumerate() {
        let number = !w.is_empty() && w.chars().all(|c| c.is_ascii_digit() || c == '.');
        let unit = words
            .get(i + 1)
            .is_some_and(|n| *n == "s" || n.starts_with("s,") || n.starts_with("s)"));
        out.push(if number && w.contains('.') && unit {
            "T"
        } else {
            w
        });
    }
    out.join(" ").trim_end().to_string()
}

/// Whether `got` reads as `want`, where a `...` line in `want` matches any
/// number of lines.
fn matches(want: &[String], got: &[&str]) -> bool {
    match want.split_first() {
        None => got.is_empty(),
        Some((w, rest)) if w.trim() == "..." => (0..=got.len()).any(|k| matches(rest, &got[k..])),
        Some((w, rest)) => got
            .split_first()
            .is_some_and(|(g, more)| timeless(g) == timeless(w) && matches(rest, more)),
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn every_readme_example_prints_what_the_readme_says() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for d in ["trees", "sessions", "tests/fixtures"] {
        copy_dir(&root.join(d), &dir.path().join(d));
    }
    // The logs the import examples name, as a robot leaves them.
    for e in std::fs::read_dir(root.join("tests/fixtures/logs")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.path().join(p.file_name().unwrap())).unwrap();
    }
    let bin = Path::new(env!("CARGO_BIN_EXE_btx")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let all = examples(&readme);
    assert!(all.len() > 30, "{} examples", all.len());
    let mut failed = Vec::new();
    for e in &all {
        if e.command.starts_with("btx open") || e.command.starts_with("btx --ascii open") {
            continue;
        }
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!("{} 2>&1", e.command))
            .current_dir(dir.path())
            .env("PATH", &path)
            .env("NO_COLOR", "1")
            .env("COLUMNS", "100")
            .output()
            .unwrap();
        let got = String::from_utf8_lossy(&out.stdout).into_owned();
        let lines: Vec<&str> = got.lines().collect();
        if !matches(&e.expected, &lines) {
            failed.push(format!(
                "README.md:{}: $ {}\n--- the README says\n{}\n--- btx printed\n{}",
                e.line,
                e.command,
                e.expected.join("\n"),
                got.trim_end()
            ));
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {} examples drifted:\n\n{}",
        failed.len(),
        all.len(),
        failed.join("\n\n")
    );
}

#[test]
fn the_ellipsis_matches_any_lines() {
    let w = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert!(matches(&w(&["a", "...", "d"]), &["a", "b", "c", "d"]));
    assert!(matches(&w(&["a", "...", "d"]), &["a", "d"]));
    assert!(!matches(&w(&["a", "d"]), &["a", "b", "d"]));
    assert!(!matches(&w(&["a"]), &["a", "b"]));
    assert!(matches(
        &w(&["200 comparisons in 0.54 s (2 threads)"]),
        &["200 comparisons in 1.57 s (2 threads)"]
    ));
    assert!(!matches(&w(&["200 comparisons"]), &["201 comparisons"]));
}
