//! `btx world`: Show a built-in world: the taxi grid, its optimal policy and the tree generated from it.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    #[arg(value_enum)]
    pub world: World,
    /// Whose costs: the optimal driver's (a toll costs 3 moves) or a person's expectation (1 move).
    #[arg(long, value_enum, default_value = "optimal")]
    pub costs: CostModel,
    /// Print the behaviour tree generated from the policy, as BehaviorTree.CPP 4 XML.
    #[arg(long)]
    pub tree: bool,
}

pub fn run(args: Args) -> Result<(), Failure> {
    let Args { world, costs, tree } = args;
    match world {
        World::Kitting => {
            for (i, (name, _)) in kitting::SCENARIOS.iter().enumerate() {
                println!("--seed {i}: {name}");
            }
        }
        World::Taxi => {
            let g = Grid::han();
            let c = match costs {
                CostModel::Optimal => Costs::OPTIMAL,
                CostModel::Expected => Costs::EXPECTED,
            };
            let actions = g.rollout(&g.solve(c));
            if tree {
                print!("{}", taxi::policy_tree_xml(&actions));
            } else {
                print!("{}", taxi_text(&g, c, &actions));
            }
        }
    }
    Ok(())
}

fn taxi_text(g: &Grid, c: Costs, actions: &[taxi::Action]) -> String {
    let mut out = String::new();
    for y in (1..=g.height).rev() {
        out.push_str(&format!("row {y} "));
        for x in 1..=g.width {
            let cell = if (x, y) == g.passenger {
                'P'
            } else if g.tolls.contains(&(x, y)) {
                'T'
            } else if (x, y) == g.start {
                'S'
            } else {
                '.'
            };
            let wall = x > 1 && g.walls.contains(&((x - 1, y), (x, y)));
            out.push_str(if wall { " | " } else { "   " });
            out.push(cell);
        }
        out.push('\n');
    }
    out.push_str("      ");
    for x in 1..=g.width {
        out.push_str(&format!("   {x}"));
    }
    out.push_str(&format!(
        "\ncosts: a move {}, a toll {}\npolicy: ",
        c.step, c.toll
    ));
    out.push_str(
        &actions
            .iter()
            .map(|a| a.name())
            .collect::<Vec<_>>()
            .join(", "),
    );
    out.push('\n');
    out
}
