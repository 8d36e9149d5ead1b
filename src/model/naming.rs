//! Naming rules that make Han et al.'s algorithms answer alike on v3 and v4
//! files (see the README, "Naming rules").

use super::{Kind, Tree, Uid};

/// IDs and names compare equal when they differ only in case or by the `_`
/// that v4 model names need in place of spaces (`lift_torso` vs `lift torso`).
fn same_words(a: &str, b: &str) -> bool {
    a.chars().count() == b.chars().count()
        && a.chars().zip(b.chars()).all(|(x, y)| {
            x.to_lowercase().eq(y.to_lowercase())
                || (matches!(x, '_' | ' ') && matches!(y, '_' | ' '))
        })
}

impl Tree {
    /// Han's `short_description`: the name, or the ID when the name is empty.
    pub fn description(&self, uid: Uid) -> &str {
        let n = self.node(uid);
        if n.name.is_empty() {
            &n.id
        } else {
            &n.name
        }
    }

    /// The node's description as words for a sentence: a name made of an
    /// ID (`ComputePathToPose`, `ClearGlobalCostmap-Context`, `go_home`)
    /// reads "compute path to pose", "clear global costmap (context)", "go
    /// home"; a name with spaces is kept as written (the papers' trees).
    pub fn spoken(&self, uid: Uid) -> String {
        words(self.description(uid))
    }

    /// Han's `has_name`. A SubTree always has one (its name, or its ID). Any
    /// other node has a name when its name is non-empty and is not just its
    /// type: v4 fills a missing name with the registration ID, and a v3 leaf
    /// with `name=""` converts to a v4 leaf named after its old ID.
    pub fn has_name(&self, uid: Uid) -> bool {
        let n = self.node(uid);
        if n.kind == Kind::SubTree {
            return true;
        }
        if n.name.is_empty() {
            return false;
        }
        if same_words(&n.name, &n.id) {
            return false;
        }
        // A built-in's other spellings (a v3 `SequenceStar` named "SequenceWithMemory").
        match n.builtin {
            Some(b) => {
                !(b.v4_name().is_some_and(|s| s == n.name)
                    || b.v3_name().is_some_and(|s| s == n.name))
            }
            None => true,
        }
    }

    /// BehaviorTree.CPP's path of a blackboard scope: its SubTree's name (or
    /// `ID::uid` when it has none) under its parent's path; `""` for the main tree.
    pub fn scope_path(&self, scope: super::ScopeId) -> String {
        let s = &self.scopes[scope];
        let (Some(parent), Some(st)) = (s.parent, s.subtree) else {
            return String::new();
        };
        let n = self.node(st);
        let seg = if n.name != n.id {
            n.name.clone()
        } else {
            format!("{}::{}", n.id, st)
        };
        let p = self.scope_path(parent);
        if p.is_empty() {
            seg
        } else {
            format!("{p}/{seg}")
        }
    }

    /// The name BehaviorTree.CPP's Groot2 publisher gives a scope's
    /// blackboard (`B`): the main tree's ID for the root, the SubTree
    /// instance's path (`_fullpath`) otherwise.
    pub fn blackboard_name(&self, scope: super::ScopeId) -> String {
        match self.scopes.get(scope).and_then(|s| s.parent) {
            None => self.main_tree.clone(),
            Some(_) => self.scope_path(scope),
        }
    }

    /// BehaviorTree.CPP's `fullPath`: the scope path, `/`, the name, with
    /// `::uid` appended when the name is the ID. Not unique.
    pub fn full_path(&self, uid: Uid) -> String {
        let n = self.node(uid);
        let name = if n.name == n.id {
            format!("{}::{}", n.name, uid)
        } else {
            n.name.clone()
        };
        let p = self.scope_path(n.scope);
        if p.is_empty() {
            name
        } else {
            format!("{p}/{name}")
        }
    }

    /// A path of descriptions from the root that `pick` resolves back to this
    /// node: nodes without a name are left out, and so is a node that repeats
    /// its parent's description.
    pub fn display_path(&self, uid: Uid) -> String {
        let mut chain: Vec<Uid> = self.ancestors(uid).collect();
        chain.reverse();
        let mut parts: Vec<&str> = Vec::new();
        for a in chain {
            if self.has_name(a) {
                let d = self.description(a);
                if parts.last() != Some(&d) {
                    parts.push(d);
                }
            }
        }
        parts.push(self.description(uid));
        parts.join("/")
    }

    /// `display_path` of every node, by uid − 1, built top-down: a deep tree
    /// costs the length of its paths, not depth × nodes ancestor walks.
    pub fn display_paths(&self) -> Vec<String> {
        use std::rc::Rc;
        // Per node: the named ancestors' joined descriptions, and the last one.
        let mut above: Vec<(Rc<str>, Option<Uid>)> = vec![(Rc::from(""), None); self.len()];
        let mut out = vec![String::new(); self.len()];
        let join = |base: &str, d: &str| {
            if base.is_empty() {
                d.to_string()
            } else {
                format!("{base}/{d}")
            }
        };
        for u in self.preorder() {
            let i = (u - 1) as usize;
            if let Some(p) = self.parent(u) {
                let (base, last) = above[(p - 1) as usize].clone();
                let d = self.description(p);
                above[i] = if self.has_name(p) && last.map(|l| self.description(l)) != Some(d) {
                    (Rc::from(join(&base, d)), Some(p))
                } else {
                    (base, last)
                };
            }
            out[i] = join(&above[i].0, self.description(u));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::same_words;

    #[test]
    fn all_paths_at_once_are_each_nodes_path() {
        let tree = crate::xml::load_file(
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/trees/kitting.xml")),
            &Default::default(),
        )
        .unwrap()
        .tree;
        let all = tree.display_paths();
        for n in &tree.nodes {
            assert_eq!(all[(n.uid - 1) as usize], tree.display_path(n.uid));
        }
    }

    #[test]
    fn underscores_match_spaces() {
        assert!(same_words("lift_torso", "lift torso"));
        assert!(same_words("ask", "ask"));
        assert!(same_words("Ask", "ask"));
        assert!(!same_words("ask", "asks"));
        assert!(!same_words("lift-torso", "lift torso"));
    }
}

/// An identifier as words (see `Tree::spoken`); text with a space, or with
/// nothing to split, is returned as it is.
pub fn words(name: &str) -> String {
    if name.contains(char::is_whitespace) || name.is_empty() {
        return name.to_string();
    }
    let (head, tail) = match name.split_once('-') {
        Some((h, t)) if !h.is_empty() && !t.is_empty() => (h, Some(t)),
        _ => (name, None),
    };
    let split = |s: &str| -> Vec<String> {
        let chars: Vec<char> = s.chars().collect();
        let mut out: Vec<String> = Vec::new();
        let mut cur = String::new();
        for (i, &c) in chars.iter().enumerate() {
            if c == '_' || c == '-' {
                if !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
                continue;
            }
            let prev = i.checked_sub(1).map(|j| chars[j]);
            let next = chars.get(i + 1).copied();
            let boundary = c.is_uppercase()
                && prev.is_some_and(|p| {
                    p.is_lowercase()
                        || p.is_ascii_digit()
                        || (p.is_uppercase() && next.is_some_and(char::is_lowercase))
                });
            if boundary && !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            cur.push(c);
        }
        if !cur.is_empty() {
            out.push(cur);
        }
        out.into_iter()
            .map(|w| {
                // An acronym stays as it is written (GPS, AMCL).
                if w.chars().count() > 1 && w.chars().all(|c| !c.is_lowercase()) {
                    w
                } else {
                    w.to_lowercase()
                }
            })
            .collect()
    };
    let head_words = split(head);
    if head_words.len() <= 1 && tail.is_none() && !name.contains('_') {
        return name.to_string();
    }
    let mut out = head_words.join(" ");
    if let Some(t) = tail {
        out.push_str(&format!(" ({})", split(t).join(" ")));
    }
    out
}

#[cfg(test)]
mod words_tests {
    use super::words;

    #[test]
    fn ids_read_as_words() {
        assert_eq!(words("ComputePathToPose"), "compute path to pose");
        assert_eq!(
            words("ClearGlobalCostmap-Context"),
            "clear global costmap (context)"
        );
        assert_eq!(words("go_home"), "go home");
        assert_eq!(words("IsGPSFixValid"), "is GPS fix valid");
        assert_eq!(words("look at chuck"), "look at chuck");
        assert_eq!(words("Sequence"), "Sequence");
        assert_eq!(words("FollowPath"), "follow path");
    }
}
