//! `btx serve`: Serve a recorded run over the Groot2 protocol, as a robot that is running now.

use super::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// A session or a log (.btlog, .fbl, .db3, btcm).
    pub run: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// The port to serve on (Groot2's is 1667); on 127.0.0.1 unless --host says otherwise.
    #[arg(long, default_value_t = btx::live::groot2::DEFAULT_PORT)]
    pub port: u16,
    /// The address to listen on (0.0.0.0: every interface).
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// How many times faster than the run's tick period (100 ms a tick for a log).
    #[arg(long, default_value_t = 1.0, value_parser = positive)]
    pub speed: f64,
    /// Stop after this many seconds (default: at Ctrl-C).
    #[arg(long = "for", value_name = "SECONDS", value_parser = seconds)]
    pub for_secs: Option<f64>,
    /// Transitions kept between two reads of a client (BehaviorTree.CPP's publisher keeps 1000;
    /// btx clients are told a larger number, other clients see longer replies). At most 100000.
    #[arg(long, value_name = "N", default_value_t = btx::live::groot2::SERVER_BUFFER, value_parser = buffer)]
    pub buffer: usize,
}

/// `--buffer`: a count of transitions a client can read in one reply.
fn buffer(s: &str) -> Result<usize, String> {
    let max = btx::live::groot2::TRANSITIONS_REPLY_MAX;
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=max).contains(&n) => Ok(n),
        _ => Err(format!(
            "\"{s}\" is not a number of transitions from 1 to {max}"
        )),
    }
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let s = match btx::input::open(&args.run, &args.reading.options()?).map_err(located)? {
        Input::Session(s) => *s,
        Input::Tree { .. } => fail!(
            "{} is a tree; btx serve replays a session or a log",
            btx::text::path(&args.run)
        ),
    };
    warn_all(cli.quiet, &s.warnings);
    if !(args.speed > 0.0 && args.speed.is_finite()) {
        fail!("--speed must be a positive number, not {}", args.speed);
    }
    let listener = std::net::TcpListener::bind((args.host.as_str(), args.port))
        .map_err(|e| Failure::Plain(format!("{}:{}: cannot listen: {e}", args.host, args.port)))?;
    // With --port 0 the system picks the port: say the one it gave.
    let port = listener.local_addr().map_or(args.port, |a| a.port());
    let replay = Arc::new(btx::live::serve::Replay::new(s, args.speed).with_buffer(args.buffer));
    if !cli.quiet {
        let s = replay.session();
        eprintln!(
            "serving {} ({} transitions in {} ticks) on {}:{} with the Groot2 protocol (Ctrl-C stops)",
            btx::text::path(&args.run),
            s.index.transitions.len(),
            s.index.ticks(),
            args.host,
            port
        );
    }
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop))
            .map_err(|e| Failure::Plain(format!("cannot catch signals: {e}")))?;
    }
    if let Some(secs) = args.for_secs {
        let stop = Arc::clone(&stop);
        let until = Instant::now() + Duration::from_secs_f64(secs.clamp(0.0, 1e9));
        std::thread::spawn(move || {
            while Instant::now() < until {
                std::thread::sleep(Duration::from_millis(20));
            }
            stop.store(true, Ordering::Relaxed);
        });
    }
    let answer = {
        let replay = Arc::clone(&replay);
        Arc::new(move |parts: &[Vec<u8>]| replay.answer(parts))
    };
    // Said only when it is not BehaviorTree.CPP's, which clients assume.
    let said = args.buffer.to_string();
    let properties: Vec<(&[u8], &[u8])> = if args.buffer == btx::live::groot2::SERVER_BUFFER {
        Vec::new()
    } else {
        vec![(btx::live::groot2::BUFFER_PROPERTY, said.as_bytes())]
    };
    btx::live::rep::serve_rep(listener, answer, &properties, stop)
        .map_err(|e| Failure::Plain(format!("{}:{}: {e}", args.host, args.port)))?;
    Ok(())
}
