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

/// The packages the differential and live tests run: the real
/// BehaviorTree.CPP (Python bindings of 4.8) and btview, a Groot2 client
/// nobody here wrote; rosbags, which writes Nav2's bags; DuckDB, which
/// reads the fleet's Parquet export.
const ORACLE_PACKAGES: [&str; 4] = [
    "behaviortreepy==0.1.4",
    "btview==0.2.0",
    "rosbags==0.11.9",
    "duckdb==2.0.1",
];

/// The Python that has BehaviorTree.CPP (the PyPI package behaviortreepy)
/// and btview: `BTX_ORACLE_PYTHON`, or a virtual environment this makes the
/// first time a test needs it, once per target directory. A machine that
/// cannot make it fails the test with what to install; nothing skips.
pub fn oracle_python() -> PathBuf {
    if let Some(p) = std::env::var_os("BTX_ORACLE_PYTHON") {
        return PathBuf::from(p);
    }
    static VENV: std::sync::OnceLock<Result<PathBuf, String>> = std::sync::OnceLock::new();
    match VENV.get_or_init(oracle_venv) {
        Ok(python) => python.clone(),
        Err(why) => panic!("{why}"),
    }
}

/// `target/oracle-venv`, made under an exclusive lock: test binaries run
/// at once, and the second must wait for the first's venv, not race it.
fn oracle_venv() -> Result<PathBuf, String> {
    use std::io::Write;
    use std::os::fd::AsRawFd;
    let target = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("CARGO_TARGET_TMPDIR is inside the target directory");
    let venv = target.join("oracle-venv");
    let python = venv.join("bin/python");
    let marker = venv.join("btx-packages.txt");
    let wanted = ORACLE_PACKAGES.join("\n");
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(target.join("oracle-venv.lock"))
        .map_err(|e| format!("cannot open {}/oracle-venv.lock: {e}", target.display()))?;
    // SAFETY: flock on a descriptor this function owns; it is released when
    // `lock` is dropped.
    if unsafe { libc::flock(lock.as_raw_fd(), libc::LOCK_EX) } != 0 {
        return Err(format!("cannot lock {}/oracle-venv.lock", target.display()));
    }
    if python.exists() && std::fs::read_to_string(&marker).is_ok_and(|m| m == wanted) {
        return Ok(python);
    }
    // Written past the test harness's capture: a first run pauses here for
    // a minute, and should say why.
    let _ = writeln!(
        std::io::stderr(),
        "btx tests: setting up the BehaviorTree.CPP oracle in {} (python3 -m venv, then pip install {}); once per target directory",
        venv.display(),
        ORACLE_PACKAGES.join(" ")
    );
    let _ = std::fs::remove_dir_all(&venv);
    let made = std::process::Command::new("python3")
        .args(["-m", "venv"])
        .arg(&venv)
        .output();
    match made {
        Ok(o) if o.status.success() => {}
        Ok(o) => {
            return Err(format!(
                "the tests that run the real BehaviorTree.CPP need Python 3 with venv: `python3 -m venv` failed ({}). On Debian or Ubuntu: apt-get install python3-venv. Or set BTX_ORACLE_PYTHON to a Python that has {}.",
                String::from_utf8_lossy(&o.stderr).trim(),
                ORACLE_PACKAGES.join(" and ")
            ))
        }
        Err(e) => {
            return Err(format!(
                "the tests that run the real BehaviorTree.CPP need Python 3 (python3 on PATH: {e}). On Debian or Ubuntu: apt-get install python3 python3-venv."
            ))
        }
    }
    let pip = std::process::Command::new(&python)
        .args([
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
        ])
        .args(ORACLE_PACKAGES)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    if !pip.status.success() {
        return Err(format!(
            "pip could not install {} into {}: the tests that run the real BehaviorTree.CPP need access to PyPI (or BTX_ORACLE_PYTHON naming a Python that has them).\n{}",
            ORACLE_PACKAGES.join(" "),
            venv.display(),
            String::from_utf8_lossy(&pip.stderr).trim()
        ));
    }
    std::fs::write(&marker, &wanted).map_err(|e| format!("{}: {e}", marker.display()))?;
    let _ = writeln!(std::io::stderr(), "btx tests: the oracle is ready");
    Ok(python)
}

/// Runs a Nav2 navigator (a path, or a name in the corpus) with its era's
/// models file and a plan (a path, or a name in `tests/fixtures/plans`),
/// into `out`.
pub fn run_nav2(navigator: impl AsRef<Path>, plan: impl AsRef<Path>, out: &Path) {
    let nav = fixture("realworld/nav2").join(navigator.as_ref());
    let plan = fixture("plans").join(plan.as_ref());
    let models = nav2_models_for(&nav);
    let (ok, _, err) = btx(&[
        "-q",
        "run",
        nav.to_str().unwrap(),
        "--models",
        models.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{}: {err}", nav.display());
}

/// The shipped kitting sessions (`sessions/kitting-*.jsonl`, relative to the
/// project, in name order), then the real BehaviorTree.CPP 4.10 log of
/// look at chuck failing once: a small fleet.
pub fn kitting_fleet() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions"))
            .unwrap()
            .map(|e| Path::new("sessions").join(e.unwrap().file_name()))
            .filter(|p| {
                p.file_name()
                    .unwrap()
                    .to_str()
                    .unwrap()
                    .starts_with("kitting-")
            })
            .collect();
    paths.sort();
    paths.push("tests/fixtures/logs/kitting_lookat_fails_once.btlog".into());
    paths
}

/// A tree run by btx on a plan (40 ticks at most), with a models file if
/// given; `None` when the tree or the plan is refused.
pub fn planned(xml: &str, plan: &str, models: Option<&Path>) -> Option<btx::session::Session> {
    let mut opts = LoadOptions::default();
    if let Some(m) = models {
        opts.models = vec![m.to_path_buf()];
    }
    let l = btx::xml::load_str(Path::new("case.xml"), xml, &opts).ok()?;
    let plan = btx::run::plan::Plan::parse(Path::new("case.plan"), plan).ok()?;
    let leaves = btx::run::plan::PlanLeaves::new(plan.clone(), &l.tree);
    let source = btx::session::Source {
        kind: "plan".into(),
        path: None,
        text: Some(plan.text),
        name: None,
    };
    btx::session::record::simulate(
        &l.tree,
        source,
        None,
        40,
        btx::run::RunOptions::default(),
        leaves,
    )
    .ok()
}

/// How a child ended: its exit code (`None`: a signal), its raw wait
/// status, and its peak memory in KiB.
pub struct Ended {
    pub code: Option<i32>,
    pub status: i32,
    pub peak_kib: i64,
}

/// Waits for `child` and reads its own rusage through wait4: per child,
/// even with tests running in parallel.
pub fn wait_peak(child: std::process::Child) -> Ended {
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: rusage is plain data, and `pid` is our unwaited child.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let got = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(got, pid, "wait4: {}", std::io::Error::last_os_error());
    // Waited for already: its handle must not wait again.
    std::mem::forget(child);
    Ended {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        status,
        peak_kib: usage.ru_maxrss,
    }
}

/// An error as one line: miette wraps its messages at the terminal's width.
pub fn one_line(err: &str) -> String {
    err.lines()
        .map(|l| l.trim_start_matches([' ', '│', '×']).trim_end())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The recorded kitting run (`tests/fixtures/logs/kitting_lookat_fails_once.btlog`)
/// `times` over as one `.btlog`, each copy later than the last.
pub fn long_btlog(times: u64) -> Vec<u8> {
    let bytes = std::fs::read(fixture("logs/kitting_lookat_fails_once.btlog")).unwrap();
    let n = i32::from_le_bytes(bytes[19..23].try_into().unwrap()) as usize;
    let (head, body) = bytes.split_at(31 + n);
    let dt = |r: &[u8]| u64::from_le_bytes([&r[..6], &[0, 0][..]].concat().try_into().unwrap());
    let span = dt(&body[body.len() - 9..]) + 100_000;
    let mut out = head.to_vec();
    for k in 0..times {
        for r in body.chunks_exact(9) {
            out.extend_from_slice(&(dt(r) + k * span).to_le_bytes()[..6]);
            out.extend_from_slice(&r[6..]);
        }
    }
    out
}
