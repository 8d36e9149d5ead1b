#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(s) = btx::session::Session::parse(Path::new("fuzz.jsonl"), text) {
        common::exercise(&s);
    }
});
