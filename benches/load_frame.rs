//! Loading and framing a generated 10,000-node tree.

use btx::frame::Framed;
use btx::xml::{load_str, LoadOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;

/// A kitting-like tree: `subtrees` SubTree definitions, each used twice, each
/// a Fallback over retried sequences of named actions with ports.
fn generated_tree(target_nodes: usize) -> String {
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

fn bench(c: &mut Criterion) {
    let xml = generated_tree(10_000);
    let path = Path::new("generated.xml");
    let tree = load_str(path, &xml, &LoadOptions::default()).unwrap().tree;
    eprintln!(
        "generated tree: {} nodes, {} bytes of XML",
        tree.len(),
        xml.len()
    );
    let mut g = c.benchmark_group("10k-node tree");
    g.bench_function("load", |b| {
        b.iter(|| load_str(path, black_box(&xml), &LoadOptions::default()).unwrap())
    });
    g.bench_function("frame", |b| b.iter(|| Framed::new(black_box(&tree))));
    g.bench_function("load+frame", |b| {
        b.iter(|| {
            let t = load_str(path, black_box(&xml), &LoadOptions::default())
                .unwrap()
                .tree;
            Framed::new(&t).nodes.len()
        })
    });
    g.bench_function("write v4 XML", |b| {
        b.iter(|| btx::xml::to_v4_xml(black_box(&tree)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
