#![allow(dead_code)]

use btx::xml::{load_file, LoadOptions};
use btx::Tree;
use std::path::{Path, PathBuf};

pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

pub fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("trees")
        .join(name)
}

/// The Nav2 navigators of the corpus (tests/fixtures/realworld/nav2), in
/// name order, without the model files.
pub fn nav2_navigators() -> Vec<PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(fixture("realworld/nav2"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| !p.to_string_lossy().contains("tree_nodes"))
        .collect();
    files.sort();
    files
}

/// The model file of a Nav2 navigator's era, as the corpus's SOURCES says:
/// humble's for a file without BTCPP_format="4", main's for the others.
pub fn nav2_models_for(navigator: &Path) -> PathBuf {
    let v4 = std::fs::read_to_string(navigator)
        .unwrap()
        .contains(r#"BTCPP_format="4""#);
    fixture("realworld/nav2").join(if v4 {
        "nav2_tree_nodes.main.xml"
    } else {
        "nav2_tree_nodes.f875f62.xml"
    })
}

pub fn load(path: &Path) -> Tree {
    match load_file(path, &LoadOptions::default()) {
        Ok(l) => l.tree,
        Err(e) => panic!("{e}"),
    }
}

pub fn uid_of(tree: &Tree, pick: &str) -> btx::Uid {
    btx::pick::pick(tree, pick).unwrap_or_else(|e| panic!("{e}"))
}

/// The (tick, uid, previous status, status) rows of `tests/fixtures/runs/RUN.txt`.
pub fn logged(run: &str) -> Vec<(u32, u32, String, String)> {
    std::fs::read_to_string(fixture(&format!("runs/{run}.txt")))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[2].to_string(),
                f[3].to_string(),
            )
        })
        .collect()
}

/// Runs the btx binary in the project's folder: (success, stdout, stderr).
pub fn btx(args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// Writes `xml` and `plan` into `dir` and runs `btx run` on them: whether it
/// succeeded, its stderr, and the session it was to write.
#[allow(dead_code)]
pub fn run_planned(
    dir: &std::path::Path,
    xml: &str,
    plan: &str,
) -> (bool, String, std::path::PathBuf) {
    let tree = dir.join("t.xml");
    std::fs::write(&tree, xml).unwrap();
    let plan_file = dir.join("p.plan");
    std::fs::write(&plan_file, plan).unwrap();
    let out = dir.join("s.jsonl");
    let (ok, _, err) = btx(&[
        "run",
        tree.to_str().unwrap(),
        "--plan",
        plan_file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    (ok, err, out)
}

/// The Python that has BehaviorTree.CPP (the PyPI package behaviortreepy):
/// `tests/oracle/setup.sh` installs it; a missing one fails the test.
pub fn oracle_python() -> PathBuf {
    if let Some(p) = std::env::var_os("BTX_ORACLE_PYTHON") {
        return PathBuf::from(p);
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/oracle-venv/bin/python");
    assert!(
        p.exists(),
        "the BehaviorTree.CPP oracle is not installed: run tests/oracle/setup.sh (or set BTX_ORACLE_PYTHON)"
    );
    p
}
