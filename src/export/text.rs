use super::{draw, kind_label, port_label};
use crate::frame::{steps, Framed, Role};
use crate::model::{Kind, Tree, Uid};

/// The full tree: description, `[type #uid]`, then ports.
pub fn tree_text(tree: &Tree) -> String {
    let mut out = String::new();
    write_tree_text(tree, &mut |l| out.push_str(l));
    out
}

/// `tree_text` a line at a time.
pub fn write_tree_text(tree: &Tree, line: &mut dyn FnMut(&str)) {
    draw(
        Tree::ROOT as usize,
        |x| {
            tree.node(x as Uid)
                .children
                .iter()
                .map(|&c| c as usize)
                .collect()
        },
        |x| {
            let uid = x as Uid;
            let n = tree.node(uid);
            let mut s = format!(
                "{}  [{} #{}]",
                tree.description(uid),
                kind_label(tree, uid),
                uid
            );
            if !n.ports.is_empty() {
                let ports: Vec<String> = n.ports.iter().map(port_label).collect();
                s.push_str("  ");
                s.push_str(&ports.join(", "));
            }
            for (k, v) in &n.scripts {
                s.push_str(&format!("  {k}={v:?}"));
            }
            if !n.metadata.is_empty() {
                let m: Vec<String> = n
                    .metadata
                    .iter()
                    .map(|(k, v)| format!("{k}={v:?}"))
                    .collect();
                s.push_str(&format!("  (metadata: {})", m.join(", ")));
            }
            s
        },
        line,
    )
}

/// The framed tree, then the semantic sets.
pub fn framed_text(tree: &Tree, framed: &Framed) -> String {
    let mut out = String::new();
    draw(
        0,
        |i| framed.nodes[i].children.clone(),
        |i| {
            let f = &framed.nodes[i];
            let role = match f.role {
                Role::Goal => "goal",
                Role::Subgoal => "subgoal",
                Role::Step => "step",
                Role::Action if tree.node(f.uid).kind == Kind::Condition => "condition",
                Role::Action => "action",
            };
            let mut s = format!("{role}: {}  #{}", tree.description(f.uid), f.uid);
            if !f.merged.is_empty() {
                let m: Vec<String> = f.merged.iter().map(|u| format!("#{u}")).collect();
                s.push_str(&format!(" (with {})", m.join(" ")));
            }
            s
        },
        &mut |l| out.push_str(l),
    );
    let names = |v: &[Uid]| {
        v.iter()
            .map(|&u| tree.description(u))
            .collect::<Vec<_>>()
            .join(", ")
    };
    out.push('\n');
    out.push_str(&format!("goal: {}\n", tree.description(framed.goal)));
    // Empty sets are left out (a subgoal whose steps are all subgoals).
    if !framed.subgoals.is_empty() {
        out.push_str(&format!("subgoals: {}\n", names(&framed.subgoals)));
    }
    for &g in std::iter::once(&framed.goal).chain(&framed.subgoals) {
        let s = steps(tree, g);
        if !s.is_empty() {
            out.push_str(&format!(
                "steps of \"{}\": {}\n",
                tree.description(g),
                names(&s)
            ));
        }
    }
    out.push_str(&format!("actions: {}\n", framed.actions.len()));
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_framed_tree_leaves_out_empty_sets() {
        // The goal's only children are subgoals: it has no steps of its
        // own, and a tree of one leaf has no subgoals.
        let xml = r#"<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence name="goal">
            <SubTree ID="A" name="a"/><SubTree ID="B" name="b"/></Sequence></BehaviorTree>
            <BehaviorTree ID="A"><Action ID="x"/></BehaviorTree>
            <BehaviorTree ID="B"><Action ID="y"/></BehaviorTree></root>"#;
        let p = std::path::Path::new("t.xml");
        let tree = crate::xml::load_str(p, xml, &Default::default())
            .unwrap()
            .tree;
        let text = super::framed_text(&tree, &crate::frame::Framed::new(&tree));
        assert!(!text.lines().any(|l| l.ends_with(": ")), "{text}");
        assert!(text.contains("subgoals: "), "{text}");
        let one =
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Action ID="x"/></BehaviorTree></root>"#;
        let one = crate::xml::load_str(p, one, &Default::default())
            .unwrap()
            .tree;
        let text = super::framed_text(&one, &crate::frame::Framed::new(&one));
        assert!(!text.contains("subgoals"), "{text}");
    }
}
