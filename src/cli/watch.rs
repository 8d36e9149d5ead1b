//! `btx watch`: Watch running robots (Groot2 or Groot 1 protocol), tell their faults as they happen (or print every transition), and keep their runs.

use super::printer::Printer;
use super::*;
use btx::explain::alerts::{Alert, Alerts, Row, What};
use btx::live::{groot2, Feed};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// The robots' servers, each `[HOST][:PORT]` (default 127.0.0.1:1667): a BehaviorTree.CPP 4 Groot2 server, or a BehaviorTree.CPP 3 robot's Groot 1 server (its publisher on the port below). Several are watched at once, each line prefixed with its robot.
    #[arg(value_name = "[HOST][:PORT]")]
    pub endpoints: Vec<String>,
    /// Also keep the run as a session file: `SESSION.partial` holds the run so far, SESSION the whole run once it ends (the robot's run finished, Ctrl-C or --for), as Parquet if it ends in .parquet; the robot's next run goes to `SESSION-2.jsonl`, and so on. With several robots, a directory: one session a robot's run, `HOST_PORT.jsonl`, `HOST_PORT-2.jsonl`.
    #[arg(long, value_name = "SESSION|DIR")]
    pub out: Option<PathBuf>,
    /// A BehaviorTree.CPP 3 robot's publisher port (Groot 1's protocol; Nav2 Humble's groot_zmq_publisher_port), when it is not the one below the server's.
    #[arg(long, value_name = "PORT")]
    pub publisher_port: Option<u16>,
    /// Stop after this many seconds.
    #[arg(long = "for", value_name = "SECONDS", value_parser = seconds)]
    pub for_secs: Option<f64>,
    /// Print every transition as a table (as `btx log` prints one) rather than the faults. JSON always holds every transition, and the faults among them.
    #[arg(long)]
    pub transitions: bool,
    /// Run CMD (with `sh -c`) for each fault, recovery and failed recovery, the event as JSON on its standard input and in BTX_EVENT, its line in BTX_TEXT, the robot in BTX_ROBOT. It never holds the watch up: a command that fails is said, one that runs past 10 s is killed and said.
    #[arg(long, value_name = "CMD")]
    pub on_fault: Option<String>,
    /// Stop watching a robot once its run has ended (its root back to IDLE after SUCCESS or FAILURE).
    #[arg(long)]
    pub until_end: bool,
    /// Wait at most this many seconds for a robot that is not up yet (default: until it is, Ctrl-C or --for).
    #[arg(long, value_name = "SECONDS", value_parser = seconds)]
    pub wait: Option<f64>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// What is printed of each robot.
#[derive(Clone, Copy)]
struct Say {
    format: Format,
    /// Every transition, not the faults.
    transitions: bool,
    quiet: bool,
}

/// One robot watched: its feed, and what was said of it so far.
struct Robot {
    ep: String,
    /// `[HOST:PORT] ` before each line when several robots are watched.
    prefix: String,
    feed: Feed,
    shell: btx::session::Session,
    alerts: Alerts,
    /// Faults said, and how their handling ended.
    tally: btx::explain::alerts::Tally,
    runs: usize,
    tick: u32,
    header: bool,
    gaps_said: usize,
    notes_said: usize,
    said: Option<String>,
}

impl Robot {
    fn start(
        ep: String,
        publisher: Option<u16>,
        out: Option<PathBuf>,
        several: bool,
    ) -> Result<Robot, btx::live::groot2::LiveError> {
        let mut feed = Feed::start(&ep, publisher, out)?;
        feed.print_rows();
        feed.without_view();
        // Names the nodes of the rows printed.
        let shell = feed
            .session()
            .map_err(|e| btx::live::groot2::LiveError(e.to_string()))?;
        Ok(Robot {
            prefix: if several {
                format!("[{ep}] ")
            } else {
                String::new()
            },
            ep,
            feed,
            alerts: Alerts::new(shell.tree.clone()),
            shell,
            tally: Default::default(),
            runs: 0,
            tick: 0,
            header: false,
            gaps_said: 0,
            notes_said: 0,
            said: None,
        })
    }

    /// The robot in one line: how it stands and what befell it.
    fn status(&self) -> String {
        let mut line = format!(
            "{}{} · tick {} · {} transitions",
            self.prefix,
            self.feed.glance(),
            self.tick,
            self.feed.transitions()
        );
        let t = &self.tally;
        if t.faults > 0 {
            line.push_str(&format!(
                " · {} fault{}: {} open, {} recovered, {} not",
                t.faults,
                if t.faults == 1 { "" } else { "s" },
                t.open,
                t.recovered,
                t.not_recovered
            ));
        }
        if self.runs > 0 {
            line.push_str(&format!(
                " · {} run{} ended",
                self.runs,
                if self.runs == 1 { "" } else { "s" }
            ));
        }
        line
    }

    /// Takes what came, prints its rows or its faults (unless standard
    /// output is closed) and says its gaps and notes; `done` halts the
    /// feed. The alerts said, for `--on-fault`.
    fn step(
        &mut self,
        done: bool,
        closed: bool,
        say: Say,
        pr: &mut Printer,
    ) -> Result<Vec<Alert>, Failure> {
        if done {
            self.feed.halt();
        } else {
            self.feed.poll();
        }
        let p = self.prefix.clone();
        for n in &self.feed.notes[self.notes_said..] {
            if !say.quiet {
                pr.err(format!("{p}warning: {}: {n}", self.ep));
            }
        }
        self.notes_said = self.feed.notes.len();
        // Each tick is printed once numbered: the numbers are final.
        let rows = self.feed.take_rows();
        let alerts = self.alerts_of(&rows, done);
        if !closed {
            let out = self.printed(&rows, &alerts, say);
            let rows = out.lines().count();
            pr.out(out, rows);
        }
        if let Some(e) = self.feed.write_error.take() {
            self.feed.halt();
            pr.err(format!("{p}watching stopped: the run cannot be written"));
            return Err(e.into());
        }
        for g in &self.feed.gaps[self.gaps_said..] {
            pr.err(format!("{p}gap after transition {}: {}", g.at, g.why));
        }
        self.gaps_said = self.feed.gaps.len();
        if self.feed.status.error != self.said {
            if let Some(e) = &self.feed.status.error {
                pr.err(format!("{p}{e}; connecting again"));
            }
            self.said = self.feed.status.error.clone();
        }
        Ok(alerts)
    }

    /// The faults, recoveries and ends that the rows tell, counted.
    fn alerts_of(&mut self, rows: &[btx::session::LogRow], done: bool) -> Vec<Alert> {
        let mut alerts = Vec::new();
        for r in rows {
            self.tick = r.tick;
            alerts.extend(self.alerts.push(Row {
                tick: r.tick,
                step: r.step,
                uid: r.uid,
                prev: r.prev,
                status: r.status,
                time_us: r.time_us,
            }));
        }
        // Nothing more came for now (or ever): a check's failure held for
        // the rest of its tick is decided on what came.
        if done {
            alerts.extend(self.alerts.finish());
        } else if rows.is_empty() {
            alerts.extend(self.alerts.flush());
        }
        for a in &alerts {
            self.tally.add(&self.shell.tree, a);
            self.runs += usize::from(a.what == What::RunEnded);
        }
        alerts
    }

    /// What is printed of the rows and alerts: in JSON every transition
    /// and the events among them; in text the transitions
    /// (`--transitions`) or the events.
    fn printed(&mut self, rows: &[btx::session::LogRow], alerts: &[Alert], say: Say) -> String {
        let p = &self.prefix;
        match (say.format, say.transitions) {
            (Format::Json, _) => {
                let mut out = String::new();
                if !rows.is_empty() {
                    out.push_str(&btx::export::log_json_lines(&self.shell, rows));
                }
                for a in alerts {
                    out.push_str(&alert_json(&self.shell.tree, a, None).to_string());
                    out.push('\n');
                }
                if p.is_empty() {
                    out
                } else {
                    let robot = serde_json::to_string(&self.ep).unwrap_or_default();
                    out.lines()
                        .map(|l| format!("{{\"robot\":{robot},{}\n", &l[1..]))
                        .collect()
                }
            }
            (Format::Text, true) if !rows.is_empty() => {
                let t = btx::export::log_text(&self.shell, rows);
                let body = if self.header {
                    t.split_once('\n')
                        .map_or(String::new(), |x| x.1.to_string())
                } else {
                    self.header = true;
                    t
                };
                body.lines().map(|l| format!("{p}{l}\n")).collect()
            }
            (Format::Text, true) => String::new(),
            (Format::Text, false) => alerts.iter().map(|a| format!("{p}{}\n", line(a))).collect(),
        }
    }

    /// The session finished (with --out) and what is said of the run.
    fn finish(mut self, quiet: bool, pr: &mut Printer) -> Result<(), Failure> {
        self.feed.halt();
        let p = self.prefix.clone();
        if let (false, Some(f)) = (quiet, &self.feed.status.finished) {
            pr.err(format!("{p}{f}"));
        }
        if !quiet {
            pr.err(self.status());
        }
        let n = self.feed.transitions();
        match (quiet, self.feed.latency_ms()) {
            (false, Some(Ok((median, p99)))) => pr.err(format!("{p}{n} transitions; from the robot to here: median {median:.1} ms, 99th percentile {p99:.1} ms")),
            (false, Some(Err(median))) => pr.err(format!(
                "{p}{n} transitions; from the robot to here: unknown (the robot's timestamps are {} this machine's clock)",
                clock_apart(median)
            )),
            _ => {}
        }
        let written = self.feed.stop()?;
        if !quiet {
            match &written[..] {
                [] => {}
                [(path, _)] => pr.err(format!(
                    "{p}{n} transitions written to {}",
                    btx::text::path(path)
                )),
                runs => {
                    for (k, (path, t)) in runs.iter().enumerate() {
                        pr.err(format!(
                            "{p}run {}: {t} transitions written to {}",
                            k + 1,
                            btx::text::path(path)
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

/// How far apart two clocks are, in words: "5.7 days behind".
fn clock_apart(ms: f64) -> String {
    let s = ms.abs() / 1000.0;
    let (n, unit) = if s >= 86_400.0 * 365.0 {
        (s / (86_400.0 * 365.25), "years")
    } else if s >= 86_400.0 {
        (s / 86_400.0, "days")
    } else if s >= 3600.0 {
        (s / 3600.0, "hours")
    } else {
        (s / 60.0, "minutes")
    };
    // A latency is here minus there: positive, the robot's clock is behind.
    let side = if ms > 0.0 { "behind" } else { "ahead of" };
    if n >= 1e6 {
        format!("far {side}")
    } else {
        format!("{n:.1} {unit} {side}")
    }
}

/// An alert as its line: the robot's time of day first, where known.
fn line(a: &Alert) -> String {
    match a.time_us {
        Some(t) => format!("{} UTC  {}", btx::clock::clock(t), a.text),
        None => a.text.clone(),
    }
}

/// An alert as `--format json` and `--on-fault` give it.
fn alert_json(tree: &btx::model::Tree, a: &Alert, robot: Option<&str>) -> serde_json::Value {
    let mut v = btx::export::alert_json(tree, a);
    // When btx said it, by this machine's clock: beside `time`, how soon
    // after the robot's transition.
    let now = now_us();
    v["said"] = btx::clock::rfc3339(now).into();
    v["said_us"] = now.into();
    if let Some(r) = robot {
        v["robot"] = r.into();
    }
    v
}

fn now_us() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_micros() as i64)
}

/// The robots' one-line statuses, kept in place at the foot of a
/// terminal's standard error (refreshed each second; `Printer` keeps it
/// out of the way of every other line).
struct StatusLine {
    on: bool,
    last: Instant,
}

impl StatusLine {
    fn new(quiet: bool) -> StatusLine {
        use std::io::IsTerminal;
        StatusLine {
            on: !quiet && std::io::stderr().is_terminal(),
            last: Instant::now(),
        }
    }

    fn show(&mut self, robots: &[Robot], pr: &mut Printer) {
        if !self.on || self.last.elapsed() < Duration::from_secs(1) {
            return;
        }
        self.last = Instant::now();
        let width = ratatui::crossterm::terminal::size()
            .map(|(w, _)| w as usize)
            .unwrap_or(80)
            .saturating_sub(1);
        let all: Vec<String> = robots.iter().map(Robot::status).collect();
        let text: String = all.join(" | ").chars().take(width).collect();
        pr.status(Some(text));
    }
}

/// `--on-fault`: each event goes to a thread that runs the command, so
/// that the watch never waits for it; at most `QUEUED` wait their turn,
/// and what does not fit is counted and said.
struct OnFault {
    tx: Option<std::sync::mpsc::SyncSender<(String, String, String)>>,
    /// Set once btx is done waiting: the command running is killed.
    leave: Arc<AtomicBool>,
    worker: Option<std::thread::JoinHandle<usize>>,
    dropped: usize,
}

const QUEUED: usize = 256;
const COMMAND_TIMEOUT: Duration = Duration::from_secs(10);

impl OnFault {
    fn new(cmd: Option<String>) -> OnFault {
        let Some(cmd) = cmd else {
            return OnFault {
                tx: None,
                leave: Arc::new(AtomicBool::new(false)),
                worker: None,
                dropped: 0,
            };
        };
        let (tx, rx) = std::sync::mpsc::sync_channel::<(String, String, String)>(QUEUED);
        let leave = Arc::new(AtomicBool::new(false));
        let left = Arc::clone(&leave);
        // The events not given to the command, once btx stopped waiting.
        let worker = std::thread::spawn(move || {
            let mut events = rx.into_iter();
            for (json, text, robot) in events.by_ref() {
                if left.load(Ordering::Relaxed) {
                    return 1 + events.count();
                }
                if let Err(e) = run_command(&cmd, &json, &text, &robot, &left) {
                    eprintln!("--on-fault: {e}");
                }
            }
            0
        });
        OnFault {
            tx: Some(tx),
            leave,
            worker: Some(worker),
            dropped: 0,
        }
    }

    fn send(&mut self, json: String, text: String, robot: String) {
        if let Some(tx) = &self.tx {
            if tx.try_send((json, text, robot)).is_err() {
                self.dropped += 1;
            }
        }
    }

    /// Waits for the commands queued (each bounded by its timeout).
    /// Waits for the events still queued, at most `COMMAND_TIMEOUT` once
    /// the watch is over: a command that hangs on each of them cannot hold
    /// btx's exit up for long; what is left is said.
    fn finish(mut self) {
        drop(self.tx.take());
        if let Some(w) = self.worker.take() {
            let until = Instant::now() + COMMAND_TIMEOUT + Duration::from_secs(1);
            while !w.is_finished() && Instant::now() < until {
                std::thread::sleep(Duration::from_millis(20));
            }
            if w.is_finished() {
                let _ = w.join();
            } else {
                self.leave.store(true, Ordering::Relaxed);
                let left = w.join().unwrap_or(0);
                eprintln!(
                    "--on-fault: the command was still busy {} s after the watch ended: it was stopped, and {}",
                    COMMAND_TIMEOUT.as_secs() + 1,
                    if left == 1 {
                        "the 1 event still waiting was not given to it".to_string()
                    } else {
                        format!("the {left} events still waiting were not given to it")
                    }
                );
            }
        }
        if self.dropped > 0 {
            eprintln!(
                "--on-fault: {} events came while {QUEUED} were waiting for the command, and were not given to it",
                self.dropped
            );
        }
    }
}

/// Kills a command started in its own process group, and all it started.
fn kill_group(child: &mut std::process::Child) {
    if let Ok(pid) = i32::try_from(child.id()) {
        // SAFETY: kill(2) with a negative pid signals that process group;
        // it reads and writes no memory of ours.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// Runs the command once, the event on its standard input.
fn run_command(
    cmd: &str,
    json: &str,
    text: &str,
    robot: &str,
    leave: &AtomicBool,
) -> Result<(), String> {
    use std::io::Write;
    use std::os::unix::process::CommandExt;
    // In a process group of its own, so that killing it kills what the
    // shell started too (a `sleep` left behind would hold the terminal).
    let mut child = std::process::Command::new("sh")
        .process_group(0)
        .arg("-c")
        .arg(cmd)
        .env("BTX_EVENT", json)
        .env("BTX_TEXT", text)
        .env("BTX_ROBOT", robot)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot run {cmd:?}: {e}"))?;
    if let Some(mut stdin) = child.stdin.take() {
        // A command that does not read its input is not an error.
        let _ = stdin.write_all(json.as_bytes());
        let _ = stdin.write_all(b"\n");
    }
    let started = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) if status.success() => return Ok(()),
            Ok(Some(status)) => return Err(format!("{cmd:?} failed ({status}) for: {text}")),
            Ok(None) if leave.load(Ordering::Relaxed) => {
                kill_group(&mut child);
                return Ok(());
            }
            Ok(None) if started.elapsed() >= COMMAND_TIMEOUT => {
                kill_group(&mut child);
                return Err(format!(
                    "{cmd:?} ran past {} s and was killed, for: {text}",
                    COMMAND_TIMEOUT.as_secs()
                ));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(format!("{cmd:?}: {e}")),
        }
    }
}

/// A file name for a robot's session: `HOST_PORT.jsonl`.
fn session_name(ep: &str) -> String {
    let safe: String = ep
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{safe}.jsonl")
}

/// The robots' endpoints as given (`[HOST][:PORT]`, none: the default),
/// each once, and `--out` for each: with several robots a directory of
/// one session a robot, made and claimed (`command` names the claimer).
pub(super) struct Robots {
    pub eps: Vec<String>,
    pub outs: Vec<Option<PathBuf>>,
    pub claims: Vec<btx::session::OutputLock>,
}

impl Robots {
    pub(super) fn new(
        specs: &[String],
        publisher: Option<u16>,
        out: Option<&Path>,
        command: &str,
    ) -> Result<Robots, Failure> {
        let mut eps: Vec<String> = specs.iter().map(|e| groot2::endpoint(e)).collect();
        if eps.is_empty() {
            eps.push(groot2::endpoint(""));
        }
        let mut seen = std::collections::HashSet::new();
        eps.retain(|e| seen.insert(e.clone()));
        let several = eps.len() > 1;
        if several && publisher.is_some() {
            fail!("--publisher-port names one robot's publisher; with several robots, each BehaviorTree.CPP 3 robot's publisher is the port below its server's");
        }
        let outs = outputs(&eps, out)?;
        let mut claims = Vec::new();
        for o in outs.iter().flatten() {
            claims.push(btx::session::OutputLock::take(o, command)?);
        }
        Ok(Robots { eps, outs, claims })
    }
}

/// Where each robot's session goes: `out` itself for one robot; for
/// several, `out` is a directory (made) of `HOST_PORT.jsonl`.
fn outputs(eps: &[String], out: Option<&Path>) -> Result<Vec<Option<PathBuf>>, Failure> {
    let several = eps.len() > 1;
    Ok(match (out, several) {
        (None, _) => vec![None; eps.len()],
        (Some(o), false) => vec![Some(o.to_path_buf())],
        (Some(dir), true) => {
            if dir.extension().is_some_and(|x| x == "jsonl") {
                fail!(
                    "with several robots --out names a directory (a session a robot), not {}",
                    btx::text::path(dir)
                );
            }
            std::fs::create_dir_all(dir).map_err(|e| {
                Failure::Plain(format!(
                    "{}: cannot make the directory: {e}",
                    btx::text::path(dir)
                ))
            })?;
            eps.iter()
                .map(|e| Some(dir.join(session_name(e))))
                .collect()
        }
    })
}

/// Why a robot could not be watched, without its address before it.
fn reason(ep: &str, e: &btx::live::groot2::LiveError) -> String {
    let e = e.to_string();
    e.strip_prefix(&format!("{ep}: ")).unwrap_or(&e).to_string()
}

/// A robot not up yet: tried again every `RETRY` until `--wait` ends.
struct Waiting {
    ep: String,
    out: Option<PathBuf>,
    why: String,
}

const RETRY: Duration = Duration::from_millis(500);

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Robots { eps, outs, claims } = Robots::new(
        &args.endpoints,
        args.publisher_port,
        args.out.as_deref(),
        "btx watch",
    )?;
    let say = Say {
        format: args.format,
        transitions: args.transitions,
        quiet: cli.quiet,
    };
    let mut w = Watch {
        args: &args,
        quiet: cli.quiet,
        several: eps.len() > 1,
        pr: Printer::new(args.out.is_some()),
        robots: Vec::new(),
        waiting: Vec::new(),
        failed: None,
        watched: 0,
        never_up: 0,
    };
    for (ep, out) in eps.iter().zip(outs) {
        w.start(ep, out)?;
    }
    if w.robots.is_empty() && w.waiting.is_empty() {
        fail!("no robot could be reached");
    }
    super::RECORDING.store(true, Ordering::Relaxed);
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop))
            .map_err(|e| Failure::Plain(format!("cannot catch signals: {e}")))?;
    }
    let begun = Instant::now();
    let after = |s: Option<f64>| s.map(|s| begun + Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    let (deadline, wait_until) = (after(args.for_secs), after(args.wait));
    let mut status = StatusLine::new(cli.quiet);
    let mut on_fault = OnFault::new(args.on_fault.clone());
    let mut closed_said = false;
    w.watched = w.robots.len();
    let mut tried = Instant::now();
    while !w.robots.is_empty() || !w.waiting.is_empty() {
        // A closed standard output (`| head`) ends the printing, never the
        // recording: with --out the watch goes on as it would have.
        let closed = super::stdout_closed();
        if closed && !closed_said {
            closed_said = true;
            w.say_closed(deadline.is_some());
        }
        let all_done = stop.load(Ordering::Relaxed)
            || deadline.is_some_and(|d| Instant::now() >= d)
            || (closed && args.out.is_none());
        // Robots not up yet: tried again, until they are or the wait ends.
        if all_done || wait_until.is_some_and(|u| Instant::now() >= u) {
            w.give_up(begun.elapsed().as_secs_f64());
        } else if !w.waiting.is_empty() && tried.elapsed() >= RETRY {
            tried = Instant::now();
            w.retry();
        }
        w.step(all_done, closed, say, &mut on_fault);
        status.show(&w.robots, &mut w.pr);
        // A robot with more waiting is served again at once.
        let busy = w.robots.iter().any(|r| r.feed.more);
        if !busy && (!w.robots.is_empty() || !w.waiting.is_empty()) {
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    w.end(on_fault, claims)
}

/// A watch of one robot or several: those watched, those not up yet, and
/// what its end will say.
struct Watch<'a> {
    args: &'a Args,
    quiet: bool,
    several: bool,
    pr: Printer,
    robots: Vec<Robot>,
    waiting: Vec<Waiting>,
    /// The first failure, which the exit reports.
    failed: Option<Failure>,
    /// Robots watched, at any time.
    watched: usize,
    /// Robots named that were never watched (with several).
    never_up: usize,
}

impl Watch<'_> {
    /// Starts watching `ep`: a robot not up yet is waited for; one that
    /// answers wrongly is said, and does not stop the others (with one
    /// robot, it ends the watch).
    fn start(&mut self, ep: &str, out: Option<PathBuf>) -> Result<(), Failure> {
        match Robot::start(
            ep.to_string(),
            self.args.publisher_port,
            out.clone(),
            self.several,
        ) {
            Ok(r) => {
                self.started(&r);
                self.robots.push(r);
            }
            Err(e) if e.not_up() && self.args.wait != Some(0.0) => {
                let why = reason(ep, &e);
                if !self.quiet {
                    let p = if self.several {
                        format!("[{ep}] ")
                    } else {
                        String::new()
                    };
                    self.pr
                        .err(format!("{p}waiting for {ep}: {why}; Ctrl-C stops"));
                }
                self.waiting.push(Waiting {
                    ep: ep.to_string(),
                    out,
                    why,
                });
            }
            Err(e) if self.several => {
                self.pr.err(format!("[{ep}] unreachable: {e}"));
                self.never_up += 1;
            }
            Err(e) => return Err(Failure::Plain(format!("{ep}: {}", reason(ep, &e)))),
        }
        Ok(())
    }

    fn started(&mut self, r: &Robot) {
        if !self.quiet {
            self.pr.err(format!(
                "{}watching {}: tree {} (Ctrl-C stops)",
                r.prefix, r.ep, r.feed.status.uuid
            ));
        }
    }

    /// Says once that standard output closed while the recording goes on.
    fn say_closed(&mut self, until_for: bool) {
        if let (Some(out), false) = (&self.args.out, self.quiet) {
            self.pr.err(format!(
                "standard output was closed; still recording to {} ({})",
                btx::text::path(out),
                if until_for {
                    "until --for ends"
                } else {
                    "Ctrl-C stops"
                }
            ));
        }
    }

    /// A robot that could not be watched: said, with several; with one,
    /// the watch's failure.
    fn not_watched(&mut self, ep: &str, said: String, lead: &str) {
        if self.several {
            self.pr.err(format!("[{ep}] {lead}{said}"));
            self.never_up += 1;
        } else {
            self.failed.get_or_insert(Failure::Plain(said));
        }
    }

    /// The wait is over: the robots still not up never came up.
    fn give_up(&mut self, waited: f64) {
        for w in std::mem::take(&mut self.waiting) {
            let said = format!("{}: {} (waited {waited:.1} s)", w.ep, w.why);
            self.not_watched(&w.ep, said, "never came up: ");
        }
    }

    /// Tries the robots not up yet again.
    fn retry(&mut self) {
        let mut still = Vec::new();
        for w in std::mem::take(&mut self.waiting) {
            match Robot::start(
                w.ep.clone(),
                self.args.publisher_port,
                w.out.clone(),
                self.several,
            ) {
                Ok(r) => {
                    self.started(&r);
                    self.watched += 1;
                    self.robots.push(r);
                }
                Err(e) if e.not_up() => still.push(Waiting {
                    why: reason(&w.ep, &e),
                    ..w
                }),
                Err(e) => {
                    let said = format!("{}: {}", w.ep, reason(&w.ep, &e));
                    self.not_watched(&w.ep, said, "");
                }
            }
        }
        self.waiting = still;
    }

    /// Serves each robot once: its news printed and recorded, its faults
    /// handed to `--on-fault`; a robot whose run is over (or the whole
    /// watch) ends its session.
    fn step(&mut self, all_done: bool, closed: bool, say: Say, on_fault: &mut OnFault) {
        let mut still = Vec::with_capacity(self.robots.len());
        for mut r in std::mem::take(&mut self.robots) {
            // A robot whose run finished ends its session; the others go on.
            let ended = self.args.until_end && r.runs > 0;
            let done = all_done || ended || r.feed.status.finished.is_some();
            match r.step(done, closed, say, &mut self.pr) {
                Ok(alerts) => {
                    for a in alerts.iter().filter(|a| a.what != What::RunEnded) {
                        let json = alert_json(&r.shell.tree, a, Some(&r.ep)).to_string();
                        on_fault.send(json, line(a), r.ep.clone());
                    }
                }
                Err(e) => {
                    self.failed.get_or_insert(e);
                    continue;
                }
            }
            if done {
                if let Err(e) = r.finish(self.quiet, &mut self.pr) {
                    self.failed.get_or_insert(e);
                }
            } else {
                still.push(r);
            }
        }
        self.robots = still;
    }

    /// Ends the watch, the output flushed, the commands run and the
    /// sessions' claims let go; the exit: the first failure, or that not
    /// every robot named was watched.
    fn end(self, on_fault: OnFault, claims: Vec<btx::session::OutputLock>) -> Result<(), Failure> {
        self.pr.finish();
        on_fault.finish();
        drop(claims);
        match self.failed {
            None if self.watched == 0 => fail!("no robot came up"),
            // The others were watched to the end and kept; the exit says not all were.
            None if self.never_up > 0 => fail!(
                "{} of the robots named could not be watched (each said above); the others were",
                self.never_up
            ),
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}
