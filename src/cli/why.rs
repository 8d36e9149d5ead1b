//! `btx why`: Why did something happen and not something else? A counterfactual search over the explanation model of the tick (Love et al.).

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// A session (or a log btx reads as one).
    pub session: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// status(NODE), executed(NODE), decision(NODE) or a state variable VAR (VAR^K: its copy K in the tick).
    pub target: String,
    /// A value the target did not have (repeatable). Default: every other value.
    #[arg(long = "not", value_name = "VALUE")]
    pub not: Vec<String>,
    /// The moment: TICK (its end), TICK:STEP, last, end, or -N (-1: the last tick). Default: the end of the run.
    #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// The largest number of variables changed together.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub max_depth: usize,
    /// Show every explanation (default: the first three, the cause first, and how many more).
    #[arg(long)]
    pub all: bool,
    /// How much to say: brief (the question and the cause), normal, or full (every explanation, and what the run shows of each node it rests on).
    #[arg(long, value_enum, default_value = "normal")]
    pub detail: DetailArg,
    /// A domain file instead of the one the session recorded.
    #[arg(long, value_name = "FILE")]
    pub domain: Option<PathBuf>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        session,
        reading,
        target,
        not,
        at,
        max_depth,
        all,
        detail,
        domain,
        format,
    } = args;
    let input = open_input(&session, &reading, cli.quiet)?;
    let s = session_of(&input, &session)?;
    let at = at
        .as_deref()
        .map(|a| s.moment_at(a))
        .transpose()
        .map_err(Failure::Plain)?;
    let d = btx::causal::session_domain(s, domain.as_deref()).map_err(located)?;
    let mut w = btx::causal::why(s, d, &target, &not, at, max_depth).map_err(located)?;
    let detail: btx::ask::Detail = detail.into();
    match format {
        Format::Text if all && detail == btx::ask::Detail::Normal => print!("{}", w.text()),
        Format::Text => print!("{}", btx::ask::detail::why_text(&mut w, s, detail)),
        Format::Json => print!("{}", pretty(&w.json())),
    }
    Ok(())
}
