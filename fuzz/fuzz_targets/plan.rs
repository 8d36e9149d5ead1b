#![no_main]
//! The plan parser, and a short run of the kitting tree with the plan.

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(plan) = btx::run::plan::Plan::parse(Path::new("fuzz.plan"), text) else {
        return;
    };
    let tree = btx::xml::load_str(
        Path::new("kitting.xml"),
        include_str!("../../trees/kitting.xml"),
        &Default::default(),
    )
    .expect("the shipped tree loads")
    .tree;
    let leaves = btx::run::plan::PlanLeaves::new(plan, &tree);
    let mut ex = btx::run::Executor::new(&tree, leaves, btx::run::RunOptions::default());
    for _ in 0..20 {
        if !matches!(ex.tick_once(), Ok(btx::run::Status::Running)) {
            break;
        }
    }
});
