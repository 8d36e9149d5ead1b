//! `btx watch`: Watch a running robot over the Groot2 protocol and print its transitions as they happen.

use super::*;
use btx::live::{groot2, uuid_text, Watch};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// The robot's Groot2 server, `[HOST][:PORT]` (default 127.0.0.1:1667).
    #[arg(value_name = "[HOST][:PORT]")]
    pub endpoint: Option<String>,
    /// Also keep the run as a session file, written when watching ends (Ctrl-C, or --for).
    #[arg(long, value_name = "SESSION")]
    pub out: Option<PathBuf>,
    /// Stop after this many seconds.
    #[arg(long = "for", value_name = "SECONDS")]
    pub for_secs: Option<f64>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// How often the server's buffer is emptied: at 10,000 transitions a
/// second, 100 of its 1,000 places.
const POLL: Duration = Duration::from_millis(10);
/// How often the table grows on screen.
const PRINT: Duration = Duration::from_millis(100);

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let ep = groot2::endpoint(args.endpoint.as_deref().unwrap_or(""));
    if let Some(out) = &args.out {
        if out.exists() {
            fail!(
                "{}: a file is here already; --out names a new session file",
                out.display()
            );
        }
    }
    let mut w = Watch::start(&ep).map_err(|e| Failure::Plain(e.to_string()))?;
    if !cli.quiet {
        eprintln!("watching {ep}: tree {} (Ctrl-C stops)", uuid_text(&w.uuid));
    }
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop))
            .map_err(|e| Failure::Plain(format!("cannot catch signals: {e}")))?;
    }
    let deadline = args
        .for_secs
        .map(|s| Instant::now() + Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    let (mut printed, mut seen, mut gaps_said) = (0usize, 0usize, 0usize);
    let mut header = false;
    let mut last_print = Instant::now();
    loop {
        let done = stop.load(Ordering::Relaxed) || deadline.is_some_and(|d| Instant::now() >= d);
        if let Err(e) = w.poll() {
            eprintln!("{e}; connecting again");
            std::thread::sleep(Duration::from_millis(500));
        }
        if (done || last_print.elapsed() >= PRINT) && w.records.len() > seen {
            last_print = Instant::now();
            seen = w.records.len();
            let s = w.session()?;
            super::log::print_grown(&s, None, false, args.format, &mut printed, &mut header);
        }
        for g in &w.gaps[gaps_said..] {
            eprintln!("gap after transition {}: {}", g.at, g.why);
        }
        gaps_said = w.gaps.len();
        if done {
            break;
        }
        std::thread::sleep(POLL);
    }
    if let Some(out) = &args.out {
        let s = w.session()?;
        let path = btx::logs::write_session(&s, out)?;
        if !cli.quiet {
            eprintln!(
                "{} transitions in {} ticks written to {}",
                s.index.transitions.len(),
                s.index.ticks(),
                path.display()
            );
        }
    }
    Ok(())
}
