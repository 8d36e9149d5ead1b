//! Reading a question (#38): the words, the moment, the nodes as spans of
//! the tree's vocabulary, and the intent, on the largest Nav2 navigator of
//! the corpus (navigate_on_route_graph_w_recovery.xml, 49 nodes), with its
//! vocabulary made for each question as `btx ask` makes it.

use btx::ask::read::{read, Vocabulary};
use btx::xml::{load_file, LoadOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;

fn questions(c: &mut Criterion) {
    let opts = LoadOptions {
        models: vec!["tests/fixtures/realworld/nav2/nav2_tree_nodes.main.xml".into()],
        ..LoadOptions::default()
    };
    let tree = load_file(
        Path::new("tests/fixtures/realworld/nav2/navigate_on_route_graph_w_recovery.xml"),
        &opts,
    )
    .unwrap()
    .tree;
    let mut g = c.benchmark_group("read a question");
    for q in [
        "why didnt the robot clear the local costmap after the controller failed at tick 7?",
        "how often did follow path fail",
        "whats it doing atm",
    ] {
        g.bench_function(q, |b| {
            b.iter(|| {
                let v = Vocabulary::new(&tree);
                black_box(read(&v, &tree, q))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, questions);
criterion_main!(benches);
