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
        Input::Tree { .. } => fail!("{} is a tree, not a log", btx::text::path(&log)),
    };
    let path = btx::logs::write_session(&s, &out)?;
    say_written(&path, &s)
}

fn say_written(path: &Path, s: &btx::session::Session) -> Result<(), Failure> {
    eprintln!(
        "{}: {} ticks, {} transitions",
        btx::text::path(path),
        s.index.ticks(),
        s.index.transitions.len()
    );
    Ok(())
}

/// A rosbag: one session a run (goal), `OUT/run-N.jsonl`; a bag of several
/// robots' logs, each robot's in a directory named by its namespace
/// (`/robot2/behavior_tree_log`: `OUT/robot2/run-N.jsonl`; the root
/// namespace's: `OUT/root/`).
fn import_runs(log: &Path, reading: &Reading, out: &Path, cli: &Globals) -> Result<(), Failure> {
    let mkdir = |d: &Path| {
        std::fs::create_dir_all(d).map_err(|e| {
            Box::new(btx::source::Located::file(
                d,
                format!("cannot make the directory: {e}"),
            ))
        })
    };
    mkdir(out).map_err(|e| located(*e))?;
    let mut warned = false;
    btx::input::each_robot_run(log, &reading.options()?, |topic, k, _, s| {
        if !warned {
            warn_all(cli.quiet, &s.warnings);
            warned = true;
        }
        let dir = match topic {
            Some(t) => {
                let ns = btx::logs::rosbag::namespace(t);
                let name = if ns.is_empty() {
                    "root".to_string()
                } else {
                    ns.replace('/', ".")
                };
                let dir = out.join(name);
                mkdir(&dir)?;
                dir
            }
            None => out.to_path_buf(),
        };
        let path =
            btx::logs::write_session(&s, &dir.join(format!("run-{k}.jsonl"))).map_err(Box::new)?;
        eprintln!(
            "{}: {} ticks, {} transitions, {}",
            btx::text::path(&path),
            s.index.ticks(),
            s.index.transitions.len(),
            s.ending()
        );
        Ok(())
    })?;
    Ok(())
}
