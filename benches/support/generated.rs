//! A generated tree of any size, shared by the benchmarks.

#![allow(dead_code)]

/// A kitting-like tree: `subtrees` SubTree definitions, each used twice, each
/// a Fallback over retried sequences of named actions with ports.
pub fn generated_tree(target_nodes: usize) -> String {
    // One definition expands to 1 + 2 + 4 * (2 + 2 + leaves) nodes.
    let leaves = 10;
    let per_def = 3 + 4 * (4 + leaves);
    let defs = target_nodes / (2 * (per_def + 1));
    let mut x = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\">\n<BehaviorTree ID=\"Main\"><Sequence name=\"do everything\">\n");
    for d in 0..defs {
        for copy in 0..2 {
            x.push_str(&format!(
                "<SubTree ID=\"Task{d}\" name=\"task {d} copy {copy}\" target=\"{{goal}}\"/>\n"
            ));
        }
    }
    x.push_str("</Sequence></BehaviorTree>\n");
    for d in 0..defs {
        x.push_str(&format!("<BehaviorTree ID=\"Task{d}\"><Fallback name=\"task {d}\"><Sequence name=\"task {d}\">\n"));
        for s in 0..4 {
            x.push_str(&format!(
                "<RetryUntilSuccessful num_attempts=\"3\"><Sequence><Sequence name=\"step {s}\">"
            ));
            for l in 0..leaves {
                x.push_str(&format!(
                    "<do_thing name=\"thing {l}\" pose=\"{{target}}\" output=\"{{out {l}}}\"/>"
                ));
            }
            x.push_str("</Sequence><check_it name=\"check\"/></Sequence></RetryUntilSuccessful>\n");
        }
        x.push_str("</Sequence><ask/></Fallback></BehaviorTree>\n");
    }
    x.push_str("<TreeNodesModel><Action ID=\"do_thing\"><input_port name=\"pose\"/><output_port name=\"output\"/></Action><Condition ID=\"check_it\"/><Action ID=\"ask\"/></TreeNodesModel>\n</root>\n");
    x
}

/// A tree of `n` nodes whose leaves are all direct children of reactive
/// sequences, so that every tick visits the whole tree.
pub fn flat_tree(groups: usize, per_group: usize) -> String {
    let mut x = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\"><BehaviorTree ID=\"Main\"><Sequence name=\"all\">\n");
    for g in 0..groups {
        x.push_str(&format!("<Sequence name=\"group {g}\">"));
        for l in 0..per_group {
            x.push_str(&format!("<do_thing name=\"thing {g}.{l}\"/>"));
        }
        x.push_str("</Sequence>\n");
    }
    x.push_str("</Sequence></BehaviorTree><TreeNodesModel><Action ID=\"do_thing\"/></TreeNodesModel></root>\n");
    x
}

/// A session of the deep generated tree under `Repeat -1` (the root never
/// completes), of 250,000 ticks (about 1,080,000 transitions), written once
/// to `$BTX_BENCH_DIR` (default: `$TMPDIR/btx-bench`) and reused.
pub fn big_session() -> std::path::PathBuf {
    use btx::run::plan::{Plan, PlanLeaves};
    use btx::session::record::{record, RunRequest};
    use std::path::{Path, PathBuf};
    let dir = std::env::var("BTX_BENCH_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| std::env::temp_dir().join("btx-bench"));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.jsonl");
    if out.exists() {
        return out;
    }
    let xml = generated_tree(10_000)
        .replace(
            "<BehaviorTree ID=\"Main\">",
            "<BehaviorTree ID=\"Main\"><Repeat num_cycles=\"-1\">",
        )
        .replacen(
            "</Sequence></BehaviorTree>",
            "</Sequence></Repeat></BehaviorTree>",
            1,
        );
    let tree = btx::xml::load_str(Path::new("deep.xml"), &xml, &Default::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(
        Path::new("bench.plan"),
        "@default_action = 1RS\n@default_condition = S",
    )
    .unwrap();
    let req = RunRequest {
        tree: &tree,
        tree_file: None,
        source: btx::session::Source {
            kind: "plan".into(),
            path: None,
            text: None,
            name: None,
        },
        seed: None,
        max_ticks: 250_000,
        options: btx::run::RunOptions::default(),
        ask: None,
        out: &out,
    };
    record(req, PlanLeaves::new(plan, &tree)).unwrap();
    out
}

/// A chain of `n` SubTrees, each a Sequence of a leaf and the next SubTree
/// (3n nodes, about 2n levels): the deep tree of #31 item 1.
pub fn subtree_chain(n: usize) -> String {
    let mut x = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"T0\">\n");
    for k in 0..n {
        let inner = if k + 1 < n {
            format!("<SubTree ID=\"T{}\"/>", k + 1)
        } else {
            "<AlwaysSuccess/>".to_string()
        };
        x.push_str(&format!(
            "<BehaviorTree ID=\"T{k}\"><Sequence><AlwaysSuccess/>{inner}</Sequence></BehaviorTree>\n"
        ));
    }
    x.push_str("</root>\n");
    x
}
