//! `btx ask`: Ask questions about a node of a tree, or about a moment of a session.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// A tree file, or a session.
    pub file: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// The moment of a session: TICK (its end), TICK:STEP, last, end, or -N (-1: the last tick). Default: the end of the run.
    #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// The node: #uid, a description or ID, or a path like "go insert large gear/detect chuck/lift torso".
    /// Default for a session: the current node at the moment.
    #[arg(long, value_name = "PICK")]
    pub node: Option<String>,
    /// Questions: the paper's wording, "Can you X?", or q1 q2 q3 q4 q5-subgoal q5-goal anything-wrong wrong handled.
    #[arg(required = true, value_name = "QUESTION")]
    pub questions: Vec<String>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        file,
        reading,
        at,
        node,
        questions,
        format,
    } = args;
    let input = open_input(&file, &reading, cli.quiet)?;
    let mut qs = Vec::new();
    for q in &questions {
        match Question::parse(q) {
            Some(q) => qs.push(q),
            None => {
                let known: Vec<String> = Question::fixed()
                    .iter()
                    .map(|q| format!("\"{}\" ({})", q.wording(), q.short()))
                    .collect();
                fail!(
                    "unknown question \"{q}\"; ask one of: {}, or \"Can you X?\"",
                    known.join(", ")
                );
            }
        }
    }
    let tree = input.tree();
    let view = match input.session() {
        Some(s) => {
            let m = match &at {
                Some(a) => Moment::parse_within(a, s.index.ticks()).map_err(Failure::Plain)?,
                None => Moment {
                    tick: s.index.ticks().max(1),
                    step: None,
                },
            };
            if s.index.ticks() == 0 {
                fail!("{}: the session recorded no tick", file.display());
            }
            Some(s.at(m).map_err(Failure::Plain)?)
        }
        None => {
            if at.is_some() {
                fail!(
                    "--at picks a moment of a run, and {} is a tree, not a session",
                    file.display()
                );
            }
            None
        }
    };
    let uid = match (&node, &view) {
        (Some(p), _) => pick_node(tree, p)?,
        (None, Some(v)) => match v.current() {
            Some(u) => u,
            None => fail!(
                "nothing has been ticked yet at moment {}; pick a node with --node",
                v.moment()
            ),
        },
        (None, None) => {
            fail!("pick the node to ask about with --node (a tree has no current node)")
        }
    };
    let mut answers = Vec::new();
    for q in &qs {
        answers.push(explain::answer(tree, view.as_ref(), uid, q).map_err(Failure::Plain)?);
    }
    match format {
        Format::Text => {
            for a in &answers {
                println!("{}", a.text);
            }
        }
        Format::Json => {
            let moment = view.map(|v| v.moment().to_string());
            print!(
                "{}",
                pretty(&export::answers_json(
                    tree,
                    uid,
                    moment.as_deref(),
                    &answers
                ))
            )
        }
    }
    Ok(())
}
