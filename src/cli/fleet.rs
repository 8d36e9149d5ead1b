//! `btx fleet`: a fleet's runs answered at once.

use super::*;
use std::sync::atomic::{AtomicBool, Ordering};

#[derive(clap::Args)]
pub struct Args {
    /// The runs: sessions, logs and rosbags, directories of them (searched for .jsonl and .parquet sessions, .btlog, .fbl, .db3 and .mcap files), or glob patterns ('runs/*.btlog').
    #[arg(required = true, value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    #[command(flatten)]
    pub reading: Reading,
    #[command(flatten)]
    pub explorer: Explorer,
    /// Also compare each run with this one, subgoal by subgoal (as `btx diff REF RUN...`).
    #[arg(long, value_name = "RUN")]
    pub reference: Option<PathBuf>,
    /// Also write the runs, their nodes and their transitions as Parquet tables under DIR (runs/, nodes/, transitions/, partitioned by robot and day), for DuckDB, Spark, Trino or DataFusion. DIR must be new or empty.
    #[arg(long, value_name = "DIR")]
    pub export: Option<PathBuf>,
    /// Show the fleet in the terminal: the failures as bars, RUNNING times, the runs on a time axis; Enter on a run opens it in the explorer.
    #[arg(long, conflicts_with = "format")]
    pub open: bool,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let opts = args.reading.options()?;
    let files = btx::fleet::files(&expand(&args.paths)?).map_err(located)?;
    if files.is_empty() {
        fail!("no run files found in {}", shown(&args.paths));
    }
    let reference = match &args.reference {
        Some(r) => match open_input(r, &args.reading, cli.quiet)? {
            Input::Session(s) => Some(s),
            Input::Tree { .. } => fail!("--reference: {} is a tree, not a run", btx::text::path(r)),
        },
        None => None,
    };
    if let Some(dir) = &args.export {
        btx::fleet::export::create(dir).map_err(located)?;
    }
    let bar = Progress::new(files.len() as u64, cli.quiet);
    let fleet = btx::fleet::Fleet::read(
        &files,
        &opts,
        reference.as_deref(),
        args.export.as_deref(),
        &|| bar.tick(),
    );
    bar.finish();
    if !fleet.unwritten.is_empty() {
        fail!("the export is incomplete:\n{}", fleet.unwritten.join("\n"));
    }
    if fleet.runs.is_empty() {
        let why: Vec<String> = fleet
            .errors
            .iter()
            .map(|(f, e)| format!("{f}: {e}"))
            .collect();
        fail!("no run could be read:\n{}", why.join("\n"));
    }
    if args.open {
        let mut app = btx::tui::fleet::FleetApp::new(fleet, opts);
        app.keymap = keymap(cli.keys.as_deref())?;
        return btx::tui::run_with(&mut app, cli.ascii)
            .map_err(|e| Failure::Plain(format!("the terminal: {e}")));
    }
    match args.format {
        Format::Text => print!("{}", btx::text::visible(&fleet.text())),
        Format::Json => print!("{}", pretty(&fleet.json())),
    }
    Ok(())
}

/// The paths given, a pattern (`*`, `?`, `[`) that names no file expanded
/// as the shell would (for a shell that did not, or a quoted pattern).
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>, Failure> {
    let mut out = Vec::new();
    for p in paths {
        let s = p.to_string_lossy();
        if p.exists() || !s.contains(['*', '?', '[']) {
            out.push(p.clone());
            continue;
        }
        let matched = glob::glob(&s).map_err(|e| Failure::Plain(format!("{s}: {e}")))?;
        let before = out.len();
        out.extend(matched.filter_map(Result::ok));
        if out.len() == before {
            fail!("{s}: no file matches this pattern");
        }
    }
    Ok(out)
}

fn shown(paths: &[PathBuf]) -> String {
    let v: Vec<String> = paths
        .iter()
        .map(|p| btx::text::path(p).to_string())
        .collect();
    v.join(", ")
}

/// A progress bar on stderr, drawn once the reading has taken a second and
/// only on a terminal (indicatif draws nothing elsewhere).
struct Progress {
    bar: indicatif::ProgressBar,
    started: std::time::Instant,
    shown: AtomicBool,
    quiet: bool,
}

impl Progress {
    fn new(files: u64, quiet: bool) -> Progress {
        let bar = indicatif::ProgressBar::with_draw_target(
            Some(files),
            indicatif::ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "reading runs {bar:30} {pos}/{len} files, {elapsed} ({eta} left)",
            )
            .expect("a valid template"),
        );
        Progress {
            bar,
            started: std::time::Instant::now(),
            shown: AtomicBool::new(false),
            quiet,
        }
    }

    fn tick(&self) {
        self.bar.inc(1);
        if !self.quiet
            && self.started.elapsed() > std::time::Duration::from_secs(1)
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar
                .set_draw_target(indicatif::ProgressDrawTarget::stderr());
        }
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
