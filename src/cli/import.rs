//! `btx import`: a log into a btx session file, or a session into the other format.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    pub log: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// The session file to write (never overwritten): JSON lines, or Parquet if it ends in .parquet. A btx session given as LOG is converted record for record.
    #[arg(long, value_name = "SESSION")]
    pub out: PathBuf,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args { log, reading, out } = args;
    let _claim = btx::session::OutputLock::take(&out, "btx import")?;
    if btx::logs::rosbag::is_bag(&log) && reading.run.is_none() {
        return import_runs(&log, &reading, &out, cli);
    }
    if reading.run_tree.is_none() && btx::session::read::format_of(&log).is_some() {
        let (path, s) = btx::session::copy::copy(&log, &out).map_err(located)?;
        warn_all(cli.quiet, &s.warnings);
        return say_written(&path, &s);
    }
    let s = match open_input(&log, &reading, cli.quiet)? {
        Input::Session(s) => *s,
        Input::Tree { .. } => fail!("{} is a tree, not a log", log.display()),
    };
    let path = btx::logs::write_session(&s, &out)?;
    say_written(&path, &s)
}

fn say_written(path: &Path, s: &btx::session::Session) -> Result<(), Failure> {
    eprintln!(
        "{}: {} ticks, {} transitions",
        path.display(),
        s.index.ticks(),
        s.index.transitions.len()
    );
    Ok(())
}

/// A rosbag: one session a run (goal), `OUT/run-N.jsonl`.
fn import_runs(log: &Path, reading: &Reading, out: &Path, cli: &Globals) -> Result<(), Failure> {
    std::fs::create_dir_all(out).map_err(|e| {
        Failure::Plain(format!("{}: cannot make the directory: {e}", out.display()))
    })?;
    btx::input::each_run(log, &reading.options()?, |k, _, s| {
        if k == 1 {
            warn_all(cli.quiet, &s.warnings);
        }
        let path =
            btx::logs::write_session(&s, &out.join(format!("run-{k}.jsonl"))).map_err(Box::new)?;
        eprintln!(
            "{}: {} ticks, {} transitions, {}",
            path.display(),
            s.index.ticks(),
            s.index.transitions.len(),
            s.ending()
        );
        Ok(())
    })?;
    Ok(())
}
