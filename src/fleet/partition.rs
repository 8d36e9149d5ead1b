//! Where a run's rows go in a fleet's tables: its robot and day.

use crate::session::Session;
use std::path::Path;

/// Where a run's rows go: its robot and day.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Partition {
    pub robot: String,
    pub day: String,
}

impl Partition {
    /// The robot is the first directory below the one given that holds the
    /// file (`fleet/robot-7/run.btlog`), else the file's name without its
    /// extension (`fleet/127.0.0.1_1667.jsonl`, as `btx watch --out`
    /// names its robots); the day is the run's first transition's (UTC),
    /// else the file's last change. A bag of several robots' logs names
    /// each by its topic's namespace (`/robot2/behavior_tree_log`: `robot2`).
    pub fn of(file: &Path, given: &Path, topic: Option<&str>, s: &Session) -> Partition {
        let namespace = topic.map(crate::logs::rosbag::namespace);
        let below = file
            .strip_prefix(given)
            .ok()
            .filter(|rest| rest.components().count() > 1)
            .and_then(|rest| rest.components().next())
            .map(|c| c.as_os_str().to_string_lossy().into_owned());
        let robot = below.unwrap_or_else(|| {
            file.file_stem()
                .map_or("robot".into(), |s| s.to_string_lossy().into_owned())
        });
        let robot = match namespace {
            Some(ns) if !ns.is_empty() => ns.to_string(),
            _ => robot,
        };
        let us = s.span_us.map(|(first, _)| first).or_else(|| {
            let t = std::fs::metadata(file).and_then(|m| m.modified()).ok()?;
            let d = t.duration_since(std::time::UNIX_EPOCH).ok()?;
            Some(d.as_micros() as i64)
        });
        Partition {
            robot: safe(&robot),
            day: us.map_or("unknown".into(), |us| {
                crate::clock::utc(us)[..10].to_string()
            }),
        }
    }
}

/// A Hive partition value as Spark escapes it (`escapePathName`): the
/// characters a path or a partition cannot hold as `%XX`, so that two
/// robots whose names differ only by them stay two; DuckDB, Spark and
/// Trino read them back. An empty value is Hive's default partition.
fn safe(s: &str) -> String {
    if s.is_empty() {
        return "__HIVE_DEFAULT_PARTITION__".into();
    }
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if matches!(
            c,
            '\u{1}'
                ..='\u{1f}'
                    | '"'
                    | '#'
                    | '%'
                    | '\''
                    | '*'
                    | '/'
                    | ':'
                    | '='
                    | '?'
                    | '\\'
                    | '\u{7f}'
                    | '{'
                    | '['
                    | ']'
                    | '^'
        ) || c == '\0'
        {
            out.push_str(&format!("%{:02X}", c as u32));
        } else {
            out.push(c);
        }
    }
    // A name that starts with a dot is hidden from the readers.
    if out.starts_with('.') {
        out.replace_range(..1, "%2E");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::safe;

    #[test]
    fn partition_values_are_escaped_as_spark_escapes_them() {
        assert_eq!(safe("robot-7"), "robot-7");
        assert_eq!(safe("127.0.0.1_1667"), "127.0.0.1_1667");
        assert_eq!(safe("a:b"), "a%3Ab");
        assert_eq!(safe("a/b"), "a%2Fb");
        assert_eq!(safe("a%3Ab"), "a%253Ab");
        assert_ne!(safe("a:b"), safe("a?b"));
        assert_eq!(safe("line\nbreak"), "line%0Abreak");
        assert_eq!(safe(".hidden"), "%2Ehidden");
        assert_eq!(safe(""), "__HIVE_DEFAULT_PARTITION__");
        assert_eq!(safe("été"), "été");
    }
}
