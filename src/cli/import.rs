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
