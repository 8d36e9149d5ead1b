//! Random trees and boolean state graphs, with the parameters of Love et
//! al.'s evaluation (btcm.md §4.3): `vars` boolean variables (half of them
//! top-level inputs T…, a quarter internal I… that leaves write, the rest
//! derived B…, each an AND/OR fold of earlier variables), and a tree of
//! `leaves` leaves under Sequence and Fallback nodes whose leaves are fixed
//! random functions of their inputs. Everything is written out as a tree
//! file and a domain file, so the simulator and the explanation model run
//! the very same functions.
//!
//! `extended` adds what the paper leaves to future work: reactive and
//! memory composites, Parallel, IfThenElse, decorators, and leaves that
//! stay RUNNING for a tick.

/// A small deterministic generator (SplitMix64): the same seed gives the
/// same domain on every machine, which btcm's hash-dependent one does not.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5851_F42D_4C95_7F2D)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `lo..=hi`.
    pub fn range(&mut self, lo: usize, hi: usize) -> usize {
        if hi <= lo {
            lo
        } else {
            lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
        }
    }

    pub fn coin(&mut self) -> bool {
        self.next_u64() & 1 == 1
    }

    /// `k` distinct items of `0..n`, in increasing order.
    pub fn choose(&mut self, n: usize, k: usize) -> Vec<usize> {
        let mut all: Vec<usize> = (0..n).collect();
        for i in 0..k.min(n) {
            let j = self.range(i, n - 1);
            all.swap(i, j);
        }
        let mut out = all[..k.min(n)].to_vec();
        out.sort_unstable();
        out
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    pub seed: u64,
    pub vars: usize,
    pub connectivity: f64,
    pub leaves: usize,
    pub extended: bool,
}

/// A generated problem: the tree (BehaviorTree.CPP 4 XML), the domain file
/// and the names of the top-level variables (the ones an evaluation flips).
#[derive(Debug, Clone)]
pub struct Generated {
    pub xml: String,
    pub domain: String,
    pub top: Vec<String>,
}

fn round_half_even(x: f64) -> usize {
    let r = x.round();
    if (x - x.trunc() - 0.5).abs() < 1e-12 && (r as i64) % 2 == 1 {
        (r - 1.0) as usize
    } else {
        r as usize
    }
}

struct Var {
    name: String,
    parents: Vec<usize>,
    /// For each parent after the first: AND (true) or OR.
    ops: Vec<bool>,
    initial: bool,
}

enum Node {
    Composite {
        tag: &'static str,
        attrs: String,
        children: Vec<usize>,
    },
    Decorator {
        tag: &'static str,
        attrs: String,
        child: usize,
    },
    Leaf(usize),
}

fn input_index(inputs: &[usize], vars: &[Var]) -> String {
    if inputs.is_empty() {
        return "0".into();
    }
    inputs
        .iter()
        .enumerate()
        .map(|(j, &x)| format!("(if {} {{ {} }} else {{ 0 }})", vars[x].name, 1u64 << j))
        .collect::<Vec<_>>()
        .join(" + ")
}

/// Generates a problem; `flip` names a top-level variable whose initial
/// value is flipped (an altered run of the same problem).
pub fn generate(p: &Params, flip: Option<&str>) -> Generated {
    let n = p.vars.max(1);
    let mut rng = Rng::new(p.seed.wrapping_mul(1_000_003) ^ (n as u64) << 32 ^ p.leaves as u64);
    let n_top = round_half_even(0.5 * n as f64).max(1);
    let n_int = round_half_even(0.25 * n as f64).min(n - n_top);
    let mut vars: Vec<Var> = (0..n)
        .map(|i| Var {
            name: if i < n_top {
                format!("T{}", i + 1)
            } else if i < n_top + n_int {
                format!("I{}", i - n_top + 1)
            } else {
                format!("B{}", i - n_top - n_int + 1)
            },
            parents: Vec::new(),
            ops: Vec::new(),
            initial: false,
        })
        .collect();
    // Edges only into bottom variables, from any earlier variable.
    let mut candidates = Vec::new();
    for b in n_top + n_int..n {
        for a in 0..b {
            candidates.push((a, b));
        }
    }
    let k = (p.connectivity * candidates.len() as f64).round() as usize;
    for i in rng.choose(candidates.len(), k) {
        let (a, b) = candidates[i];
        vars[b].parents.push(a);
    }
    for v in &mut vars {
        v.ops = (1..v.parents.len()).map(|_| rng.coin()).collect();
    }
    // Initial values: the same for every seed of a size, as btcm draws them.
    let mut init = Rng::new(42 + n as u64);
    for v in &mut vars {
        v.initial = init.coin();
    }
    if let Some(f) = flip {
        if let Some(v) = vars.iter_mut().find(|v| v.name == f) {
            v.initial = !v.initial;
        }
    }

    // The tree's shape.
    let mut kids: Vec<Vec<usize>> = vec![Vec::new()];
    let mut leaves = 1;
    while leaves < p.leaves.max(1) {
        let i = rng.range(0, kids.len() - 1);
        let new = if kids[i].is_empty() { 2 } else { 1 };
        for _ in 0..new {
            kids.push(Vec::new());
            let c = kids.len() - 1;
            kids[i].push(c);
        }
        leaves += 1;
    }
    let k_in = round_half_even(0.5 * n as f64);
    let k_out = round_half_even(0.5 * n_int as f64).max(1);
    let internals: Vec<usize> = (n_top..n_top + n_int).collect();
    let mut nodes: Vec<Node> = Vec::new();
    let mut leaf_defs = String::new();
    let mut models = String::new();
    let mut extra_vars = String::new();
    let mut leaf_no = 0;
    let mut comp_no = 0;
    // Builds node `i` of the shape, returning its index in `nodes`.
    #[allow(clippy::too_many_arguments)]
    fn build(
        i: usize,
        kids: &[Vec<usize>],
        rng: &mut Rng,
        p: &Params,
        vars: &[Var],
        internals: &[usize],
        k_in: usize,
        k_out: usize,
        nodes: &mut Vec<Node>,
        leaf_defs: &mut String,
        models: &mut String,
        extra_vars: &mut String,
        leaf_no: &mut usize,
        comp_no: &mut usize,
    ) -> usize {
        let me = if kids[i].is_empty() {
            let l = *leaf_no;
            *leaf_no += 1;
            let name = format!("L{l}");
            let action = rng.coin() && !internals.is_empty();
            let n_in = if action {
                rng.range(0, k_in)
            } else {
                rng.range(1, k_in.max(1))
            };
            let mut inputs = rng.choose(vars.len(), n_in);
            let quote = |xs: &[String]| {
                xs.iter()
                    .map(|x| format!("\"{x}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            if action {
                let n_out = rng.range(1, k_out.min(internals.len()));
                let outputs: Vec<usize> = rng
                    .choose(internals.len(), n_out)
                    .into_iter()
                    .map(|j| internals[j])
                    .collect();
                let n_act = rng.range(1, 2);
                let acts: Vec<usize> = rng.choose(4, n_act);
                let names: Vec<String> = acts.iter().map(|a| format!("RandomAction{a}")).collect();
                let key = names[rng.range(0, names.len() - 1)].clone();
                // A leaf that stays RUNNING until it has made progress.
                let slow = p.extended && rng.range(0, 3) == 0;
                let progress = format!("P{l}");
                let mut in_names: Vec<String> =
                    inputs.iter().map(|&x| vars[x].name.clone()).collect();
                let mut out_names: Vec<String> =
                    outputs.iter().map(|&x| vars[x].name.clone()).collect();
                inputs.sort_unstable();
                let rows = 1usize << inputs.len();
                let table: Vec<String> = (0..rows)
                    .map(|_| {
                        let c = rng.range(0, names.len());
                        if c == names.len() {
                            "()".to_string()
                        } else {
                            format!("\"{}\"", names[c])
                        }
                    })
                    .collect();
                let index = input_index(&inputs, vars);
                let mut effect = String::from("switch action {\n");
                for a in &names {
                    let mut sets: Vec<String> = Vec::new();
                    for &o in &outputs {
                        if rng.coin() {
                            sets.push(format!("{}: {}", vars[o].name, rng.coin()));
                        }
                    }
                    if slow {
                        sets.push(format!("{progress}: true"));
                    }
                    effect.push_str(&format!("    \"{a}\" => #{{ {} }},\n", sets.join(", ")));
                }
                effect.push_str("    _ => ()\n}");
                let mut status = format!("if action == \"{key}\" {{ SUCCESS }} else {{ FAILURE }}");
                if slow {
                    status =
                        format!("if action != () && !{progress} {{ RUNNING }} else {{ {status} }}");
                    extra_vars.push_str(&format!(
                        "\n[state.{progress}]\ntype = \"bool\"\ninitial = false\n"
                    ));
                    in_names.push(progress.clone());
                    out_names.push(progress.clone());
                }
                leaf_defs.push_str(&format!(
                    "\n[leaf.{name}]\ninputs = [{}]\noutputs = [{}]\nactions = [{}]\ndecide = '''\nlet i = {index};\n[{}][i]\n'''\neffect = '''\n{effect}\n'''\nstatus = '''\n{status}\n'''\n",
                    quote(&in_names),
                    quote(&out_names),
                    quote(&names),
                    table.join(", "),
                ));
                models.push_str(&format!("    <Action ID=\"{name}\"/>\n"));
            } else {
                let rows = 1usize << inputs.len();
                let table: Vec<String> = (0..rows).map(|_| rng.coin().to_string()).collect();
                let in_names: Vec<String> = inputs.iter().map(|&x| vars[x].name.clone()).collect();
                leaf_defs.push_str(&format!(
                    "\n[leaf.{name}]\ninputs = [{}]\nstatus = '''\nlet i = {};\nif [{}][i] {{ SUCCESS }} else {{ FAILURE }}\n'''\n",
                    quote(&in_names),
                    input_index(&inputs, vars),
                    table.join(", "),
                ));
                models.push_str(&format!("    <Condition ID=\"{name}\"/>\n"));
            }
            nodes.push(Node::Leaf(l));
            nodes.len() - 1
        } else {
            let children: Vec<usize> = kids[i]
                .iter()
                .map(|&c| {
                    build(
                        c, kids, rng, p, vars, internals, k_in, k_out, nodes, leaf_defs, models,
                        extra_vars, leaf_no, comp_no,
                    )
                })
                .collect();
            let c = *comp_no;
            *comp_no += 1;
            let (tag, attrs) = if p.extended {
                match rng.range(0, 6) {
                    0 => ("Sequence", String::new()),
                    1 => ("Fallback", String::new()),
                    2 => ("ReactiveSequence", String::new()),
                    3 => ("ReactiveFallback", String::new()),
                    4 => ("SequenceWithMemory", String::new()),
                    5 if children.len() <= 3 => ("IfThenElse", String::new()),
                    _ => (
                        "Parallel",
                        format!(
                            " success_count=\"{}\" failure_count=\"1\"",
                            rng.range(1, children.len())
                        ),
                    ),
                }
            } else if rng.coin() {
                ("Sequence", String::new())
            } else {
                ("Fallback", String::new())
            };
            nodes.push(Node::Composite {
                tag,
                attrs: format!(" name=\"C{c}\"{attrs}"),
                children,
            });
            nodes.len() - 1
        };
        if p.extended && i != 0 && rng.range(0, 4) == 0 {
            let tag = [
                "Inverter",
                "ForceSuccess",
                "ForceFailure",
                "KeepRunningUntilFailure",
            ][rng.range(0, 3)];
            nodes.push(Node::Decorator {
                tag,
                attrs: String::new(),
                child: me,
            });
            return nodes.len() - 1;
        }
        me
    }
    let root = build(
        0,
        &kids,
        &mut rng,
        p,
        &vars,
        &internals,
        k_in,
        k_out,
        &mut nodes,
        &mut leaf_defs,
        &mut models,
        &mut extra_vars,
        &mut leaf_no,
        &mut comp_no,
    );
    fn write(nodes: &[Node], i: usize, depth: usize, out: &mut String) {
        let pad = "  ".repeat(depth + 2);
        match &nodes[i] {
            Node::Leaf(l) => out.push_str(&format!("{pad}<L{l}/>\n")),
            Node::Composite {
                tag,
                attrs,
                children,
            } => {
                out.push_str(&format!("{pad}<{tag}{attrs}>\n"));
                for &c in children {
                    write(nodes, c, depth + 1, out);
                }
                out.push_str(&format!("{pad}</{tag}>\n"));
            }
            Node::Decorator { tag, attrs, child } => {
                out.push_str(&format!("{pad}<{tag}{attrs}>\n"));
                write(nodes, *child, depth + 1, out);
                out.push_str(&format!("{pad}</{tag}>\n"));
            }
        }
    }
    let mut body = String::new();
    write(&nodes, root, 0, &mut body);
    let xml = format!(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Random\">\n  <BehaviorTree ID=\"Random\">\n{body}  </BehaviorTree>\n  <TreeNodesModel>\n{models}  </TreeNodesModel>\n</root>\n"
    );
    let mut domain = format!(
        "# Generated by btx: seed {}, {} variables, connectivity {}, {} leaves{}.\nbtx_domain = 1\nname = \"random {} {} {} {}\"\n",
        p.seed,
        n,
        p.connectivity,
        p.leaves,
        if p.extended { ", extended" } else { "" },
        p.seed,
        n,
        p.connectivity,
        p.leaves
    );
    for v in &vars {
        domain.push_str(&format!("\n[state.{}]\ntype = \"bool\"\n", v.name));
        if v.parents.is_empty() {
            domain.push_str(&format!("initial = {}\n", v.initial));
        } else {
            let names: Vec<String> = v.parents.iter().map(|&x| vars[x].name.clone()).collect();
            let mut f = names[0].clone();
            for (name, &and) in names[1..].iter().zip(&v.ops) {
                f = format!("({f} {} {name})", if and { "&&" } else { "||" });
            }
            domain.push_str(&format!(
                "parents = [{}]\nfunction = \"{f}\"\n",
                names
                    .iter()
                    .map(|x| format!("\"{x}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    domain.push_str(&extra_vars);
    domain.push_str(&leaf_defs);
    Generated {
        xml,
        domain,
        top: vars[..n_top].iter().map(|v| v.name.clone()).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_problem_and_flips_only_the_initial_value() {
        let p = Params {
            seed: 3,
            vars: 8,
            connectivity: 0.5,
            leaves: 4,
            extended: false,
        };
        let a = generate(&p, None);
        let b = generate(&p, None);
        assert_eq!(a.xml, b.xml);
        assert_eq!(a.domain, b.domain);
        assert_eq!(a.top, vec!["T1", "T2", "T3", "T4"]);
        let c = generate(&p, Some("T2"));
        let diff: Vec<(&str, &str)> = a
            .domain
            .lines()
            .zip(c.domain.lines())
            .filter(|(x, y)| x != y)
            .collect();
        assert_eq!(diff.len(), 1, "{diff:?}");
        assert!(diff[0].0.starts_with("initial = "));
        assert_eq!(a.xml.matches("<L").count(), 4);
    }
}
