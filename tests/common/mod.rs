#![allow(dead_code)]

use btx::xml::{load_file, LoadOptions};
use btx::Tree;
use std::path::{Path, PathBuf};

pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

pub fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("trees")
        .join(name)
}

pub fn load(path: &Path) -> Tree {
    match load_file(path, &LoadOptions::default()) {
        Ok(l) => l.tree,
        Err(e) => panic!("{e}"),
    }
}

pub fn uid_of(tree: &Tree, pick: &str) -> btx::Uid {
    btx::pick::pick(tree, pick).unwrap_or_else(|e| panic!("{e}"))
}
