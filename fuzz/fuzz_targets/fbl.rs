#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(s) = btx::logs::open_fbl(Path::new("fuzz.fbl"), data) {
        common::exercise(&s);
    }
});
