//! Node numbering matches BehaviorTree.CPP's own (the uid tables of the
//! fixture logs), and v3 and v4 files give the same answers.

mod common;
use btx::explain::{han, TreeQuestion};
use btx::{Kind, Tree};
use common::*;

/// (uid, registration ID, instance name) rows of a decoded log's node table.
fn table(name: &str) -> Vec<(u32, String, String, usize)> {
    let text = std::fs::read_to_string(fixture(name)).unwrap();
    text.lines()
        .map(|l| {
            let rest = l.trim_start_matches('#').trim_start();
            let (uid, rest) = rest.split_once(' ').unwrap();
            let indent = rest.len() - rest.trim_start().len();
            let rest = rest.trim_start();
            let q = rest.find('\'').unwrap();
            let id = rest[..q].trim().to_string();
            let end = rest[q + 1..].find('\'').unwrap();
            let inst = rest[q + 1..q + 1 + end].to_string();
            (uid.parse().unwrap(), id, inst, indent)
        })
        .collect()
}

#[test]
fn v4_uids_match_btcpp_4_10() {
    for (tree, log) in [
        ("kitting-tree.v4.xml", "kitting_nominal.uids.txt"),
        ("taxi-domain-tree.v4.xml", "taxi_nominal.uids.txt"),
    ] {
        let t = load(&fixture(tree));
        let rows = table(log);
        assert_eq!(rows.len(), t.len(), "{tree}");
        for (uid, id, name, _) in rows {
            let n = t.node(uid);
            // The log names the element by registration ID ("SubTree" for subtrees).
            let ours = if n.kind == Kind::SubTree {
                "SubTree"
            } else {
                t.type_name(uid)
            };
            assert_eq!(ours, id, "{tree} #{uid}");
            assert_eq!(n.name, name, "{tree} #{uid}");
        }
    }
}

#[test]
fn v3_uids_names_and_depths_match_btcpp_3_8() {
    for (tree, log) in [
        ("kitting-tree.v3.xml", "kitting_nominal_v3.uids.txt"),
        ("taxi-domain-tree.v3.xml", "taxi_nominal_v3.uids.txt"),
    ] {
        let t = load(&fixture(tree));
        let rows = table(log);
        assert_eq!(rows.len(), t.len(), "{tree}");
        for (uid, id, name, indent) in rows {
            let n = t.node(uid);
            let ours = if n.kind == Kind::SubTree {
                "SubTree"
            } else {
                n.id.as_str()
            };
            assert_eq!(ours, id, "{tree} #{uid}");
            assert_eq!(n.name, name, "{tree} #{uid}");
            assert_eq!(n.depth as usize, (indent - 1) / 2, "{tree} #{uid}");
        }
    }
}

#[test]
fn shipped_trees_number_like_the_recorded_runs() {
    for (tree, fix) in [
        ("kitting.xml", "kitting-tree.v4.xml"),
        ("taxi.xml", "taxi-domain-tree.v4.xml"),
    ] {
        let ours = load(&shipped(tree));
        let theirs = load(&fixture(fix));
        assert_eq!(ours.len(), theirs.len());
        for u in 1..=ours.len() as u32 {
            assert_eq!(ours.node(u).kind, theirs.node(u).kind, "{tree} #{u}");
            assert_eq!(
                ours.node(u).children,
                theirs.node(u).children,
                "{tree} #{u}"
            );
        }
    }
}

/// Names of SubTrees that v4 takes from `name` where v3 used the ID.
fn renamed_subtrees(v3: &Tree, v4: &Tree) -> Vec<(String, String)> {
    (1..=v4.len() as u32)
        .filter(|&u| v4.node(u).kind == Kind::SubTree && v4.description(u) != v3.description(u))
        .map(|u| (v4.description(u).to_string(), v3.description(u).to_string()))
        .collect()
}

#[test]
fn v3_and_v4_answer_alike_for_every_leaf() {
    for (a, b, expect_renamed) in [
        ("kitting-tree.v3.xml", "kitting-tree.v4.xml", 2),
        ("taxi-domain-tree.v3.xml", "taxi-domain-tree.v4.xml", 0),
    ] {
        let v3 = load(&fixture(a));
        let v4 = load(&fixture(b));
        assert_eq!(v3.len(), v4.len());
        let renamed = renamed_subtrees(&v3, &v4);
        assert_eq!(renamed.len(), expect_renamed, "{renamed:?}");
        let mut compared = 0;
        for leaf in v3.leaves_below(Tree::ROOT) {
            for q in TreeQuestion::ALL {
                let x = han::answer(&v3, leaf, q);
                let y = han::answer(&v4, leaf, q);
                if x.text == y.text {
                    assert_eq!(x.nodes, y.nodes, "{a} #{leaf} {q:?}");
                    compared += 1;
                    continue;
                }
                // The one allowed difference: a v4 SubTree's own name.
                let mut renamed_text = y.text.clone();
                for (new, old) in &renamed {
                    renamed_text = renamed_text.replace(new.as_str(), old);
                }
                let in_renamed = y.nodes.iter().any(|&u| {
                    v4.node(u).kind == Kind::SubTree
                        && renamed.iter().any(|(n, _)| n == v4.description(u))
                });
                assert!(in_renamed, "{a} #{leaf} {q:?}: {} vs {}", x.text, y.text);
                if q != TreeQuestion::HowSubgoal {
                    assert_eq!(x.text, renamed_text, "{a} #{leaf} {q:?}");
                }
            }
        }
        assert!(compared > 0);
    }
}

#[test]
fn pick_by_path_description_id_and_uid() {
    let t = load(&fixture("kitting-tree.v4.xml"));
    assert_eq!(
        uid_of(&t, "go insert large gear/detect chuck/lift torso"),
        10
    );
    assert_eq!(uid_of(&t, "#10"), 10);
    assert_eq!(uid_of(&t, "go pick first screw/lift torso"), 37);
    // The outermost of a same-named line of descent: the subgoal.
    assert_eq!(uid_of(&t, "go insert large gear"), 2);
    // A leaf that repeats its parent's name is reached through it.
    assert_eq!(uid_of(&t, "detect chuck"), 9);
    assert_eq!(uid_of(&t, "detect chuck/detect chuck"), 12);
    // IDs, and any case.
    assert_eq!(uid_of(&t, "go insert large gear/look_at"), 18);
    assert_eq!(uid_of(&t, "Go Insert Large Gear/MOVE TO SEE CHUCK"), 6);
    // The display path of every node picks it back, unless two nodes share it.
    for u in 1..=t.len() as u32 {
        let path = t.display_path(u);
        let same: Vec<u32> = (1..=t.len() as u32)
            .filter(|&v| t.display_path(v) == path)
            .collect();
        if same.len() == 1 {
            assert_eq!(uid_of(&t, &path), u, "{path}");
        }
    }
}

#[test]
fn bad_picks_list_ranked_candidates() {
    let t = load(&fixture("kitting-tree.v4.xml"));
    match btx::pick::pick(&t, "lift torso") {
        Err(btx::pick::PickError::Ambiguous { candidates, .. }) => {
            assert_eq!(
                candidates.iter().map(|c| c.uid).collect::<Vec<_>>(),
                vec![10, 37, 64]
            );
        }
        other => panic!("{other:?}"),
    }
    match btx::pick::pick(&t, "lfit torso") {
        Err(btx::pick::PickError::Unknown { candidates, .. }) => {
            assert_eq!(t.description(candidates[0].uid), "lift torso");
        }
        other => panic!("{other:?}"),
    }
    assert!(btx::pick::pick(&t, "#999").is_err());
    assert!(btx::pick::pick(&t, "#0").is_err());
    assert!(btx::pick::pick(&t, "").is_err());
}
