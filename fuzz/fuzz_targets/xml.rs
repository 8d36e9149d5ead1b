#![no_main]
//! The XML loader, v3 and v4, with includes served from an in-memory file
//! set (the input names its files: `<include path="a.xml"/>` reads the
//! part of the input after a `\0a.xml\0` marker) — here through a real
//! temporary directory, since the loader reads included files from disk.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // "main\0name\0body\0name\0body…": the main file, then included files.
    let mut parts = text.split('\0');
    let main = parts.next().unwrap_or("");
    // tmpfs when there is one: a disk's stalls would read as 1 s timeouts.
    let base = if std::path::Path::new("/dev/shm").is_dir() {
        std::path::PathBuf::from("/dev/shm")
    } else {
        std::env::temp_dir()
    };
    let dir = base.join(format!("btx-fuzz-xml-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let mut written = Vec::new();
    while let (Some(name), Some(body)) = (parts.next(), parts.next()) {
        if name.is_empty() || name.contains('/') || name.contains("..") || name.len() > 40 {
            continue;
        }
        let p = dir.join(name);
        if std::fs::write(&p, body).is_ok() {
            written.push(p);
        }
    }
    let main_path = dir.join("main.xml");
    for version in [None, Some(btx::Version::V3), Some(btx::Version::V4)] {
        let opts = btx::xml::LoadOptions {
            version,
            ..Default::default()
        };
        if let Ok(l) = btx::xml::load_str(&main_path, main, &opts) {
            let t = l.tree;
            let _ = btx::xml::to_v4_xml(&t);
            let _ = btx::frame::Framed::new(&t);
            if t.len() > 1 {
                let _ = btx::pick::pick(&t, "#2");
            }
        }
    }
    for p in written {
        let _ = std::fs::remove_file(p);
    }
});
