//! The index's tests, and its tables as text for the tests of the logs
//! it indexes.

use super::*;

impl Index {
    /// Every table, as text: two indexes of one run compared.
    pub(crate) fn tables(&self) -> String {
        let mut attempts: Vec<_> = self.attempts.iter().collect();
        attempts.sort_by_key(|(u, _)| **u);
        format!(
            "{:?}\n{:?}\n{:?}\n{:?}\n{:?} {}\n{attempts:?}\n{:?}",
            self.transitions,
            self.tick_end,
            self.by_node,
            self.completed,
            self.current,
            self.current_now,
            self.resyncs
        )
    }
}

#[test]
fn moments_count_from_the_end_of_a_run() {
    let m = |tick, step| Moment { tick, step };
    assert_eq!(Moment::parse_within("last", 54).unwrap(), m(54, None));
    assert_eq!(Moment::parse_within("END", 54).unwrap(), m(54, None));
    assert_eq!(Moment::parse_within("-1", 54).unwrap(), m(54, None));
    assert_eq!(Moment::parse_within("-3:2", 54).unwrap(), m(52, Some(2)));
    assert_eq!(Moment::parse_within("7:1", 54).unwrap(), m(7, Some(1)));
    assert_eq!(
        Moment::parse_within("-55", 54).unwrap_err(),
        "\"-55\": the run has 54 ticks"
    );
    assert!(Moment::parse_within("-0", 54).is_err());
    assert!(Moment::parse_within("-x", 54)
        .unwrap_err()
        .contains("last, end or -N"));
}

#[test]
fn moments_parse() {
    assert_eq!(
        Moment::parse("10").unwrap(),
        Moment {
            tick: 10,
            step: None
        }
    );
    assert_eq!(
        Moment::parse(" 10:3 ").unwrap(),
        Moment {
            tick: 10,
            step: Some(3)
        }
    );
    assert!(Moment::parse("0").is_err());
    assert!(Moment::parse("a:1").is_err());
    assert!(Moment::parse("1:").is_err());
}

#[test]
fn changes_answer_by_binary_search() {
    let mut c = Changes::default();
    c.push(3, 'a');
    c.push(7, 'b');
    c.push(7, 'c');
    assert_eq!(c.at(2), None);
    assert_eq!(c.at(3), Some(&'a'));
    assert_eq!(c.at(6), Some(&'a'));
    assert_eq!(c.at(100), Some(&'c'));
}
