//! The real binary in a real terminal (tmux): open the demo, press keys,
//! read the screen, quit, and check the terminal came back.

mod common;

use std::process::Command;
use std::time::{Duration, Instant};

struct Tmux(String);

impl Tmux {
    fn run(&self, args: &[&str]) -> String {
        let out = Command::new("tmux")
            .arg("-L")
            .arg(&self.0)
            .args(args)
            .output()
            .expect("tmux runs");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Runs `cmd` in a detached 110×34 session named `btx`.
    fn start(&self, cmd: &str) {
        self.run(&[
            "new-session",
            "-d",
            "-s",
            "btx",
            "-x",
            "110",
            "-y",
            "34",
            cmd,
        ]);
    }

    /// `alternate-screen mouse cursor` as tmux sees the pane: `1 1 0` while
    /// the explorer runs, `0 0 1` once the terminal is given back.
    fn terminal(&self) -> String {
        self.run(&[
            "display",
            "-p",
            "-t",
            "btx",
            "#{alternate_on} #{mouse_any_flag} #{cursor_flag}",
        ])
        .trim()
        .to_string()
    }

    fn screen(&self) -> String {
        self.run(&["capture-pane", "-p", "-t", "btx"])
    }

    /// Waits until the screen shows `text`.
    fn wait_for(&self, text: &str) -> String {
        let start = Instant::now();
        loop {
            let s = self.screen();
            if s.contains(text) {
                return s;
            }
            if start.elapsed() > Duration::from_secs(20) {
                panic!("the screen never showed {text:?}:\n{s}");
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .arg("-L")
            .arg(&self.0)
            .arg("kill-server")
            .output();
    }
}

/// Whether tmux is here; under CI it must be (.ci/run installs it), so a
/// missing tmux fails the run instead of passing by skipping.
fn tmux_here() -> bool {
    let here = Command::new("tmux").arg("-V").output().is_ok();
    if !here {
        assert!(
            std::env::var_os("CI").is_none(),
            "tmux is missing under CI: the terminal tests cannot run"
        );
        eprintln!("tmux is not installed; .ci/run installs it");
    }
    here
}

#[test]
fn every_signal_restores_the_terminal() {
    if !tmux_here() {
        return;
    }
    for (sig, n) in [("TERM", 15), ("HUP", 1), ("INT", 2), ("QUIT", 3)] {
        let t = Tmux(format!("btx-sig{sig}-{}", std::process::id()));
        let dir = tempfile::tempdir().unwrap();
        let pidfile = dir.path().join("pid");
        let cmd = format!(
            "{} & echo $! > {}; wait $!; echo EXITED:$?; sleep 30",
            env!("CARGO_BIN_EXE_btx"),
            pidfile.display()
        );
        t.start(&cmd);
        t.wait_for("moment 1 ");
        // The explorer has the alternate screen and mouse reporting on.
        let on = t.run(&[
            "display",
            "-p",
            "-t",
            "btx",
            "#{alternate_on} #{mouse_any_flag}",
        ]);
        assert_eq!(on.trim(), "1 1", "SIG{sig}: before");
        let pid = std::fs::read_to_string(&pidfile).unwrap();
        Command::new("kill")
            .arg(format!("-{sig}"))
            .arg(pid.trim())
            .status()
            .unwrap();
        let s = t.wait_for("EXITED:");
        assert!(s.contains(&format!("EXITED:{}", 128 + n)), "SIG{sig}: {s}");
        assert_eq!(t.terminal(), "0 0 1", "SIG{sig}: the terminal after: {s}");
    }
}

#[test]
fn demo_in_a_real_terminal() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-e2e-{}", std::process::id()));
    let cmd = format!("{}; echo EXITED:$?; sleep 30", env!("CARGO_BIN_EXE_btx"));
    t.start(&cmd);
    // The frame may be captured half drawn: wait for its last pane too.
    t.wait_for("full tree");
    t.wait_for("moment 1 ");
    t.run(&["send-keys", "-t", "btx", "f"]);
    t.wait_for("moment 10 ");
    t.run(&["send-keys", "-t", "btx", "?"]);
    t.wait_for("keys and signs (↑↓ scroll, ? or Esc to close)");
    t.run(&["send-keys", "-t", "btx", "Escape"]);
    t.run(&["send-keys", "-t", "btx", "q"]);
    let s = t.wait_for("EXITED:0");
    assert!(
        !s.contains("full tree"),
        "the alternate screen was left: {s}"
    );
}

/// `btx FILE` opens FILE in the explorer, as `btx open FILE` does.
#[test]
fn a_file_given_alone_opens_in_the_explorer() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-e2e-file-{}", std::process::id()));
    let cmd = format!(
        "cd {} && {} --ascii sessions/kitting-lookat-fails-once.jsonl; echo EXITED:$?; sleep 30",
        env!("CARGO_MANIFEST_DIR"),
        env!("CARGO_BIN_EXE_btx")
    );
    t.start(&cmd);
    t.wait_for("kitting-lookat-fails-once.jsonl");
    let s = t.wait_for("moment 1 ");
    assert!(
        !s.contains('┏'),
        "--ascii before the file is the explorer's: {s}"
    );
    t.run(&["send-keys", "-t", "btx", "q"]);
    t.wait_for("EXITED:0");
}

#[test]
fn side_by_side_diff_in_a_real_terminal() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-e2e-diff-{}", std::process::id()));
    let cmd = format!(
        "cd {} && {} open --diff sessions/taxi-expected.jsonl sessions/taxi.jsonl; echo EXITED:$?; sleep 30",
        env!("CARGO_MANIFEST_DIR"),
        env!("CARGO_BIN_EXE_btx")
    );
    t.start(&cmd);
    t.wait_for("edit distance 4, LCS 10 in all");
    t.wait_for("A: moment 1 ");
    t.run(&["send-keys", "-t", "btx", "d"]);
    t.wait_for("divergence 1 of 4 (the runs part ways here): go pick up passenger");
    t.run(&["send-keys", "-t", "btx", "N"]);
    t.wait_for("A: moment 4 ");
    // A key the diff has no use for says so.
    t.run(&["send-keys", "-t", "btx", "f"]);
    t.wait_for("is not in the side-by-side diff");
    t.run(&["send-keys", "-t", "btx", "q"]);
    let s = t.wait_for("EXITED:0");
    assert!(
        !s.contains("edit distance"),
        "the alternate screen was left: {s}"
    );
}

#[test]
fn ctrl_z_suspends_and_fg_redraws() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-suspend-{}", std::process::id()));
    t.start("bash --norc --noprofile -i");
    t.run(&["send-keys", "-t", "btx", "PS1='$ '", "Enter"]);
    let cmd = format!(
        "{} open sessions/kitting-nominal.jsonl",
        env!("CARGO_BIN_EXE_btx")
    );
    t.run(&[
        "send-keys",
        "-t",
        "btx",
        &format!("cd {}", env!("CARGO_MANIFEST_DIR")),
        "Enter",
    ]);
    t.run(&["send-keys", "-t", "btx", &cmd, "Enter"]);
    t.wait_for("moment 1 ");
    t.run(&["send-keys", "-t", "btx", "C-z"]);
    let s = t.wait_for("Stopped");
    // The shell has the terminal back, as it was.
    assert_eq!(t.terminal(), "0 0 1", "{s}");
    t.run(&["send-keys", "-t", "btx", "fg", "Enter"]);
    t.wait_for("moment 1 ");
    assert!(t.terminal().starts_with("1 1"), "{}", t.terminal());
    t.run(&["send-keys", "-t", "btx", "q"]);
    // The shell has the terminal once btx is gone: keys sent before that
    // are btx's (a loaded CI read "echo …" as keys of the explorer).
    let start = Instant::now();
    while t.terminal() != "0 0 1" {
        assert!(start.elapsed() < Duration::from_secs(20), "{}", t.screen());
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_millis(200));
    // fg's status is btx's.
    t.run(&["send-keys", "-t", "btx", "echo EXITED:$?", "Enter"]);
    let s = t.wait_for("EXITED:0");
    assert_eq!(t.terminal(), "0 0 1", "{s}");
}

#[test]
fn a_panic_gives_the_terminal_back_and_says_why() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-panic-{}", std::process::id()));
    let cmd = format!(
        "BTX_CRASH_AFTER_DRAW=1 {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx")
    );
    t.start(&cmd);
    let s = t.wait_for("EXITED:");
    assert!(s.contains("EXITED:101"), "{s}");
    assert!(
        s.contains("crashing on purpose"),
        "the panic is reported: {s}"
    );
    assert!(
        !s.contains("full tree"),
        "the alternate screen was left: {s}"
    );
    assert_eq!(t.terminal(), "0 0 1", "the terminal after: {s}");
}

#[test]
fn an_abort_gives_the_terminal_back() {
    // An abort (exhausted memory) runs no panic hook: `open --live` left
    // the terminal in the alternate screen and raw mode (#26 item 4).
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-abort-{}", std::process::id()));
    let cmd = format!(
        "BTX_ABORT_AFTER_DRAW=1 {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx")
    );
    t.start(&cmd);
    let s = t.wait_for("EXITED:");
    assert!(
        s.contains("EXITED:134"),
        "killed by SIGABRT, as before: {s}"
    );
    assert!(
        !s.contains("full tree"),
        "the alternate screen was left: {s}"
    );
    assert_eq!(t.terminal(), "0 0 1", "the terminal after: {s}");
}

#[test]
fn why_on_a_run_stopped_by_an_unknown_control_node_answers_in_the_terminal() {
    // Was a panic (src/session/index.rs:278) that left mouse reporting on.
    if !tmux_here() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("t.xml");
    let plan = dir.path().join("t.plan");
    let out = dir.path().join("s.jsonl");
    std::fs::write(
        &tree,
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><MyControl><a name="a"/><b name="b"/></MyControl></BehaviorTree></root>"#,
    )
    .unwrap();
    std::fs::write(&plan, "a = S\nb = S\n").unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["run", tree.to_str().unwrap(), "--plan"])
        .arg(&plan)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(1), "the run stops with an error");
    let t = Tmux(format!("btx-unknown-{}", std::process::id()));
    t.start(&format!(
        "{} open {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx"),
        out.display()
    ));
    t.wait_for("run stopped at tick 1 by an error");
    t.run(&["send-keys", "-t", "btx", "w"]);
    // The status line says why there is nothing to ask.
    let s = t.wait_for("replaying tick 1");
    assert!(s.contains("full tree"), "{s}");
    t.run(&["send-keys", "-t", "btx", "Escape"]);
    t.run(&["send-keys", "-t", "btx", "q"]);
    let s = t.wait_for("EXITED:");
    assert!(s.contains("EXITED:0"), "{s}");
    assert_eq!(t.terminal(), "0 0 1", "the terminal after: {s}");
}

/// A key as tmux's `send-keys` names it (`None`: typed as text).
fn tmux_key(name: &str) -> Option<String> {
    Some(match name {
        "Esc" => "Escape".into(),
        "Backspace" => "BSpace".into(),
        "PageUp" => "PPage".into(),
        "PageDown" => "NPage".into(),
        "Up" | "Down" | "Left" | "Right" | "Enter" | "Tab" | "Home" | "End" | "Space" => {
            name.into()
        }
        n if n.starts_with("Ctrl-") => format!("C-{}", &n[5..]),
        _ => return None,
    })
}

#[test]
fn every_key_of_the_keymap_in_a_real_terminal() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-keys-{}", std::process::id()));
    t.start(&format!(
        "{}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx")
    ));
    t.wait_for("moment 1 ");
    let km = btx::tui::keymap::Keymap::default();
    let mut pressed = 0;
    for (keys, action, _, _) in &km.keys {
        if *action == btx::tui::keymap::Action::Quit {
            continue;
        }
        for k in keys {
            match tmux_key(k) {
                Some(name) => t.run(&["send-keys", "-t", "btx", &name]),
                None => t.run(&["send-keys", "-t", "btx", "-l", k]),
            };
            // Whatever the key opened (a list, a prompt, the help) closes.
            t.run(&["send-keys", "-t", "btx", "Escape"]);
            std::thread::sleep(Duration::from_millis(100));
            let s = t.screen();
            assert!(
                !s.contains("EXITED:"),
                "{action:?} ({k}) ended the explorer: {s}"
            );
            pressed += 1;
        }
    }
    assert!(pressed >= 30, "{pressed}");
    // A key that cannot act says why in the real terminal's status bar
    // (every key in every mode: tests/tui.rs, through the same event path).
    t.run(&["send-keys", "-t", "btx", "Escape"]);
    t.wait_for("nothing to close (q quits)");
    // Still drawing, and it gives the terminal back on quit.
    t.run(&["send-keys", "-t", "btx", "q"]);
    let s = t.wait_for("EXITED:");
    assert!(s.contains("EXITED:0"), "{s}");
    assert_eq!(t.terminal(), "0 0 1", "the terminal after: {s}");
}

#[test]
fn the_explorer_on_a_live_robot_grows_steps_back_and_keeps_the_run() {
    if !tmux_here() {
        return;
    }
    use std::io::{BufRead, BufReader};
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().port()
    };
    let dir = tempfile::tempdir().unwrap();
    let btlog = dir.path().join("robot.btlog");
    let out = dir.path().join("live.jsonl");
    let mut robot = Command::new(common::oracle_python())
        .arg(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/live/robot.py"))
        .arg(common::fixture("kitting-tree.v4.xml"))
        .arg(common::fixture("plans/kitting_lookat_fails_once.plan"))
        .arg(port.to_string())
        .arg(&btlog)
        .args(["100", "stdin"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("the robot starts");
    let mut lines = BufReader::new(robot.stdout.take().unwrap()).lines();
    assert_eq!(lines.next().unwrap().unwrap(), "READY");
    let t = Tmux(format!("btx-live-{}", std::process::id()));
    t.start(&format!(
        "{} open --live :{port} --out {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx"),
        out.display()
    ));
    t.wait_for(&format!("live 127.0.0.1:{port}"));
    t.wait_for("connected");
    // Before the robot's first tick: said, not "tick 1 of 0".
    let s = t.wait_for("waiting for the robot's first tick");
    assert!(!s.contains("tick 1 of 0"), "{s}");
    {
        use std::io::Write;
        writeln!(robot.stdin.as_mut().unwrap(), "go").unwrap();
    }
    // The failure at tick 10 has happened: step back to it while it runs.
    let start = Instant::now();
    loop {
        let s = t.screen();
        // "tick N of M" in the timeline.
        let tick = s.split("tick ").skip(1).find_map(|x| {
            let (n, rest) = x.split_once(' ')?;
            rest.starts_with("of ").then(|| n.parse::<u32>().ok())?
        });
        if tick.is_some_and(|n| n >= 12) {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(20), "{s}");
        std::thread::sleep(Duration::from_millis(50));
    }
    // The details pane shows the robot's blackboard of the selected
    // node's scope, read from it (`B`); these leaves write none.
    let s = t.wait_for("(no entries)");
    assert_eq!(s.matches("(no entries)").count(), 1, "shown once: {s}");
    t.run(&["send-keys", "-t", "btx", "F"]);
    let s = t.wait_for("transitions behind live");
    assert!(s.contains("moment 10 "), "{s}");
    // Asked there while the robot runs on: the run recorded the failure.
    t.run(&["send-keys", "-t", "btx", "a"]);
    t.wait_for("What went wrong?");
    for _ in 0..7 {
        t.run(&["send-keys", "-t", "btx", "Down"]);
    }
    t.run(&["send-keys", "-t", "btx", "Enter"]);
    let s = t.wait_for("at chuck failed.");
    assert!(
        s.contains("I could not insert large gear because look"),
        "{s}"
    );
    // Back to the present from the ask pane, which has the focus (End
    // scrolled the answer there), following the robot to its run's end.
    t.run(&["send-keys", "-t", "btx", "End"]);
    t.wait_for("tick 54 of 54");
    // Quitting at tick 54's first transition would keep a run stopped
    // there (a busy machine showed it); the robot says when it is done.
    let s = t.wait_for("run finished");
    // The robot is gone: nobody is being asked.
    if s.contains("the robot closed the connection") {
        std::thread::sleep(Duration::from_millis(500));
        assert!(!t.screen().contains("asking the robot"), "{}", t.screen());
    }
    t.run(&["send-keys", "-t", "btx", "q"]);
    let s = t.wait_for("EXITED:");
    assert!(s.contains("EXITED:0"), "{s}");
    assert_eq!(t.terminal(), "0 0 1", "the terminal after: {s}");
    let _ = robot.wait();
    let (ok, a, _) = common::btx(&["log", out.to_str().unwrap()]);
    assert!(ok);
    let (ok, b, _) = common::btx(&["log", btlog.to_str().unwrap()]);
    assert!(ok);
    // BehaviorTree.CPP 4.8's publisher can zero records it is sent while
    // it answers (a race a loaded machine meets); btx says each such gap
    // with its count. What it kept is then the logged run less exactly
    // those, in order.
    let kept = btx::session::Session::load(&out).unwrap();
    let lost: usize = kept
        .index
        .gaps
        .iter()
        .filter_map(|(_, why)| why.split("the server sent ").nth(1))
        .filter_map(|w| w.split(' ').next()?.parse::<usize>().ok())
        .sum();
    if lost > 0 {
        let logged = match btx::input::open(&btlog, &Default::default()).unwrap() {
            btx::input::Input::Session(s) => s,
            _ => panic!("the robot's log is a run"),
        };
        let key = |t: &btx::session::Transition| (t.uid, t.status);
        let (l, k) = (&logged.index.transitions, &kept.index.transitions);
        assert_eq!(k.len() + lost, l.len(), "{a}");
        let mut it = l.iter().map(key);
        assert!(k.iter().map(key).all(|t| it.any(|x| x == t)), "{a}");
        return;
    }
    if a != b {
        let d = similar::TextDiff::from_lines(&b, &a);
        panic!(
            "the run kept is not the run the robot logged:\n{}",
            d.unified_diff().context_radius(2).header("logged", "kept")
        );
    }
}

/// `btx serve RUN` on a free port, once it listens: the child and the port.
fn serving(run: &str, speed: &str) -> (std::process::Child, u16) {
    let port = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().port()
    };
    let child = Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(["-q", "serve", run, "--port", &port.to_string()])
        .args(["--speed", speed, "--for", "60"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .spawn()
        .unwrap();
    let start = Instant::now();
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(start.elapsed() < Duration::from_secs(10), "never listened");
        std::thread::sleep(Duration::from_millis(20));
    }
    (child, port)
}

#[test]
fn several_robots_in_the_explorer_are_picked_with_r_and_each_kept() {
    if !tmux_here() {
        return;
    }
    let (mut a, pa) = serving("sessions/kitting-lookat-fails-once.jsonl", "1");
    let (mut b, pb) = serving("sessions/serial-recall.jsonl", "1");
    // A third that nothing serves: said, and the others watched.
    let pc = {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().port()
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fleet");
    let t = Tmux(format!("btx-robots-{}", std::process::id()));
    t.start(&format!(
        "{} open --live :{pa} :{pb} :{pc} --out {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx"),
        out.display()
    ));
    t.wait_for(&format!("full tree · live 127.0.0.1:{pa}"));
    t.run(&["send-keys", "-t", "btx", "R"]);
    let s = t.wait_for("robots · Enter shows one");
    assert!(s.contains(&format!("▸ 127.0.0.1:{pa}  ")), "{s}");
    assert!(s.contains(&format!("  127.0.0.1:{pb}  ")), "{s}");
    assert!(s.contains(&format!("127.0.0.1:{pc}  unreachable (")), "{s}");
    // Each robot's state at a glance, and how much of its run came.
    assert!(s.contains(" transitions · no gap"), "{s}");
    t.run(&["send-keys", "-t", "btx", "Down", "Enter"]);
    t.wait_for(&format!("full tree · live 127.0.0.1:{pb}"));
    // The unreachable one cannot be shown: said.
    t.run(&["send-keys", "-t", "btx", "R", "Down", "Enter"]);
    t.wait_for("could not be reached when the explorer opened");
    // Both runs are watched to their end while one is shown (`btx serve`
    // stays up after its run: the root is IDLE after succeeding).
    let start = Instant::now();
    loop {
        t.run(&["send-keys", "-t", "btx", "R"]);
        let s = t.wait_for("robots · Enter shows one");
        if s.matches("idle after succeeding").count() == 2 {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(20), "{s}");
        t.run(&["send-keys", "-t", "btx", "Escape"]);
        std::thread::sleep(Duration::from_millis(300));
    }
    // Esc then q apart: together a terminal reads them as Alt-q.
    t.run(&["send-keys", "-t", "btx", "Escape"]);
    std::thread::sleep(Duration::from_millis(300));
    t.run(&["send-keys", "-t", "btx", "q"]);
    let s = t.wait_for("EXITED:");
    assert!(s.contains("EXITED:0"), "{s}");
    let _ = (a.kill(), b.kill());
    for (port, run) in [
        (pa, "sessions/kitting-lookat-fails-once.jsonl"),
        (pb, "sessions/serial-recall.jsonl"),
    ] {
        // Transition for transition, tick for tick (the protocol carries
        // no decisions, so `btx log`'s last column differs).
        let kept = btx::session::Session::load(&out.join(format!("127.0.0.1_{port}.jsonl")));
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let served = btx::session::Session::load(&root.join(run)).unwrap();
        assert_eq!(
            kept.unwrap().index.transitions,
            served.index.transitions,
            "{run}"
        );
    }
}

#[test]
fn every_prompt_takes_text_in_a_real_terminal() {
    if !tmux_here() {
        return;
    }
    let t = Tmux(format!("btx-prompts-{}", std::process::id()));
    t.start(&format!(
        "cd {} && {} open sessions/kitting-lookat-fails-once.jsonl; echo EXITED:$?; sleep 30",
        env!("CARGO_MANIFEST_DIR"),
        env!("CARGO_BIN_EXE_btx")
    ));
    t.wait_for("full tree");
    let keys = |ks: &[&str]| {
        t.run(&[&["send-keys", "-t", "btx"][..], ks].concat());
        std::thread::sleep(Duration::from_millis(150));
    };
    // The finder: typing, ← and a letter where the cursor is.
    keys(&["/"]);
    keys(&["-l", "chuk"]);
    keys(&["Left"]);
    keys(&["-l", "c"]);
    t.wait_for("find: chuc▏k");
    keys(&["C-u"]);
    t.wait_for("find: ▏k");
    keys(&["Escape"]);
    // "Can you …?", the last of the questions.
    keys(&["a"]);
    t.wait_for("Can you …?");
    for _ in 0..30 {
        keys(&["Down"]);
    }
    keys(&["Enter"]);
    keys(&["-l", "pick"]);
    t.wait_for("Can you pick▏?");
    keys(&["C-w"]);
    t.wait_for("Can you ▏?");
    keys(&["Escape"]);
    // The timeline's filter.
    keys(&["Tab"]);
    keys(&["/"]);
    keys(&["-l", "look"]);
    t.wait_for("look▏");
    keys(&["Enter"]);
    keys(&["q"]);
    let s = t.wait_for("EXITED:");
    assert!(s.contains("EXITED:0"), "{s}");
}

#[test]
fn a_long_log_shows_at_once_and_then_whole_and_one_broken_further_on_says_where() {
    if !tmux_here() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join("long.btlog");
    let mut bytes = common::long_btlog(600);
    std::fs::write(&long, &bytes).unwrap();
    let t = Tmux(format!("btx-e2e-long-{}", std::process::id()));
    t.start(&format!(
        "{} --ascii {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx"),
        long.display()
    ));
    // The whole comes without a key pressed: the screen is drawn again.
    t.wait_for("transition 6 of 148800 ");
    t.run(&["send-keys", "-t", "btx", "q"]);
    t.wait_for("EXITED:0");
    drop(t);

    let n = i32::from_le_bytes(bytes[19..23].try_into().unwrap()) as usize;
    let at = 31 + n + 9 * 100_000 + 8;
    bytes[at] = 9;
    let broken = dir.path().join("broken.btlog");
    std::fs::write(&broken, &bytes).unwrap();
    let t = Tmux(format!("btx-e2e-broken-{}", std::process::id()));
    t.start(&format!(
        "{} --ascii {}; echo EXITED:$?; sleep 30",
        env!("CARGO_BIN_EXE_btx"),
        broken.display()
    ));
    // A long path may wrap the message at the screen's edge.
    let s = t.wait_for("EXITED:1").replace('\n', "");
    assert!(
        s.contains(&format!("byte offset {at}: status byte 9 is not a status")),
        "{s}"
    );
    assert_eq!(t.terminal(), "0 0 1", "the terminal is given back");
}
