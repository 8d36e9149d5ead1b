//! The library reads one way (#43 item 5): each module of `src/lib.rs`
//! imports only the modules declared above it there, and the files of a
//! module import each other without a circle. A module's unit tests (from
//! its `#[cfg(test)]` on) may build their fixtures with any module.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The modules of the library, in the order `lib.rs` declares them.
fn stages() -> Vec<String> {
    std::fs::read_to_string(src().join("lib.rs"))
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("pub mod "))
        .map(|m| m.trim_end_matches(';').to_string())
        .collect()
}

/// Every `.rs` file below `dir`.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The code of a file up to its unit tests, without comments.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let text = text.split("#[cfg(test)]").next().unwrap_or_default();
    text.lines()
        .map(|l| l.split("//").next().unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The names that follow `prefix` in `code` (`crate::` → `session`, …).
fn after<'a>(code: &'a str, prefix: &str) -> Vec<&'a str> {
    code.match_indices(prefix)
        .filter(|(i, _)| {
            // `crate::x`, not `mycrate::x`.
            !code[..*i]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
        .map(|(i, _)| {
            let rest = &code[i + prefix.len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            &rest[..end]
        })
        .collect()
}

/// Upward imports: (file, the module it imports that is declared below its own).
fn upward(stages: &[String]) -> Vec<(String, String)> {
    let rank: BTreeMap<&str, usize> = stages
        .iter()
        .enumerate()
        .map(|(i, m)| (m.as_str(), i))
        .collect();
    let mut out = Vec::new();
    for f in files(&src()) {
        let rel = f.strip_prefix(src()).unwrap();
        let top = rel.components().next().unwrap().as_os_str();
        let top = top.to_str().unwrap().trim_end_matches(".rs");
        let Some(&own) = rank.get(top) else { continue };
        for m in after(&code(&f), "crate::") {
            if rank.get(m).is_some_and(|&r| r > own) {
                out.push((rel.display().to_string(), m.to_string()));
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// The words of `text` that are names (identifiers), each with where it
/// starts.
fn idents(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices().chain([(text.len(), ' ')]) {
        let part = c.is_alphanumeric() || c == '_';
        match (start, part) {
            (None, true) => start = Some(i),
            (Some(s), false) => {
                if !text[s..].starts_with(|c: char| c.is_ascii_digit()) {
                    out.push((s, &text[s..i]));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// The items a file declares at its top level (not inside an `impl`):
/// functions, types, traits, constants, statics and modules; `public`:
/// only those its siblings may take (`pub`, `pub(crate)`, `pub(super)`).
fn items(code: &str, public: bool) -> BTreeSet<String> {
    let kinds = [
        "fn", "struct", "enum", "trait", "const", "static", "type", "mod",
    ];
    code.lines()
        .filter(|l| !l.starts_with(char::is_whitespace))
        .filter_map(|l| {
            let mut w = l.split_whitespace();
            let mut first = w.next()?;
            if first.starts_with("pub") {
                first = w.next()?;
            } else if public {
                return None;
            }
            kinds.contains(&first).then(|| w.next()).flatten()
        })
        .map(|n| {
            n.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .next()
                .unwrap_or_default()
                .to_string()
        })
        .collect()
}

/// The names a file of a module's own folder takes from its parent
/// (`super::`): those it names (`super::{A, B}`, `super::A`), and, where
/// it takes them all (`use super::*`), every name it uses that it neither
/// declares nor imports from elsewhere: a type, or a name called, used as
/// a macro or as a path (a method, `.x(`, and a path's later part,
/// `a::x`, are no names of the parent's).
fn from_parent(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("super::") {
        let rest = &code[i + "super::".len()..];
        let group = match rest.strip_prefix('{') {
            Some(g) => &g[..g.find('}').unwrap_or(g.len())],
            None => {
                &rest[..rest
                    .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .unwrap_or(rest.len())]
            }
        };
        out.extend(idents(group).into_iter().map(|(_, n)| n.to_string()));
    }
    if code.contains("use super::*") {
        let mut own = items(code, false);
        // Each `use` to its `;`, however many lines it takes.
        for (i, _) in code.match_indices("use ") {
            let line_start = i == 0 || code[..i].ends_with('\n');
            let path = &code[i..code[i..].find(';').map_or(code.len(), |e| i + e)];
            if line_start && !path.starts_with("use super::") {
                own.extend(idents(path).into_iter().map(|(_, n)| n.to_string()));
            }
        }
        for (i, n) in idents(code) {
            let before = code[..i].chars().next_back();
            let next = code[i + n.len()..].trim_start().chars().next();
            let named =
                n.starts_with(|c: char| c.is_uppercase()) || matches!(next, Some('(' | '!' | ':'));
            if named && !matches!(before, Some('.' | ':')) && !own.contains(n) {
                out.insert(n.to_string());
            }
        }
    }
    out
}

/// Which of a module's files declares each name its files may take from
/// the module (`mod.rs`'s `use unit::…` lines count for `unit`), where
/// one file alone does.
fn declared_by(dir: &Path, units: &BTreeSet<String>) -> BTreeMap<String, String> {
    let mut by: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for u in units.iter().filter(|u| *u != "mod") {
        let face = [dir.join(format!("{u}.rs")), dir.join(u).join("mod.rs")];
        for f in face.iter().filter(|f| f.exists()) {
            for n in items(&code(f), true) {
                by.entry(n).or_default().insert(u.clone());
            }
        }
    }
    let face = dir.join("mod.rs");
    if face.exists() {
        for l in code(&face).lines() {
            let l = l
                .trim_start_matches("pub(crate) ")
                .trim_start_matches("pub ");
            let Some(path) = l.strip_prefix("use ") else {
                continue;
            };
            let names = idents(path);
            if let Some((_, u)) = names.first().filter(|(_, u)| units.contains(*u)) {
                for (_, n) in &names[1..] {
                    by.entry(n.to_string()).or_default().insert(u.to_string());
                }
            }
        }
    }
    by.into_iter()
        .filter(|(_, us)| us.len() == 1)
        .map(|(n, us)| (n, us.into_iter().next().unwrap()))
        .collect()
}

/// The circles among a module's files: each pair of its files (or folders)
/// that import each other, directly or through others. `module` is a
/// folder below `root` (`ask`, `ask/read`).
fn circles(root: &Path, module: &str) -> Vec<(String, String)> {
    let dir = root.join(module);
    let unit = |p: &Path| -> String {
        let rel = p.strip_prefix(&dir).unwrap();
        let first = rel.components().next().unwrap().as_os_str();
        first.to_str().unwrap().trim_end_matches(".rs").to_string()
    };
    let all = files(&dir);
    let units: BTreeSet<String> = all.iter().map(|p| unit(p)).collect();
    let declared = declared_by(&dir, &units);
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &all {
        let u = unit(f);
        // `mod.rs` is the module's face: it holds what its files share.
        if u == "mod" {
            continue;
        }
        let code = code(f);
        let within = format!("crate::{}::", module.replace('/', "::"));
        let mut named: Vec<String> = after(&code, &within)
            .into_iter()
            .map(str::to_string)
            .collect();
        // `super::x` is a sibling from a file of the module's own folder,
        // and so is a name one of them declares, taken through `super`.
        if f.parent() == Some(dir.as_path()) {
            for n in from_parent(&code) {
                match declared.get(&n) {
                    Some(by) if !units.contains(&n) => named.push(by.clone()),
                    _ => named.push(n),
                }
            }
        }
        for n in named {
            if n != u && units.contains(&n) && n != "mod" {
                edges.entry(u.clone()).or_default().insert(n);
            }
        }
    }
    let reaches = |from: &str, to: &str| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.to_string()];
        while let Some(x) = todo.pop() {
            if x == to {
                return true;
            }
            if seen.insert(x.clone()) {
                todo.extend(edges.get(&x).into_iter().flatten().cloned());
            }
        }
        false
    };
    let mut out = Vec::new();
    for (a, bs) in &edges {
        for b in bs {
            if a < b && reaches(b, a) {
                out.push((a.clone(), b.clone()));
            }
        }
    }
    out
}

#[test]
fn no_module_imports_one_declared_below_it() {
    let stages = stages();
    assert!(stages.len() > 15, "{stages:?}");
    let up = upward(&stages);
    assert!(up.is_empty(), "imports of a later stage: {up:#?}");
}

#[test]
fn the_files_of_a_module_import_each_other_one_way() {
    // Every folder of the library, the folders inside modules too.
    let mut found = Vec::new();
    let mut folders = 0;
    for f in files(&src()).iter().filter(|f| f.ends_with("mod.rs")) {
        let m = f.parent().unwrap().strip_prefix(src()).unwrap();
        let m = m.to_str().unwrap().to_string();
        folders += 1;
        for c in circles(&src(), &m) {
            found.push(format!("{m}: {} ↔ {}", c.0, c.1));
        }
    }
    assert!(folders > 20, "{folders}");
    assert!(found.is_empty(), "circles: {found:#?}");
}

#[test]
fn the_check_sees_a_circle_where_there_is_one() {
    // The explorer as it was before its components (#43 item 1): the app
    // took each pane's state, and each pane took the app.
    let root = tempfile::tempdir().unwrap();
    let tui = root.path().join("tui");
    std::fs::create_dir_all(tui.join("panes")).unwrap();
    let write = |p: &str, text: &str| std::fs::write(tui.join(p), text).unwrap();
    write("mod.rs", "pub mod app;\npub mod panes;\npub mod view;\n");
    write("app.rs", "use super::panes::timeline::TimelineState;\n");
    write("panes/timeline.rs", "use crate::tui::app::{App, Pane};\n");
    write("view.rs", "use super::app::App;\n");
    let found = circles(root.path(), "tui");
    assert_eq!(found, [("app".to_string(), "panes".to_string())]);
}

#[test]
fn the_check_sees_a_circle_through_the_modules_face() {
    // The BehaviorTree.CPP 3 watch as it was: `groot1` took the `Watch`
    // its parent re-exports, and `watch` took everything of its parent,
    // `groot1`'s constants among it. Neither names the other's file.
    let root = tempfile::tempdir().unwrap();
    let live = root.path().join("live");
    std::fs::create_dir_all(&live).unwrap();
    let write = |p: &str, text: &str| std::fs::write(live.join(p), text).unwrap();
    write("mod.rs", "pub mod groot1;\nmod watch;\npub use watch::*;\n");
    write(
        "groot1.rs",
        "use super::{Gap, Watch};\npub const POLL_WAIT: u64 = 20;\nimpl Watch {}\n",
    );
    write(
        "watch.rs",
        "use super::*;\npub struct Watch;\npub struct Gap;\nfn poll() { wait(groot1::POLL_WAIT); }\n",
    );
    assert_eq!(
        circles(root.path(), "live"),
        [("groot1".to_string(), "watch".to_string())]
    );
    // A method of the same name is no import: `.why(` is not `why`.
    write("groot1.rs", "pub fn why() {}\n");
    write("watch.rs", "use super::*;\nfn f(x: X) { x.why(); }\n");
    write("mod.rs", "pub mod groot1;\nmod watch;\nuse watch::f;\n");
    std::fs::write(live.join("groot1.rs"), "pub fn why() { super::f(); }\n").unwrap();
    assert!(circles(root.path(), "live").is_empty());
}

#[test]
fn the_check_sees_an_import_of_a_later_stage() {
    let mut stages = stages();
    // With `session` declared after `logs`, `logs` would import upward.
    let s = stages.iter().position(|m| m == "session").unwrap();
    let l = stages.iter().position(|m| m == "logs").unwrap();
    stages.swap(s, l);
    let up = upward(&stages);
    assert!(
        up.iter()
            .any(|(f, m)| f.starts_with("logs") && m == "session"),
        "{up:?}"
    );
}

/// The longest a function may be (#43 item 3): past it, it is split along
/// its ideas.
const FUNCTION_LINES_MAX: usize = 80;

/// A line's code without its comment, string and character literals, so
/// that only its own braces count.
fn braces_of(line: &str) -> String {
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '/' if chars.peek() == Some(&'/') => break,
            '"' => {
                while let Some(d) = chars.next() {
                    match d {
                        '\\' => {
                            chars.next();
                        }
                        '"' => break,
                        _ => {}
                    }
                }
            }
            // '{' and '\'' are characters; 'a is a lifetime.
            '\'' => {
                let rest: String = chars.clone().take(3).collect();
                if rest.starts_with('\\') {
                    chars.nth(2);
                } else if rest.chars().nth(1) == Some('\'') {
                    chars.nth(1);
                }
            }
            '{' | '}' => out.push(c),
            _ => {}
        }
    }
    out
}

/// Each function of `text` (up to its unit tests) longer than the most:
/// (its line, its name, its length in lines).
fn long_functions(text: &str) -> Vec<(usize, String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .iter()
        .position(|l| l.trim() == "#[cfg(test)]")
        .unwrap_or(lines.len());
    let mut out = Vec::new();
    for (i, l) in lines[..end].iter().enumerate() {
        let words: Vec<&str> = l.split_whitespace().collect();
        let Some(at) = words.iter().position(|w| *w == "fn") else {
            continue;
        };
        let header = words[..at]
            .iter()
            .all(|w| w.starts_with("pub") || ["const", "async", "unsafe"].contains(w));
        if !header || l.trim_end().ends_with(';') {
            continue;
        }
        let name = words
            .get(at + 1)
            .map_or("", |w| w.split(['(', '<']).next().unwrap_or(""));
        let mut depth = 0i32;
        let mut opened = false;
        for (j, body) in lines[i..end].iter().enumerate() {
            for b in braces_of(body).chars() {
                depth += if b == '{' { 1 } else { -1 };
                opened = true;
            }
            if opened && depth == 0 {
                if j + 1 > FUNCTION_LINES_MAX {
                    out.push((i + 1, name.to_string(), j + 1));
                }
                break;
            }
        }
    }
    out
}

#[test]
fn no_function_is_longer_than_eighty_lines() {
    let long: Vec<String> = files(&src())
        .iter()
        .flat_map(|p| {
            let text = std::fs::read_to_string(p).unwrap();
            long_functions(&text)
                .into_iter()
                .map(move |(line, name, n)| format!("{}:{line} {name}: {n} lines", p.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "split along their ideas:\n{}",
        long.join("\n")
    );
}

#[test]
fn the_length_check_counts_a_function_to_its_closing_brace() {
    let body: String = (0..81).map(|i| format!("    let x{i} = '{{';\n")).collect();
    let long = format!("pub(crate) fn long(a: &'static str) -> usize {{\n{body}    0\n}}\n");
    assert_eq!(long_functions(&long), [(1, "long".to_string(), 84)]);
    let short = "fn short() {\n    let s = \"}}}\"; // }\n}\n";
    assert!(long_functions(short).is_empty());
}
