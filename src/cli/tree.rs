//! `btx tree`: Print a tree (of a tree file or a session): the full tree, or the framed tree.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// A BehaviorTree.CPP XML file (v3 or v4), or a session.
    pub file: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// Show the framed tree and the semantic sets {goal, subgoals, steps, actions}.
    #[arg(long)]
    pub framed: bool,
    #[arg(long, value_enum, default_value = "text")]
    pub format: TreeFormat,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        file,
        reading,
        framed,
        format,
    } = args;
    let input = open_input(&file, &reading, cli.quiet)?;
    let tree = input.tree();
    let out = match (framed, format) {
        (false, TreeFormat::Text) => {
            export::write_tree_text(tree, &mut |l| print!("{l}"));
            return Ok(());
        }
        (false, TreeFormat::Json) => {
            export::write_tree_json(tree, &mut |s| print!("{s}"));
            return Ok(());
        }
        (false, TreeFormat::Dot) => export::tree_dot(tree),
        (false, TreeFormat::Mermaid) => export::tree_mermaid(tree),
        (true, TreeFormat::Xml) => {
            fail!("the framed tree is a view, not a runnable tree: drop --framed to write XML")
        }
        (false, TreeFormat::Xml) => btx::xml::to_v4_xml(tree),
        (true, f) => {
            let fr = Framed::new(tree);
            match f {
                TreeFormat::Json => pretty(&export::framed_json(tree, &fr)),
                TreeFormat::Dot => export::framed_dot(tree, &fr),
                TreeFormat::Mermaid => export::framed_mermaid(tree, &fr),
                _ => export::framed_text(tree, &fr),
            }
        }
    };
    print!("{out}");
    Ok(())
}
