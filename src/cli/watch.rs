//! `btx watch`: Watch running robots (Groot2 or Groot 1 protocol) and print their transitions as they happen.

use super::*;
use btx::live::{groot2, Feed};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// The robots' servers, each `[HOST][:PORT]` (default 127.0.0.1:1667): a BehaviorTree.CPP 4 Groot2 server, or a BehaviorTree.CPP 3 robot's Groot 1 server (its publisher on the port below). Several are watched at once, each line prefixed with its robot.
    #[arg(value_name = "[HOST][:PORT]")]
    pub endpoints: Vec<String>,
    /// Also keep the run as a session file: `SESSION.partial` holds the run so far, SESSION the whole run once watching ends (Ctrl-C, --for, or the robot's run finished), as Parquet if it ends in .parquet. With several robots, a directory: one session a robot, `HOST_PORT.jsonl`.
    #[arg(long, value_name = "SESSION|DIR")]
    pub out: Option<PathBuf>,
    /// A BehaviorTree.CPP 3 robot's publisher port (Groot 1's protocol; Nav2 Humble's groot_zmq_publisher_port), when it is not the one below the server's.
    #[arg(long, value_name = "PORT")]
    pub publisher_port: Option<u16>,
    /// Stop after this many seconds.
    #[arg(long = "for", value_name = "SECONDS", value_parser = seconds)]
    pub for_secs: Option<f64>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// One robot watched: its feed, and what was said of it so far.
struct Robot {
    ep: String,
    /// `[HOST:PORT] ` before each line when several robots are watched.
    prefix: String,
    feed: Feed,
    shell: btx::session::Session,
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
    ) -> Result<Robot, String> {
        let mut feed = Feed::start(&ep, publisher, out).map_err(|e| e.to_string())?;
        feed.print_rows();
        feed.without_view();
        // Names the nodes of the rows printed.
        let shell = feed.session().map_err(|e| e.to_string())?;
        Ok(Robot {
            prefix: if several {
                format!("[{ep}] ")
            } else {
                String::new()
            },
            ep,
            feed,
            shell,
            header: false,
            gaps_said: 0,
            notes_said: 0,
            said: None,
        })
    }

    /// Takes what came, prints its rows (unless standard output is
    /// closed) and says its gaps and notes; `done` halts the feed.
    fn step(
        &mut self,
        done: bool,
        closed: bool,
        format: Format,
        quiet: bool,
    ) -> Result<(), Failure> {
        if done {
            self.feed.halt();
        } else {
            self.feed.poll();
        }
        let p = &self.prefix;
        for n in &self.feed.notes[self.notes_said..] {
            if !quiet {
                eprintln!("{p}warning: {}: {n}", self.ep);
            }
        }
        self.notes_said = self.feed.notes.len();
        // Each tick is printed once numbered: the numbers are final.
        let rows = self.feed.take_rows();
        if !closed && !rows.is_empty() {
            let out = match format {
                Format::Json => {
                    let lines = btx::export::log_json_lines(&self.shell, &rows);
                    if p.is_empty() {
                        lines
                    } else {
                        let robot = serde_json::to_string(&self.ep).unwrap_or_default();
                        lines
                            .lines()
                            .map(|l| format!("{{\"robot\":{robot},{}\n", &l[1..]))
                            .collect()
                    }
                }
                Format::Text => {
                    let t = btx::export::log_text(&self.shell, &rows);
                    let body = if self.header {
                        t.split_once('\n')
                            .map_or(String::new(), |x| x.1.to_string())
                    } else {
                        self.header = true;
                        t
                    };
                    body.lines().map(|l| format!("{p}{l}\n")).collect()
                }
            };
            print!("{out}");
        }
        if let Some(e) = self.feed.write_error.take() {
            self.feed.halt();
            eprintln!("{p}watching stopped: the run cannot be written");
            return Err(e.into());
        }
        for g in &self.feed.gaps[self.gaps_said..] {
            eprintln!("{p}gap after transition {}: {}", g.at, g.why);
        }
        self.gaps_said = self.feed.gaps.len();
        if self.feed.status.error != self.said {
            if let Some(e) = &self.feed.status.error {
                eprintln!("{p}{e}; connecting again");
            }
            self.said = self.feed.status.error.clone();
        }
        Ok(())
    }

    /// The session finished (with --out) and what is said of the run.
    fn finish(mut self, quiet: bool) -> Result<(), Failure> {
        self.feed.halt();
        let p = &self.prefix;
        if let (false, Some(f)) = (quiet, &self.feed.status.finished) {
            eprintln!("{p}{f}");
        }
        let n = self.feed.transitions();
        if let (false, Some((median, p99))) = (quiet, self.feed.latency_ms()) {
            eprintln!("{p}{n} transitions; from the robot to here: median {median:.1} ms, 99th percentile {p99:.1} ms");
        }
        if let Some(path) = self.feed.stop()? {
            if !quiet {
                eprintln!("{p}{n} transitions written to {}", path.display());
            }
        }
        Ok(())
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
                    dir.display()
                );
            }
            std::fs::create_dir_all(dir).map_err(|e| {
                Failure::Plain(format!("{}: cannot make the directory: {e}", dir.display()))
            })?;
            eps.iter()
                .map(|e| Some(dir.join(session_name(e))))
                .collect()
        }
    })
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Robots { eps, outs, claims } = Robots::new(
        &args.endpoints,
        args.publisher_port,
        args.out.as_deref(),
        "btx watch",
    )?;
    let several = eps.len() > 1;
    let mut robots = Vec::new();
    for (ep, out) in eps.iter().zip(outs) {
        match Robot::start(ep.clone(), args.publisher_port, out, several) {
            Ok(r) => {
                if !cli.quiet {
                    eprintln!(
                        "{}watching {ep}: tree {} (Ctrl-C stops)",
                        r.prefix, r.feed.status.uuid
                    );
                }
                robots.push(r);
            }
            // One robot that cannot be reached does not stop the others.
            Err(e) if several => eprintln!("[{ep}] unreachable: {e}"),
            Err(e) => return Err(Failure::Plain(e)),
        }
    }
    if robots.is_empty() {
        fail!("no robot could be reached");
    }
    super::RECORDING.store(true, Ordering::Relaxed);
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop))
            .map_err(|e| Failure::Plain(format!("cannot catch signals: {e}")))?;
    }
    let deadline = args
        .for_secs
        .map(|s| Instant::now() + Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    let mut closed_said = false;
    let mut failed = None;
    while !robots.is_empty() {
        // A closed standard output (`| head`) ends the printing, never the
        // recording: with --out the watch goes on as it would have.
        let closed = super::stdout_closed();
        if closed && !closed_said {
            closed_said = true;
            if let (Some(out), false) = (&args.out, cli.quiet) {
                eprintln!(
                    "standard output was closed; still recording to {} ({})",
                    out.display(),
                    if deadline.is_some() {
                        "until --for ends"
                    } else {
                        "Ctrl-C stops"
                    }
                );
            }
        }
        let all_done = stop.load(Ordering::Relaxed)
            || deadline.is_some_and(|d| Instant::now() >= d)
            || (closed && args.out.is_none());
        let mut still = Vec::with_capacity(robots.len());
        for mut r in robots {
            // A robot whose run finished ends its session; the others go on.
            let done = all_done || r.feed.status.finished.is_some();
            if let Err(e) = r.step(done, closed, args.format, cli.quiet) {
                failed.get_or_insert(e);
                continue;
            }
            if done {
                if let Err(e) = r.finish(cli.quiet) {
                    failed.get_or_insert(e);
                }
            } else {
                still.push(r);
            }
        }
        robots = still;
        if !robots.is_empty() {
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    drop(claims);
    match failed {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
