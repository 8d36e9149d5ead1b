//! `btx watch`: Watch a running robot over the Groot2 protocol and print its transitions as they happen.

use super::*;
use btx::live::{groot2, Feed};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// The robot's Groot2 server, `[HOST][:PORT]` (default 127.0.0.1:1667).
    #[arg(value_name = "[HOST][:PORT]")]
    pub endpoint: Option<String>,
    /// Also keep the run as a session file: `SESSION.partial` holds the run so far (rewritten as the run grows, at most every 20 ms), SESSION the whole run once watching ends (Ctrl-C, or --for).
    #[arg(long, value_name = "SESSION")]
    pub out: Option<PathBuf>,
    /// Stop after this many seconds.
    #[arg(long = "for", value_name = "SECONDS", value_parser = seconds)]
    pub for_secs: Option<f64>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let ep = groot2::endpoint(args.endpoint.as_deref().unwrap_or(""));
    let _claim = match &args.out {
        Some(out) => Some(btx::session::OutputLock::take(out, "btx watch")?),
        None => None,
    };
    let mut feed = Feed::start(&ep, args.out.clone()).map_err(|e| Failure::Plain(e.to_string()))?;
    if !cli.quiet {
        eprintln!("watching {ep}: tree {} (Ctrl-C stops)", feed.status.uuid);
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
    feed.print_rows();
    feed.without_view();
    // Names the nodes of the rows printed.
    let shell = feed.session()?;
    let mut header = false;
    let mut gaps_said = 0usize;
    let mut notes_said = 0usize;
    let mut said: Option<String> = None;
    let mut closed_said = false;
    loop {
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
        let done = stop.load(Ordering::Relaxed)
            || feed.status.finished.is_some()
            || deadline.is_some_and(|d| Instant::now() >= d)
            || (closed && args.out.is_none());
        if done {
            feed.halt();
        } else {
            feed.poll();
        }
        for n in &feed.notes[notes_said..] {
            if !cli.quiet {
                eprintln!("warning: {ep}: {n}");
            }
        }
        notes_said = feed.notes.len();
        // Each tick is printed once numbered: the numbers are final.
        let rows = feed.take_rows();
        if !closed && !rows.is_empty() {
            let out = match args.format {
                Format::Json => btx::export::log_json_lines(&shell, &rows),
                Format::Text => {
                    let t = btx::export::log_text(&shell, &rows);
                    if header {
                        t.split_once('\n')
                            .map_or(String::new(), |x| x.1.to_string())
                    } else {
                        header = true;
                        t
                    }
                }
            };
            print!("{out}");
        }
        if let Some(e) = feed.write_error.take() {
            feed.halt();
            eprintln!("watching stopped: the run cannot be written");
            return Err(e.into());
        }
        for g in &feed.gaps[gaps_said..] {
            eprintln!("gap after transition {}: {}", g.at, g.why);
        }
        gaps_said = feed.gaps.len();
        if feed.status.error != said {
            if let Some(e) = &feed.status.error {
                eprintln!("{e}; connecting again");
            }
            said = feed.status.error.clone();
        }
        if done {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    if let (false, Some(f)) = (cli.quiet, &feed.status.finished) {
        eprintln!("{f}");
    }
    let n = feed.transitions();
    if let (false, Some((median, p99))) = (cli.quiet, feed.latency_ms()) {
        eprintln!("{n} transitions; from the robot to here: median {median:.1} ms, 99th percentile {p99:.1} ms");
    }
    if let Some(path) = feed.stop()? {
        if !cli.quiet {
            eprintln!("{n} transitions written to {}", path.display());
        }
    }
    Ok(())
}
