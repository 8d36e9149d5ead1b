//! `btx import`: Convert a log (BehaviorTree.CPP .btlog, .db3 or .fbl, or a btcm log) into a btx session file.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    pub log: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    #[arg(long, value_name = "SESSION")]
    pub out: PathBuf,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args { log, reading, out } = args;
    let _claim = btx::session::OutputLock::take(&out, "btx import")?;
    if btx::logs::rosbag::is_bag(&log) && reading.run.is_none() {
        return import_runs(&log, &reading, &out, cli);
    }
    let s = match open_input(&log, &reading, cli.quiet)? {
        Input::Session(s) => *s,
        Input::Tree { .. } => fail!("{} is a tree, not a log", log.display()),
    };
    let path = btx::logs::write_session(&s, &out)?;
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
