//! Ranking of candidate strings for "did you mean" lists.

use fuzzy_matcher::skim::SkimMatcherV2;
use fuzzy_matcher::FuzzyMatcher;

/// Ranks `items` by how well their text matches `query`, best first. Items
/// that do not match at all come last, ordered by edit distance, so that a
/// typo still finds its target.
pub fn rank<T: Clone>(query: &str, items: &[(String, T)], limit: usize) -> Vec<T> {
    let matcher = SkimMatcherV2::default().ignore_case();
    let q = query.to_lowercase();
    let mut scored: Vec<(i64, usize, usize)> = items
        .iter()
        .enumerate()
        .map(|(i, (text, _))| {
            let fuzzy = matcher.fuzzy_match(text, query).unwrap_or(i64::MIN / 2);
            (fuzzy, edit_distance(&q, &text.to_lowercase()), i)
        })
        .collect();
    scored.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    scored
        .into_iter()
        .take(limit)
        .map(|(_, _, i)| items[i].1.clone())
        .collect()
}

/// The one of `known` that `id` misspells: the same but for case, or one
/// letter added, dropped or changed (in a name of 4 letters or more, so
/// that a short ID is not taken for another). The closest wins.
pub fn misspelt<'a>(id: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = id.to_lowercase();
    known
        .into_iter()
        .filter(|k| *k != id)
        .filter_map(|k| {
            let d = edit_distance(&lower, &k.to_lowercase());
            let close = d == 0 || (d == 1 && id.chars().count() >= 4);
            close.then_some((d, k))
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_misspelt_id_is_found_by_case_or_one_letter() {
        let known = ["Inverter", "Sequence", "Fallback", "FollowPath"];
        assert_eq!(misspelt("inverter", known), Some("Inverter"));
        assert_eq!(misspelt("Followpath", known), Some("FollowPath"));
        assert_eq!(misspelt("Sequense", known), Some("Sequence"));
        assert_eq!(misspelt("Fallbak", known), Some("Fallback"));
        assert_eq!(misspelt("Inverter", known), None);
        assert_eq!(misspelt("MyFallback", known), None);
        assert_eq!(misspelt("Seq", ["Sea"]), None);
    }

    #[test]
    fn fuzzy_matches_rank_first_and_typos_still_rank() {
        let items: Vec<(String, u32)> = ["lift torso", "look at table", "detect screw"]
            .iter()
            .enumerate()
            .map(|(i, s)| (s.to_string(), i as u32))
            .collect();
        assert_eq!(rank("lftrs", &items, 1), vec![0]);
        assert_eq!(rank("detect scerw", &items, 1), vec![2]);
    }
}
