#![no_main]
//! The explorer's keymap file.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = btx::tui::keymap::Keymap::parse(std::path::Path::new("keys.toml"), text);
});
