#![no_main]
//! The domain-file loader (TOML and the rhai scripts, under the operation
//! budget), and a short run of the case-study tree with it.

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::Arc;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(d) = btx::run::domain::Domain::parse(Path::new("fuzz.domain.toml"), text) else {
        return;
    };
    let tree = btx::xml::load_str(
        Path::new("case-study.xml"),
        include_str!("../../trees/case-study.xml"),
        &Default::default(),
    )
    .expect("the shipped tree loads")
    .tree;
    let Ok(leaves) = btx::run::domain::DomainLeaves::new(Arc::new(d), &tree) else {
        return;
    };
    let mut ex = btx::run::Executor::new(&tree, leaves, btx::run::RunOptions::default());
    for _ in 0..5 {
        if !matches!(ex.tick_once(), Ok(btx::run::Status::Running)) {
            break;
        }
    }
});
