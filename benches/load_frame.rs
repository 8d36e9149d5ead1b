//! Loading and framing a generated 10,000-node tree.

use btx::frame::Framed;
use btx::xml::{load_str, LoadOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;

#[path = "support/generated.rs"]
mod generated;
use generated::generated_tree;

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
