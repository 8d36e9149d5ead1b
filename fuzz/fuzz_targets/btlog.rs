#![no_main]
mod common;

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(s) = btx::logs::open_btlog(Path::new("fuzz.btlog"), data) {
        common::exercise(&s);
    }
});
