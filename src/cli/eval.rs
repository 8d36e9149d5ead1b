//! `btx eval`: Evaluations: `btx eval recovery random` (Love et al.'s Table 2).

use super::*;

#[derive(clap::Args)]
pub struct Args {
    #[arg(value_enum)]
    pub what: EvalWhat,
    #[arg(value_enum)]
    pub domain: EvalDomain,
    /// Seeds per configuration (random: the paper uses 10; serial recall: 50), at most 10,000.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub seeds: Option<u64>,
    /// Random trees with reactive and memory composites, Parallel, IfThenElse, decorators and RUNNING leaves.
    #[arg(long)]
    pub extended: bool,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args) -> Result<(), Failure> {
    match args {
        Args {
            what: EvalWhat::Truth,
            domain,
            seeds,
            extended,
            format,
        } => {
            if !matches!(domain, EvalDomain::Random) {
                fail!("btx eval truth runs on random domains: btx eval truth random");
            }
            let started = std::time::Instant::now();
            let t = btx::causal::truth::truth_random(seeds.unwrap_or(2), extended)
                .map_err(Failure::Plain)?;
            let secs = started.elapsed().as_secs_f64();
            match format {
                Format::Text => {
                    print!("{}", t.text());
                    println!("in {secs:.2} s");
                }
                Format::Json => print!(
                    "{}",
                    pretty(&serde_json::json!({"tally": t, "seconds": secs}))
                ),
            }
        }
        Args {
            what: EvalWhat::Recovery,
            domain,
            seeds,
            extended,
            format,
        } => {
            let started = std::time::Instant::now();
            let (rows, table) = match domain {
                EvalDomain::Random => {
                    let rows = btx::causal::eval::recovery_random(seeds.unwrap_or(10), extended)
                        .map_err(Failure::Plain)?;
                    let t = btx::causal::eval::table2(&rows);
                    (rows, t)
                }
                EvalDomain::SerialRecall => {
                    let rows = btx::causal::eval::recovery_serial_recall(seeds.unwrap_or(50))
                        .map_err(Failure::Plain)?;
                    let t = btx::causal::eval::table3(&rows);
                    (rows, t)
                }
            };
            let secs = started.elapsed().as_secs_f64();
            match format {
                Format::Text => {
                    print!("{table}");
                    println!(
                        "{} comparisons in {secs:.2} s ({} threads)",
                        rows.len(),
                        rayon::current_num_threads()
                    );
                }
                Format::Json => print!(
                    "{}",
                    pretty(&serde_json::json!({"rows": rows, "seconds": secs}))
                ),
            }
        }
    }
    Ok(())
}
