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
