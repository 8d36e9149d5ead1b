//! The README and the guide in `docs/` are tests. Every `$ btx …` line in
//! a ```` ```console ```` block is run (through `sh`, so pipes work), page
//! by page in order, each page in its own scratch copy of the project's
//! trees, sessions and fixtures, and what it prints (stdout and stderr)
//! must be the lines under it. A line `...` stands for any lines, and
//! durations (`0.17 s`) are not compared. The explorer (`btx open`) is
//! drawn, not printed, and is left out. Every link between the pages
//! resolves, headings included; the README stays short and its set-up is
//! the two commands CI runs.

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

/// README.md, then every page of `docs/`, by name: (path from the
/// project's root, text).
fn pages() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    names.sort();
    names.insert(0, "README.md".to_string());
    names
        .into_iter()
        .map(|n| {
            let text = std::fs::read_to_string(root.join(&n)).unwrap();
            (n, text)
        })
        .collect()
}

/// A scratch copy of what the examples read, as a user's checkout has it.
fn scratch() -> tempfile::TempDir {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    for d in ["trees", "sessions", "tests/fixtures"] {
        copy_dir(&root.join(d), &dir.path().join(d));
    }
    // Nothing else: every example runs from the project root as written
    // (#27 item 9: the logs were copied beside them, where a user has none).
    dir
}

/// Runs a page's examples in order in a scratch directory of its own: the
/// drifted ones, as messages.
fn drifted(page: &str, text: &str, path: &str) -> (usize, Vec<String>) {
    let dir = scratch();
    let all = examples(text);
    let mut failed = Vec::new();
    for e in &all {
        if e.command.starts_with("btx open") || e.command.starts_with("btx --ascii open") {
            continue;
        }
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!("{} 2>&1", e.command))
            .current_dir(dir.path())
            .env("PATH", path)
            .env("NO_COLOR", "1")
            .env("COLUMNS", "100")
            .output()
            .unwrap();
        let got = String::from_utf8_lossy(&out.stdout).into_owned();
        let lines: Vec<&str> = got.lines().collect();
        if !matches(&e.expected, &lines) {
            failed.push(format!(
                "{page}:{}: $ {}\n--- the page says\n{}\n--- btx printed\n{}",
                e.line,
                e.command,
                e.expected.join("\n"),
                got.trim_end()
            ));
        }
    }
    (all.len(), failed)
}

#[test]
fn every_example_prints_what_its_page_says() {
    let bin = Path::new(env!("CARGO_BIN_EXE_btx")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut count = 0;
    let mut failed = Vec::new();
    for (page, text) in pages() {
        let (n, f) = drifted(&page, &text, &path);
        count += n;
        failed.extend(f);
    }
    assert!(count > 30, "{count} examples");
    assert!(
        failed.is_empty(),
        "{} of {} examples drifted:\n\n{}",
        failed.len(),
        count,
        failed.join("\n\n")
    );
}

/// GitHub's anchor for a heading: lower case, punctuation dropped but `-`
/// and `_`, spaces as `-`.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a page's headings (a repeated one gets `-1`, `-2`, …).
fn anchors(text: &str) -> Vec<String> {
    let mut seen: Vec<String> = Vec::new();
    let mut fence = false;
    for l in text.lines() {
        if l.starts_with("```") {
            fence = !fence;
        }
        if fence || !l.starts_with('#') {
            continue;
        }
        let base = slug(l.trim_start_matches('#'));
        let n = seen
            .iter()
            .filter(|s| **s == base || s.starts_with(&format!("{base}-")))
            .count();
        seen.push(if n == 0 { base } else { format!("{base}-{n}") });
    }
    seen
}

/// The targets of a page's links, outside code: `(line, target)`.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fence = false;
    for (i, l) in text.lines().enumerate() {
        if l.starts_with("```") || l.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        // Inline code may hold `](` that is no link.
        let prose: String = l.split('`').step_by(2).collect::<Vec<_>>().join("");
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((i + 1, after[..end].to_string()));
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn no_page_points_outside_the_repository() {
    // A user of the repository has no ../shared (#27 item 9).
    for (page, text) in pages() {
        for (i, line) in text.lines().enumerate() {
            assert!(!line.contains("../shared"), "{page}:{}: {line}", i + 1);
        }
    }
}

#[test]
fn every_link_between_the_pages_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut broken = Vec::new();
    let mut checked = 0;
    for (page, text) in pages() {
        let dir = Path::new(&page).parent().unwrap().to_path_buf();
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let (file, anchor) = match target.split_once('#') {
                Some((f, a)) => (f, Some(a)),
                None => (target.as_str(), None),
            };
            let file = if file.is_empty() {
                root.join(&page)
            } else {
                root.join(&dir).join(file)
            };
            let Ok(file) = file.canonicalize() else {
                broken.push(format!("{page}:{line}: {target}: no such file"));
                continue;
            };
            if let Some(a) = anchor {
                let target_text = std::fs::read_to_string(&file).unwrap_or_default();
                if !anchors(&target_text).iter().any(|h| h == a) {
                    broken.push(format!(
                        "{page}:{line}: {target}: no heading has that anchor"
                    ));
                }
            }
        }
    }
    assert!(checked > 20, "only {checked} links");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn anchors_are_github_s() {
    assert_eq!(slug(" `btx why`"), "btx-why");
    assert_eq!(
        slug(" Han's questions: how each answer is worded"),
        "hans-questions-how-each-answer-is-worded"
    );
    assert_eq!(anchors("# A\n## A\n```\n# A\n```\n"), ["a", "a-1"]);
    assert_eq!(
        links("see [x](a.md#b) and `[y](no)`\n```\n[z](no)\n```\n"),
        [(1, "a.md#b".to_string())]
    );
}

#[test]
fn the_readme_is_a_front_page_and_each_guide_page_says_what_it_is_for() {
    let all = pages();
    let readme = &all[0].1;
    let n = readme.lines().count();
    assert!(
        n <= 200,
        "README.md has {n} lines; the rest belongs in docs/"
    );
    for (page, text) in &all[1..] {
        let first = text.lines().find(|l| !l.is_empty() && !l.starts_with('#'));
        assert!(
            first.is_some_and(|l| l.starts_with("What this page is for")),
            "{page} does not start with what it is for: {first:?}"
        );
        assert!(
            readme.contains(&format!("]({page})")),
            "the README's table does not link {page}"
        );
    }
}

/// The lines of the README's set-up section that are commands (in a
/// ```` ```sh ```` block, comments and blank lines aside).
fn setup_commands(readme: &str) -> Vec<String> {
    let section: Vec<&str> = readme
        .lines()
        .skip_while(|l| *l != "## Set-up")
        .skip(1)
        .take_while(|l| !l.starts_with("## "))
        .collect();
    let mut out = Vec::new();
    let mut inside = false;
    for l in section {
        if l.starts_with("```") {
            inside = l == "```sh";
            continue;
        }
        let cmd = l.split('#').next().unwrap().trim();
        if inside && !cmd.is_empty() {
            out.push(cmd.to_string());
        }
    }
    out
}

#[test]
fn the_set_up_is_two_commands_and_ci_runs_the_second() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let commands = setup_commands(&readme);
    assert_eq!(commands, ["cargo run --release", "cargo test --locked"]);
    let ci = std::fs::read_to_string(root.join(".ci/run")).unwrap();
    let steps: Vec<&str> = ci
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("cargo "))
        .collect();
    assert_eq!(
        steps,
        [
            "cargo fmt --check",
            "cargo clippy --all-targets --locked -- -D warnings",
            commands[1].as_str()
        ],
        "CI runs the README's test command after fmt and clippy, and no other cargo step"
    );
    assert!(
        !ci.contains("setup.sh"),
        "CI sets up nothing the README does not name"
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
