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
    let vars = variables(&mut rng, n, n_top, n_int, p.connectivity, flip);
    let kids = shape(&mut rng, p.leaves);
    let mut b = Builder {
        rng,
        p,
        vars: &vars,
        internals: (n_top..n_top + n_int).collect(),
        k_in: round_half_even(0.5 * n as f64),
        k_out: round_half_even(0.5 * n_int as f64).max(1),
        nodes: Vec::new(),
        leaf_defs: String::new(),
        models: String::new(),
        extra_vars: String::new(),
        leaf_no: 0,
        comp_no: 0,
    };
    let root = b.node(0, &kids);
    let mut body = String::new();
    write(&b.nodes, root, 0, &mut body);
    let xml = format!(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Random\">\n  <BehaviorTree ID=\"Random\">\n{body}  </BehaviorTree>\n  <TreeNodesModel>\n{}  </TreeNodesModel>\n</root>\n",
        b.models
    );
    let mut domain = domain_header(p, n, &vars);
    domain.push_str(&b.extra_vars);
    domain.push_str(&b.leaf_defs);
    Generated {
        xml,
        domain,
        top: vars[..n_top].iter().map(|v| v.name.clone()).collect(),
    }
}

/// The state variables: top, intermediate and bottom, edges only into the
/// bottom ones from any earlier variable, each bottom one the AND or OR of
/// its parents.
fn variables(
    rng: &mut Rng,
    n: usize,
    n_top: usize,
    n_int: usize,
    connectivity: f64,
    flip: Option<&str>,
) -> Vec<Var> {
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
    let mut candidates = Vec::new();
    for b in n_top + n_int..n {
        for a in 0..b {
            candidates.push((a, b));
        }
    }
    let k = (connectivity * candidates.len() as f64).round() as usize;
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
    vars
}

/// The tree's shape: each node's children, grown a leaf at a time by
/// splitting a node drawn at random.
fn shape(rng: &mut Rng, leaves: usize) -> Vec<Vec<usize>> {
    let mut kids: Vec<Vec<usize>> = vec![Vec::new()];
    let mut grown = 1;
    while grown < leaves.max(1) {
        let i = rng.range(0, kids.len() - 1);
        let new = if kids[i].is_empty() { 2 } else { 1 };
        for _ in 0..new {
            kids.push(Vec::new());
            let c = kids.len() - 1;
            kids[i].push(c);
        }
        grown += 1;
    }
    kids
}

/// Builds the tree's nodes and the leaves' tables, drawing from one random
/// stream in a fixed order: the same problem for the same seed.
struct Builder<'a> {
    rng: Rng,
    p: &'a Params,
    vars: &'a [Var],
    internals: Vec<usize>,
    k_in: usize,
    k_out: usize,
    nodes: Vec<Node>,
    leaf_defs: String,
    models: String,
    extra_vars: String,
    leaf_no: usize,
    comp_no: usize,
}

fn quote(xs: &[String]) -> String {
    xs.iter()
        .map(|x| format!("\"{x}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Builder<'_> {
    /// Node `i` of the shape, perhaps under a decorator: its index in
    /// `nodes`.
    fn node(&mut self, i: usize, kids: &[Vec<usize>]) -> usize {
        let me = if kids[i].is_empty() {
            self.leaf()
        } else {
            self.composite(i, kids)
        };
        if self.p.extended && i != 0 && self.rng.range(0, 4) == 0 {
            let tag = [
                "Inverter",
                "ForceSuccess",
                "ForceFailure",
                "KeepRunningUntilFailure",
            ][self.rng.range(0, 3)];
            self.nodes.push(Node::Decorator {
                tag,
                attrs: String::new(),
                child: me,
            });
            return self.nodes.len() - 1;
        }
        me
    }

    /// A leaf: an action writing intermediate variables, or a condition.
    fn leaf(&mut self) -> usize {
        let l = self.leaf_no;
        self.leaf_no += 1;
        let action = self.rng.coin() && !self.internals.is_empty();
        let n_in = if action {
            self.rng.range(0, self.k_in)
        } else {
            self.rng.range(1, self.k_in.max(1))
        };
        let inputs = self.rng.choose(self.vars.len(), n_in);
        if action {
            self.action(l, inputs);
        } else {
            self.condition(l, inputs);
        }
        self.nodes.push(Node::Leaf(l));
        self.nodes.len() - 1
    }

    /// An action leaf: a decision table over its inputs, an effect of each
    /// action on its outputs, success for one action.
    fn action(&mut self, l: usize, mut inputs: Vec<usize>) {
        let vars = self.vars;
        let rng = &mut self.rng;
        let name = format!("L{l}");
        let n_out = rng.range(1, self.k_out.min(self.internals.len()));
        let outputs: Vec<usize> = rng
            .choose(self.internals.len(), n_out)
            .into_iter()
            .map(|j| self.internals[j])
            .collect();
        let n_act = rng.range(1, 2);
        let acts: Vec<usize> = rng.choose(4, n_act);
        let names: Vec<String> = acts.iter().map(|a| format!("RandomAction{a}")).collect();
        let key = names[rng.range(0, names.len() - 1)].clone();
        // A leaf that stays RUNNING until it has made progress.
        let slow = self.p.extended && rng.range(0, 3) == 0;
        let progress = format!("P{l}");
        let mut in_names: Vec<String> = inputs.iter().map(|&x| vars[x].name.clone()).collect();
        let mut out_names: Vec<String> = outputs.iter().map(|&x| vars[x].name.clone()).collect();
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
            status = format!("if action != () && !{progress} {{ RUNNING }} else {{ {status} }}");
            self.extra_vars.push_str(&format!(
                "\n[state.{progress}]\ntype = \"bool\"\ninitial = false\n"
            ));
            in_names.push(progress.clone());
            out_names.push(progress.clone());
        }
        self.leaf_defs.push_str(&format!(
            "\n[leaf.{name}]\ninputs = [{}]\noutputs = [{}]\nactions = [{}]\ndecide = '''\nlet i = {index};\n[{}][i]\n'''\neffect = '''\n{effect}\n'''\nstatus = '''\n{status}\n'''\n",
            quote(&in_names),
            quote(&out_names),
            quote(&names),
            table.join(", "),
        ));
        self.models
            .push_str(&format!("    <Action ID=\"{name}\"/>\n"));
    }

    /// A condition leaf: a truth table over its inputs.
    fn condition(&mut self, l: usize, inputs: Vec<usize>) {
        let name = format!("L{l}");
        let rows = 1usize << inputs.len();
        let table: Vec<String> = (0..rows).map(|_| self.rng.coin().to_string()).collect();
        let in_names: Vec<String> = inputs.iter().map(|&x| self.vars[x].name.clone()).collect();
        self.leaf_defs.push_str(&format!(
            "\n[leaf.{name}]\ninputs = [{}]\nstatus = '''\nlet i = {};\nif [{}][i] {{ SUCCESS }} else {{ FAILURE }}\n'''\n",
            quote(&in_names),
            input_index(&inputs, self.vars),
            table.join(", "),
        ));
        self.models
            .push_str(&format!("    <Condition ID=\"{name}\"/>\n"));
    }

    /// A composite over node `i`'s children, built first: a Sequence or a
    /// Fallback, or in the extended problems any control node btx models.
    fn composite(&mut self, i: usize, kids: &[Vec<usize>]) -> usize {
        let children: Vec<usize> = kids[i].iter().map(|&c| self.node(c, kids)).collect();
        let c = self.comp_no;
        self.comp_no += 1;
        let rng = &mut self.rng;
        let (tag, attrs) = if self.p.extended {
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
        self.nodes.push(Node::Composite {
            tag,
            attrs: format!(" name=\"C{c}\"{attrs}"),
            children,
        });
        self.nodes.len() - 1
    }
}

/// Node `i` as BehaviorTree.CPP 4 XML, indented by its depth.
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

/// The domain file's header and its state tables.
fn domain_header(p: &Params, n: usize, vars: &[Var]) -> String {
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
    for v in vars {
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
                quote(&names)
            ));
        }
    }
    domain
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
