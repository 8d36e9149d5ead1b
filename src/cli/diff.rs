//! `btx diff`: Compare two trees or runs subgoal by subgoal (Han et al.'s expected vs actual policy), or one reference with several runs.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// A then B (trees, sessions or logs); or a reference and several runs.
    #[arg(required = true, num_args = 2.., value_name = "A B | REF RUN...")]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub reading: Reading,
    /// For two runs of one tree: where they first part ways, and why B did not do what A did.
    #[arg(long)]
    pub why: bool,
    /// With --why: the largest number of variables changed together.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub max_depth: usize,
    /// With --why: a domain file instead of the one B recorded.
    #[arg(long, value_name = "FILE")]
    pub domain: Option<PathBuf>,
    /// Exit with status 1 when the inputs diverge (like diff(1)).
    #[arg(long)]
    pub exit_code: bool,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        files,
        reading,
        why,
        max_depth,
        domain,
        exit_code,
        format,
    } = args;
    let inputs = files
        .iter()
        .map(|f| {
            // Runs are compared by order, not time: a log's times (8 bytes
            // a transition) go as each is read.
            let mut i = open_input(f, &reading, cli.quiet)?;
            if let Input::Session(s) = &mut i {
                s.times_us = Vec::new();
            }
            Ok(i)
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let sides: Vec<btx::diff::Side> = files
        .iter()
        .zip(&inputs)
        .map(|(f, i)| {
            let name = btx::text::path(f).to_string();
            match i.session() {
                Some(s) => btx::diff::Side::session(name, s),
                None => btx::diff::Side::tree(name, i.tree()),
            }
        })
        .collect();
    let diverges = if sides.len() > 2 {
        if why {
            fail!("--why compares two runs; give A and B only");
        }
        let f = btx::diff::fleet::Fleet::new(&sides[0], &sides[1..]);
        match format {
            Format::Text => print!("{}", f.text()),
            Format::Json => print!("{}", pretty(&f.json())),
        }
        f.diffs.iter().any(|d| !d.is_empty())
    } else {
        let d = btx::diff::Diff::new(&sides[0], &sides[1]);
        let diverged = if why {
            Some(why_parted(&inputs, &files, domain.as_deref(), max_depth)?)
        } else {
            None
        };
        print_pair(&d, &diverged, format, &inputs);
        !d.is_empty() || matches!(diverged, Some(Some(_)))
    };
    if exit_code && diverges {
        return Err(Failure::Exit(1));
    }
    Ok(())
}

/// `--why`: where two runs of one tree first part ways, and why B did not
/// do what A did (none: they do not part).
fn why_parted(
    inputs: &[Input],
    files: &[PathBuf],
    domain: Option<&std::path::Path>,
    max_depth: usize,
) -> Result<Option<btx::causal::compare::Diverged>, Failure> {
    let (Some(a), Some(b)) = (inputs[0].session(), inputs[1].session()) else {
        fail!("--why asks why two runs diverged: give two sessions or logs");
    };
    if !btx::diff::same_shape(&a.tree, &b.tree) {
        fail!(
            "--why compares two runs of one tree, and {} and {} ran different trees",
            btx::text::path(&files[0]),
            btx::text::path(&files[1])
        );
    }
    let dom = btx::causal::session_domain(b, domain).map_err(located)?;
    btx::causal::compare::why_diverged(a, b, dom, max_depth).map_err(located)
}

/// Two trees or runs compared, and with `--why` why they parted.
fn print_pair(
    d: &btx::diff::Diff,
    diverged: &Option<Option<btx::causal::compare::Diverged>>,
    format: Format,
    inputs: &[Input],
) {
    use btx::causal::compare::Diverged;
    match format {
        Format::Text => {
            let mut out = std::io::BufWriter::new(std::io::stdout().lock());
            written(
                d.write_text(&mut out)
                    .and_then(|()| std::io::Write::flush(&mut out)),
            );
            drop(out);
            match diverged {
                Some(None) => println!("\n{}", Diverged::SAME),
                Some(Some(x)) => {
                    print!("\n{}", x.why_text("Why, in B: "))
                }
                None => {}
            }
        }
        Format::Json => {
            let mut v = d.json();
            if let Some(x) = diverged {
                v["why"] = match x {
                    None => serde_json::Value::Null,
                    Some(x) => serde_json::json!({
                        "transition": x.difference.index + 1,
                        "moment": x.difference.moment.to_string(),
                        "text": x.difference.text(inputs[0].tree(), inputs[1].tree(), "A", "B"),
                        "answer": x.why.as_ref().map(|w| w.json()),
                    }),
                };
            }
            print!("{}", pretty(&v));
        }
    }
}
