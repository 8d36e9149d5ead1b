//! Naming rules that make Han et al.'s algorithms answer alike on v3 and v4
//! files (see docs/trees-and-runs.md, "Naming rules").

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

    /// The node as an answer names it: its name as the XML writes it, with
    /// its uid; where other nodes share the name, with its kind too ("the
    /// FollowPath action (#22)", "the FollowPath recovery node (#21)").
    pub fn told(&self, uid: Uid) -> String {
        let d = self.description(uid);
        let shared = self
            .nodes
            .iter()
            .any(|n| n.uid != uid && self.description(n.uid) == d);
        let n = self.node(uid);
        // An unnamed control node is its kind already ("RetryUntilSuccessful").
        if !shared || (d == n.id && !n.kind.is_leaf()) {
            return format!("{d} (#{uid})");
        }
        let kind = match n.kind {
            Kind::Action => "action".to_string(),
            Kind::Condition => "condition".to_string(),
            Kind::SubTree => "subtree".to_string(),
            _ => words(&n.id).to_lowercase(),
        };
        format!("the {d} {kind} (#{uid})")
    }

    /// The node as a sentence names it: as the tree's XML writes it
    /// (`FollowPath`, `ClearLocalCostmap-Context`, `look at chuck`), so
    /// that an answer's names are the ones the user greps for (#39 item 8).
    pub fn spoken(&self, uid: Uid) -> String {
        self.description(uid).to_string()
    }

    /// The node's description as words, for reading questions: a name made
    /// of an ID (`ComputePathToPose`, `ClearGlobalCostmap-Context`,
    /// `go_home`) reads "compute path to pose", "clear global costmap
    /// (context)", "go home"; a name with spaces is kept as written.
    pub fn words_of(&self, uid: Uid) -> String {
        words(self.description(uid))
    }

    /// What Han's answers say the node does, after "I" or "to". A name a
    /// person wrote as words is kept as written (the papers' trees); a name
    /// made of an ID keeps the ID, as the XML writes it: a condition is a
    /// check ("check GoalUpdated", under an Inverter "check that
    /// GlobalUpdatedGoal does not hold"), anything else a thing run ("run
    /// FollowPath"), so that no ID is used as a verb; a one-word ID that is
    /// a verb (`Spin`, `Wait`, the paper's `ask`) is the verb.
    pub fn deed(&self, uid: Uid) -> String {
        let d = self.description(uid);
        let s = self.words_of(uid);
        let n = self.node(uid);
        if d.contains(char::is_whitespace) || d.is_empty() {
            // Written as words: kept when it says a deed ("look at chuck");
            // a check or a thing said as words reads as a deed too ("battery
            // ok" → "check whether the battery is ok", "guarded patrol
            // step" → "run the guarded patrol step").
            let s = lower_first(&s);
            let first = s.split(' ').next().unwrap_or("");
            if d.is_empty() || VERBS.contains(&first) || first == "check" {
                return s;
            }
            if n.kind == super::Kind::Condition {
                let negated = n
                    .parent
                    .is_some_and(|p| self.node(p).builtin == Some(super::Builtin::Inverter));
                return check(&s, negated);
            }
            return as_deed(&s);
        }
        // One word that is the node's ID, as BehaviorTree.CPP registers it
        // (`Spin`, `Wait`): a word, not a proper name. A lowercase word is
        // kept as written (a paper's `ask`).
        let one_id_word = !s.contains(' ') && d == n.id;
        let lowercase = d.chars().all(|c| !c.is_uppercase());
        if one_id_word && (VERBS.contains(&lower_first(&s).as_str()) || (s == d && lowercase)) {
            return lower_first(&s);
        }
        // snake_case is words already (PlanSys2's `open_gripper`): a deed
        // when its first word is a verb.
        let first = s.split(' ').next().unwrap_or("");
        if d.chars()
            .all(|c| c.is_lowercase() || c.is_ascii_digit() || c == '_')
            && VERBS.contains(&first)
        {
            return s;
        }
        // A check written as an action ("IsDoorClosed" without a model
        // saying it is a condition) is still a check.
        let asks = AUX.contains(&s.split(' ').next().unwrap_or("")) && s.contains(' ');
        if n.kind == super::Kind::Condition || (n.kind.is_leaf() && asks) {
            let negated = n
                .parent
                .is_some_and(|p| self.node(p).builtin == Some(super::Builtin::Inverter));
            return if negated {
                format!("check that {d} does not hold")
            } else {
                format!("check {d}")
            };
        }
        format!("run {d}")
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
        // A control named after its kind in another case (`<Sequence
        // name="sequence">`) has no name of its own; a leaf named so was
        // named by a person (PlanSys2's `<Move name="move">`), since v4 fills
        // a missing name with the ID as written.
        let case_only = n.name != n.id && n.name.to_lowercase() == n.id.to_lowercase();
        if same_words(&n.name, &n.id) && !(n.kind.is_leaf() && case_only) {
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
        // Walked up once and joined once: building it parent by parent
        // copied the path at every level, cubic on a deep chain of SubTrees.
        let mut segs: Vec<std::borrow::Cow<str>> = Vec::new();
        let mut at = scope;
        while let Some((parent, seg)) = self.scope_step(at) {
            segs.push(seg);
            at = parent;
        }
        segs.reverse();
        segs.join("/")
    }

    /// A scope's parent and what the scope adds to its path (its SubTree's
    /// name, or `ID::uid` when the name is the ID); none for the root.
    fn scope_step(
        &self,
        scope: super::ScopeId,
    ) -> Option<(super::ScopeId, std::borrow::Cow<'_, str>)> {
        let (parent, st) = (self.scopes[scope].parent?, self.scopes[scope].subtree?);
        let n = self.node(st);
        Some((
            parent,
            if n.name != n.id {
                n.name.as_str().into()
            } else {
                format!("{}::{}", n.id, st).into()
            },
        ))
    }

    /// Every scope's path, each made from its parent's (for what asks for
    /// the paths of all the leaves: a walk up for each is quadratic in
    /// formatting on a deep chain).
    pub fn scope_paths(&self) -> Vec<String> {
        let mut paths: Vec<Option<String>> = vec![None; self.scopes.len()];
        for s in 0..self.scopes.len() {
            let path = match self.scope_step(s) {
                None => String::new(),
                Some((parent, seg)) => match &paths[parent] {
                    Some(p) if p.is_empty() => seg.into_owned(),
                    Some(p) => format!("{p}/{seg}"),
                    // A parent numbered after its child: walked up instead.
                    None => self.scope_path(s),
                },
            };
            paths[s] = Some(path);
        }
        paths.into_iter().map(Option::unwrap_or_default).collect()
    }

    /// Every scope's path as a `PathKey`, each from its parent's: what
    /// matches a leaf's fullPath to a plan's keys in time and memory linear
    /// in the tree, where the paths themselves grow with depth squared.
    pub fn scope_path_keys(&self) -> Vec<PathKey> {
        let mut keys: Vec<Option<PathKey>> = vec![None; self.scopes.len()];
        for s in 0..self.scopes.len() {
            let key = match self.scope_step(s) {
                None => PathKey::EMPTY,
                Some((parent, seg)) => match keys[parent] {
                    Some(p) => p.joined(&seg),
                    // A parent numbered after its child: walked up instead.
                    None => PathKey::of(&self.scope_path(s)),
                },
            };
            keys[s] = Some(key);
        }
        keys.into_iter().map(Option::unwrap_or_default).collect()
    }

    /// `full_path_in` as a `PathKey`, given its scope's.
    pub fn full_path_key(&self, scope: PathKey, uid: Uid) -> PathKey {
        let n = self.node(uid);
        if n.name == n.id {
            scope.joined(&n.name).then("::").then(&uid.to_string())
        } else {
            scope.joined(&n.name)
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
        self.full_path_in(&self.scope_path(self.node(uid).scope), uid)
    }

    /// `full_path`, given the path of the node's scope.
    pub fn full_path_in(&self, p: &str, uid: Uid) -> String {
        let n = self.node(uid);
        let name = if n.name == n.id {
            format!("{}::{}", n.name, uid)
        } else {
            n.name.clone()
        };
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
    fn a_full_paths_key_is_the_key_of_the_path_written_out() {
        // SubTrees named and not (`ID::uid`), nested, a name with a slash.
        let xml = r#"<root BTCPP_format="4" main_tree_to_execute="M">
            <BehaviorTree ID="M"><Sequence>
                <SubTree ID="A" name="first/a"/><SubTree ID="A"/><Action ID="Go" name="go"/>
            </Sequence></BehaviorTree>
            <BehaviorTree ID="A"><Sequence><SubTree ID="B"/><Action ID="Go"/></Sequence></BehaviorTree>
            <BehaviorTree ID="B"><Action ID="Go" name="leaf"/></BehaviorTree>
            <TreeNodesModel><Action ID="Go"/></TreeNodesModel></root>"#;
        let tree = crate::xml::load_str(std::path::Path::new("t.xml"), xml, &Default::default())
            .unwrap()
            .tree;
        let keys = tree.scope_path_keys();
        let mut distinct = std::collections::HashSet::new();
        for n in &tree.nodes {
            let written = tree.full_path(n.uid);
            let key = tree.full_path_key(keys[n.scope], n.uid);
            assert_eq!(key, super::PathKey::of(&written), "{written}");
            distinct.insert(key);
        }
        // Two paths differ where their strings do.
        let strings: std::collections::HashSet<String> =
            tree.nodes.iter().map(|n| tree.full_path(n.uid)).collect();
        assert_eq!(distinct.len(), strings.len());
        assert!(strings.contains("first/a/B::4/leaf"), "{strings:?}");
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

/// Verbs that names made of IDs start with, in robots' trees (Nav2's,
/// BehaviorTree.CPP's examples, MoveIt Pro's): such a name is read as what
/// the robot does.
const VERBS: &[&str] = &[
    "abort",
    "accept",
    "activate",
    "add",
    "adjust",
    "align",
    "append",
    "apply",
    "approach",
    "ask",
    "assign",
    "assist",
    "attach",
    "avoid",
    "back",
    "backup",
    "bring",
    "build",
    "calibrate",
    "call",
    "cancel",
    "capture",
    "carry",
    "change",
    "charge",
    "check",
    "choose",
    "clean",
    "clear",
    "close",
    "collect",
    "compute",
    "concatenate",
    "connect",
    "convert",
    "count",
    "create",
    "deactivate",
    "decrement",
    "deliver",
    "deploy",
    "detach",
    "detect",
    "disable",
    "disconnect",
    "dock",
    "do",
    "drive",
    "drop",
    "enable",
    "estimate",
    "execute",
    "explore",
    "extract",
    "fetch",
    "fill",
    "find",
    "finish",
    "follow",
    "get",
    "give",
    "go",
    "grab",
    "grasp",
    "handle",
    "hold",
    "home",
    "increment",
    "initialize",
    "insert",
    "inspect",
    "keep",
    "land",
    "launch",
    "lift",
    "load",
    "localize",
    "lock",
    "log",
    "look",
    "lower",
    "make",
    "map",
    "measure",
    "monitor",
    "mount",
    "move",
    "navigate",
    "notify",
    "open",
    "patrol",
    "pause",
    "pick",
    "place",
    "plan",
    "play",
    "point",
    "pop",
    "pour",
    "prepare",
    "press",
    "print",
    "publish",
    "pull",
    "push",
    "put",
    "raise",
    "reach",
    "read",
    "recalibrate",
    "receive",
    "record",
    "recover",
    "refine",
    "reinitialize",
    "release",
    "reload",
    "remove",
    "replan",
    "report",
    "request",
    "reset",
    "resume",
    "retreat",
    "retry",
    "return",
    "rotate",
    "run",
    "save",
    "say",
    "scan",
    "search",
    "select",
    "send",
    "set",
    "shut",
    "sleep",
    "slow",
    "smooth",
    "speak",
    "spin",
    "stack",
    "start",
    "stop",
    "store",
    "switch",
    "take",
    "takeoff",
    "teleop",
    "tell",
    "toggle",
    "track",
    "transform",
    "travel",
    "trigger",
    "truncate",
    "try",
    "turn",
    "undock",
    "unload",
    "unlock",
    "update",
    "upload",
    "use",
    "validate",
    "visit",
    "wait",
    "walk",
    "wander",
    "wave",
    "write",
];

/// Condition words that begin a question ("is path valid").
const AUX: &[&str] = &[
    "is", "are", "was", "were", "has", "have", "had", "can", "could", "would", "will", "should",
    "does", "do", "did",
];

/// Words that, after an auxiliary, say where the robot is ("is within
/// bounds"): the robot is the subject.
const PLACES: &[&str] = &[
    "at", "in", "inside", "near", "on", "within", "outside", "under",
];

/// Last words that say a state ("transform available").
const STATES: &[&str] = &[
    "active",
    "available",
    "blocked",
    "busy",
    "clear",
    "closed",
    "empty",
    "enabled",
    "free",
    "full",
    "high",
    "idle",
    "low",
    "nearby",
    "ok",
    "open",
    "present",
    "ready",
    "reachable",
    "safe",
    "stuck",
    "valid",
    "visible",
];

/// A sentence's first word as it reads inside a sentence ("Drive in a
/// square" → "drive in a square"); an acronym ("GPS fix") is kept.
fn lower_first(s: &str) -> String {
    let first = s.split(' ').next().unwrap_or("");
    let mut cs = first.chars();
    match (cs.next(), cs.clone().all(|c| c.is_lowercase())) {
        (Some(c), true) if c.is_uppercase() && first.chars().count() > 1 => {
            format!("{}{}", c.to_lowercase(), &s[c.len_utf8()..])
        }
        _ => s.to_string(),
    }
}

/// Words made of an ID as what the robot does: as they are when they start
/// with a verb, else "run the …" (see `Tree::deed`).
pub fn as_deed(s: &str) -> String {
    let first = s.split(' ').next().unwrap_or("");
    // A name that ends in a kind of node names the node, not a deed
    // (Nav2's `ComputeRouteRateController`).
    let last = s.rsplit(' ').next().unwrap_or("");
    let names_a_node = s.contains(' ')
        && matches!(
            last,
            "controller"
                | "sequence"
                | "fallback"
                | "selector"
                | "decorator"
                | "recovery"
                | "recoveries"
                | "server"
                | "client"
                | "node"
                | "tree"
                | "subtree"
                | "behavior"
                | "behaviour"
        );
    if VERBS.contains(&first) && !names_a_node {
        s.to_string()
    } else {
        format!("run the {s}")
    }
}

/// A deed's first word as its -ing form ("clear local costmap" → "clearing
/// local costmap", "run the …" → "running the …").
pub fn gerund(deed: &str) -> String {
    let (first, rest) = deed.split_once(' ').unwrap_or((deed, ""));
    let chars: Vec<char> = first.chars().collect();
    let vowel = |c: char| "aeiou".contains(c);
    let ing = match chars.as_slice() {
        [.., 'i', 'e'] => format!("{}ying", &first[..first.len() - 2]),
        [.., a, 'e'] if *a != 'e' && first.len() > 2 => format!("{}ing", &first[..first.len() - 1]),
        // One syllable ending consonant-vowel-consonant doubles it (run,
        // stop, spin, drop); w, x and y never double.
        [.., c1, v, c2]
            if !vowel(*c1)
                && vowel(*v)
                && !vowel(*c2)
                && !"wxy".contains(*c2)
                && chars.iter().filter(|c| vowel(**c)).count() == 1 =>
        {
            format!("{first}{c2}ing")
        }
        _ => format!("{first}ing"),
    };
    if rest.is_empty() {
        ing
    } else {
        format!("{ing} {rest}")
    }
}

/// A condition's words as a check; see `Tree::deed`.
fn check(s: &str, negated: bool) -> String {
    let (core, tail) = match s.find(" (") {
        Some(i) if s.ends_with(')') => (&s[..i], &s[i..]),
        _ => (s, ""),
    };
    let w: Vec<&str> = core.split(' ').collect();
    let not = if negated { " not" } else { "" };
    let the = |subject: &[&str]| {
        let det = if matches!(
            subject.first(),
            Some(&("a" | "an" | "the" | "my" | "any" | "some"))
        ) {
            ""
        } else {
            "the "
        };
        format!("{det}{}", subject.join(" "))
    };
    let clause = match w.as_slice() {
        [aux, rest @ ..] if AUX.contains(aux) && !rest.is_empty() => {
            if rest.len() == 1 || PLACES.contains(&rest[0]) {
                let aux = match *aux {
                    "is" | "are" => "am",
                    "has" => "have",
                    "does" => "do",
                    "were" => "was",
                    a => a,
                };
                Some(format!("I {aux}{not} {}", rest.join(" ")))
            } else {
                let (subject, pred) = rest.split_at(rest.len() - 1);
                Some(format!("{} {aux}{not} {}", the(subject), pred[0]))
            }
        }
        [subject @ .., last] if !subject.is_empty() && last.len() > 3 && last.ends_with("ed") => {
            Some(format!("{} was{not} {last}", the(subject)))
        }
        [subject @ .., last] if !subject.is_empty() && STATES.contains(last) => {
            Some(format!("{} is{not} {last}", the(subject)))
        }
        _ => None,
    };
    match (clause, negated) {
        (Some(c), false) => format!("check whether {c}{tail}"),
        (Some(c), true) => format!("check that {c}{tail}"),
        (None, false) => format!("check {s}"),
        (None, true) => format!("check that {s} does not hold"),
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
mod deed_tests {
    fn tree(body: &str) -> crate::model::Tree {
        let xml = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="M">{body}</BehaviorTree><TreeNodesModel><Condition ID="GoalUpdated"/><Condition ID="IsPathValid"/><Condition ID="IsStuck"/><Condition ID="WouldAControllerRecoveryHelp"/><Condition ID="TransformAvailable"/><Condition ID="PathExpiringTimer"/><Condition ID="IsWithinPathTrackingBounds"/></TreeNodesModel></root>"#
        );
        crate::xml::load_str(std::path::Path::new("t.xml"), &xml, &Default::default())
            .unwrap()
            .tree
    }

    #[test]
    fn names_made_of_ids_read_as_deeds_and_checks() {
        let t = tree(
            r#"<Sequence name="go home"><ComputePathToPose/><ControllerSelector/><Spin/><GoalUpdated/><Inverter><GoalUpdated/></Inverter><IsPathValid/><IsStuck/><WouldAControllerRecoveryHelp/><TransformAvailable/><Inverter><PathExpiringTimer/></Inverter><IsWithinPathTrackingBounds/><PathExpiringTimer/><Action ID="ask" name="ask"/></Sequence>"#,
        );
        let deeds: Vec<String> = (1..=t.len() as u32)
            .filter(|&u| t.node(u).kind.is_leaf())
            .map(|u| t.deed(u))
            .collect();
        assert_eq!(
            deeds,
            [
                "run ComputePathToPose",
                "run ControllerSelector",
                "spin",
                "check GoalUpdated",
                "check that GoalUpdated does not hold",
                "check IsPathValid",
                "check IsStuck",
                "check WouldAControllerRecoveryHelp",
                "check TransformAvailable",
                "check that PathExpiringTimer does not hold",
                "check IsWithinPathTrackingBounds",
                "check PathExpiringTimer",
                "ask",
            ]
        );
        // A name written as words is the person's, inside a sentence.
        assert_eq!(t.deed(1), "go home");
        let t = tree(r#"<Sequence name="Drive in a square"><Action ID="GPS fix"/></Sequence>"#);
        assert_eq!(t.deed(1), "drive in a square");
        // Words that are no deed are a thing run, never a verb.
        assert_eq!(t.deed(2), "run the GPS fix");
        // A name that ends in a kind of node names the node.
        let t = tree(
            r#"<RateController name="ComputeRouteRateController" hz="1"><ComputeRoute name="ComputeRoute"/></RateController>"#,
        );
        assert_eq!(t.deed(1), "run ComputeRouteRateController");
        assert_eq!(t.deed(2), "run ComputeRoute");
        // snake_case that starts with a verb is a deed in words.
        let t = tree(r#"<Sequence name="s"><open_gripper/><gripper_state/></Sequence>"#);
        assert_eq!(
            (t.deed(2), t.deed(3)),
            ("open gripper".into(), "run gripper_state".into())
        );
    }

    #[test]
    fn a_leaf_named_after_its_id_in_another_case_has_a_name() {
        let t = tree(r#"<Sequence name="sequence"><Move name="move"/><Move/></Sequence>"#);
        assert!(!t.has_name(1), "a control named after its kind");
        assert!(t.has_name(2), "PlanSys2's <Move name=\"move\">");
        assert!(!t.has_name(3), "v4 names it after its ID");
    }

    #[test]
    fn deeds_take_ing() {
        use super::gerund;
        assert_eq!(
            gerund("run the recovery fallback"),
            "running the recovery fallback"
        );
        assert_eq!(
            gerund("clear local costmap (context)"),
            "clearing local costmap (context)"
        );
        assert_eq!(gerund("spin"), "spinning");
        assert_eq!(gerund("wait"), "waiting");
        assert_eq!(gerund("back up"), "backing up");
        assert_eq!(gerund("retreat arm"), "retreating arm");
        assert_eq!(gerund("compute path"), "computing path");
        assert_eq!(gerund("tie knot"), "tying knot");
        assert_eq!(
            gerund("check whether I am stuck"),
            "checking whether I am stuck"
        );
    }
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

/// A path's fingerprint: two polynomial hashes modulo 2^61 − 1 and the
/// length, extended a piece at a time, so equal paths have equal keys and
/// different ones collide with odds near 2^-120, without the path being
/// written out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PathKey(u64, u64, usize);

impl PathKey {
    pub const EMPTY: PathKey = PathKey(0, 0, 0);
    const P: u64 = (1 << 61) - 1;

    pub fn of(s: &str) -> PathKey {
        PathKey::EMPTY.then(s)
    }

    /// The key of this path with `s` appended.
    pub fn then(self, s: &str) -> PathKey {
        let step = |h: u64, base: u64, b: u8| {
            ((u128::from(h) * u128::from(base) + u128::from(b) + 1) % u128::from(Self::P)) as u64
        };
        s.bytes().fold(self, |k, b| {
            PathKey(step(k.0, 1_000_003, b), step(k.1, 998_244_353, b), k.2 + 1)
        })
    }

    /// The key of `self/seg` (of `seg` alone when this path is empty).
    pub fn joined(self, seg: &str) -> PathKey {
        if self.2 == 0 {
            self.then(seg)
        } else {
            self.then("/").then(seg)
        }
    }
}
