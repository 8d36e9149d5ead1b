//! `btx graph`: Print the explanation model (causal graph) of a tick of a session.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    pub session: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// The moment: TICK, TICK:STEP, last, end, or -N (-1: the last tick). Default: the last tick.
    #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// A domain file instead of the one the session recorded.
    #[arg(long, value_name = "FILE")]
    pub domain: Option<PathBuf>,
    #[arg(long, value_enum, default_value = "dot")]
    pub format: GraphFormat,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        session,
        reading,
        at,
        domain,
        format,
    } = args;
    let input = open_input(&session, &reading, cli.quiet)?;
    let s = session_of(&input, &session)?;
    let tick = match at.as_deref() {
        Some(a) => {
            let m = s.moment_at(a).map_err(Failure::Plain)?;
            s.index.position(m).map_err(Failure::Plain)?;
            m.tick
        }
        None => s.index.ticks(),
    };
    let d = btx::causal::session_domain(s, domain.as_deref()).map_err(located)?;
    let m = btx::causal::model_at(s, d, tick).map_err(located)?;
    match format {
        GraphFormat::Dot => print!("{}", btx::causal::graph::dot(&m)),
        GraphFormat::Json => print!("{}", pretty(&btx::causal::graph::json(&m))),
        GraphFormat::Mermaid => print!("{}", btx::causal::graph::mermaid(&m)),
    }
    Ok(())
}
