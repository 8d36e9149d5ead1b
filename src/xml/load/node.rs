//! One element made a node: its ID, kind and built-in behaviour, its
//! instance name, ports, scripts and metadata, and BehaviorTree.CPP's
//! checks of its children.

use super::*;

impl Loader {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn make_node(
        &mut self,
        version: Version,
        file: FileId,
        el: &Element,
        uid: Uid,
        parent: Option<Uid>,
        scope: ScopeId,
        depth: u32,
    ) -> Result<Node, Located> {
        let tag = el.tag.as_str();
        let explicit_kind = explicit_kind(tag);
        let id = self.node_id(file, el, explicit_kind)?;
        // A bare element named after a <BehaviorTree> calls it as a SubTree
        // when no node is registered under that name (createNodeFromXML
        // looks at the factory's builders before the tree roots).
        let called = explicit_kind.is_none()
            && builtins::lookup(&id).is_none()
            && !self.models.contains_key(&id)
            && self.tree_ids.contains(&id);

        // What kind of node, and which built-in behaviour.
        let (kind, builtin, guessed) = self.kind_of(version, file, el, &id, explicit_kind, called);
        if builtin.is_none() {
            self.check_declared_kind(file, el, &id, explicit_kind, kind);
        }
        self.check_children(version, file, el, &id, kind, builtin)?;

        let name = instance_name(version, el, kind, &id);

        // Ports, scripts and subtree flags.
        let (mut ports, scripts, metadata) =
            self.attributes(version, file, el, uid, &id, kind, builtin)?;
        self.subtree_defaults(file, el, &id, kind, &mut ports)?;
        Ok(Node {
            uid,
            kind,
            id,
            name,
            builtin,
            ports,
            scripts,
            metadata,
            kind_declared: !guessed,
            parent,
            children: Vec::with_capacity(el.children.len()),
            scope,
            opens_scope: None,
            depth,
            origin: Origin {
                file,
                start: el.start,
                end: el.end,
            },
        })
    }

    /// A node's ID: the `ID` attribute of an explicit element (`<Action
    /// ID="…">`), else the tag of the compact form.
    fn node_id(
        &mut self,
        file: FileId,
        el: &Element,
        explicit_kind: Option<Kind>,
    ) -> Result<String, Located> {
        let tag = el.tag.as_str();
        Ok(match explicit_kind {
            Some(_) => match el.attr("ID") {
                Some(id) => id.to_string(),
                None => return Err(self.err(file, el, format!("<{tag}> needs an ID attribute"))),
            },
            None => {
                if matches!(tag, "root" | "BehaviorTree" | "TreeNodesModel" | "include") {
                    return Err(self.err(file, el, format!("<{tag}> cannot be used as a node")));
                }
                if el.attr("ID").is_some() {
                    self.warn(
                        file,
                        el,
                        format!("<{tag}> is in compact form, where ID is not allowed; ignored"),
                    );
                }
                tag.to_string()
            }
        })
    }

    /// A node's attributes: its ports (with their directions, from its
    /// model or the built-in's), its scripts and the editors' metadata.
    #[allow(clippy::too_many_arguments)]
    fn attributes(
        &self,
        version: Version,
        file: FileId,
        el: &Element,
        uid: Uid,
        id: &str,
        kind: Kind,
        builtin: Option<Builtin>,
    ) -> Result<Attributes, Located> {
        let old_style_subtree = el.tag == "SubTree" && version == Version::V3;
        let model_ports: &[PortModel] = self.models.get(id).map_or(&[], |m| &m.ports);
        let mut ports = Vec::new();
        let mut scripts = Vec::new();
        let mut metadata = Vec::new();
        for a in &el.attrs {
            let k = a.key.as_str();
            if k == "_uid" && a.value.trim().parse::<Uid>().ok() != Some(uid) {
                let msg = format!("this node is _uid=\"{}\" in the file, but BehaviorTree.CPP's numbering gives it {uid}", a.value);
                return Err(self.err(file, el, msg));
            }
            if matches!(k, "ID" | "name" | "_uid" | "_fullpath") {
                continue;
            }
            if SCRIPT_ATTRS.contains(&k) {
                scripts.push((k.to_string(), a.value.clone()));
                continue;
            }
            if kind == Kind::SubTree
                && matches!(k, "_autoremap" | "__autoremap" | "__shared_blackboard")
            {
                continue;
            }
            // Groot2 and other editors keep `_collapsed`, `_description`
            // and the like on nodes; BehaviorTree.CPP 4 reads no port from
            // them (`xml_parsing.cpp` skips the `_`-prefixed attributes it
            // does not know).
            if k.starts_with('_') && !k.starts_with("__") {
                metadata.push((k.to_string(), a.value.clone()));
                continue;
            }
            let value = if old_style_subtree {
                // v3 <SubTree inner="outer"/>: values are key names, without braces.
                match PortValue::parse(k, &a.value) {
                    PortValue::Literal(s) => PortValue::Key(s),
                    other => other,
                }
            } else {
                PortValue::parse(k, &a.value)
            };
            let direction = model_ports
                .iter()
                .find(|p| p.name == k)
                .map(|p| p.direction)
                .or_else(|| {
                    builtin
                        .filter(|b| *b != Builtin::SubTree)
                        .and_then(|b| b.spec().ports.iter().find(|p| p.0 == k).map(|p| p.1))
                });
            ports.push(Port {
                name: k.to_string(),
                value,
                direction,
            });
        }
        Ok((ports, scripts, metadata))
    }

    /// A SubTree's ports its instance does not remap, from its model.
    fn subtree_defaults(
        &self,
        file: FileId,
        el: &Element,
        id: &str,
        kind: Kind,
        ports: &mut Vec<Port>,
    ) -> Result<(), Located> {
        // A SubTree's model (the only models BehaviorTree.CPP 4's executor
        // reads): a port the instance does not remap takes the model's
        // default, and without one the tree is refused (`loadSubtreeModel`
        // and the check in `recursivelyCreateSubtree`, xml_parsing.cpp).
        if let Some(m) = self
            .models
            .get(id)
            .filter(|m| kind == Kind::SubTree && m.kind == Kind::SubTree)
        {
            for pm in &m.ports {
                if ports.iter().any(|p| p.name == pm.name) {
                    continue;
                }
                let Some(d) = &pm.default else {
                    return Err(self.err(
                        file,
                        el,
                        format!(
                            "the <TreeNodesModel> of SubTree \"{id}\" declares the port \"{}\" with no default, and this SubTree does not remap it; BehaviorTree.CPP refuses the tree",
                            pm.name
                        ),
                    ).with_help(format!("give it: {}=\"{{{}}}\" or a value, or a default in the model", pm.name, pm.name)));
                };
                ports.push(Port {
                    name: pm.name.clone(),
                    value: PortValue::parse(&pm.name, d),
                    direction: Some(pm.direction),
                });
            }
        }
        Ok(())
    }

    /// What kind of node `id` is, and which built-in behaviour: a SubTree
    /// called, a built-in (a name of the other version said), a model's
    /// declared kind, the element's, or a kind guessed from the children
    /// (counted, to be said once per ID). Whether it was guessed.
    #[allow(clippy::too_many_arguments)]
    fn kind_of(
        &mut self,
        version: Version,
        file: FileId,
        el: &Element,
        id: &str,
        explicit_kind: Option<Kind>,
        called: bool,
    ) -> (Kind, Option<Builtin>, bool) {
        let mut guessed = false;
        let (kind, builtin) = if explicit_kind == Some(Kind::SubTree) || called {
            (Kind::SubTree, Some(Builtin::SubTree))
        } else if let Some(spec) = builtins::lookup(id) {
            match (spec.availability, version) {
                (Availability::V3Only, Version::V4) => {
                    let msg = match spec.builtin.v4_name() {
                        Some(v4) => format!("\"{id}\" is a BehaviorTree.CPP 3 name; read as {v4}"),
                        None => format!("\"{id}\" exists only in BehaviorTree.CPP 3"),
                    };
                    self.warn(file, el, msg);
                }
                (Availability::V4Only, Version::V3) => {
                    self.warn(
                        file,
                        el,
                        format!("\"{id}\" does not exist in BehaviorTree.CPP 3"),
                    );
                }
                _ => {}
            }
            (spec.kind, Some(spec.builtin))
        } else if let Some(m) = self.models.get(id) {
            (m.kind, None)
        } else if let Some(k) = explicit_kind {
            (k, None)
        } else {
            guessed = true;
            let (k, what) = match el.children.len() {
                0 => (Kind::Action, "an Action"),
                1 => (Kind::Decorator, "a Decorator"),
                _ => (Kind::Control, "a Control"),
            };
            match self.unknown_at.get(id) {
                Some(&i) => self.unknown[i].4 += 1,
                None => {
                    self.unknown_at.insert(id.to_string(), self.unknown.len());
                    self.unknown.push((id.to_string(), file, el.start, what, 1));
                }
            }
            (k, None)
        };
        (kind, builtin, guessed)
    }

    /// A node that is not built in keeps one kind per ID, as
    /// BehaviorTree.CPP registers it: an element or a use elsewhere that
    /// says another is warned of.
    fn check_declared_kind(
        &mut self,
        file: FileId,
        el: &Element,
        id: &str,
        explicit_kind: Option<Kind>,
        kind: Kind,
    ) {
        if let Some(k) = explicit_kind.filter(|k| *k != kind) {
            let msg = format!(
                "<{}> names \"{id}\", which <TreeNodesModel> declares {}; read as {}",
                k.as_str(),
                a_kind(kind),
                a_kind(kind)
            );
            self.warn(file, el, msg);
        }
        let (first, ffile, fstart) = *self
            .kinds
            .entry(id.to_string())
            .or_insert((kind, file, el.start));
        if first != kind {
            let f = &self.files[ffile];
            let (line, _) = crate::source::line_col(&f.text, fstart);
            let msg = format!(
                "\"{id}\" is used as {} here and as {} at {}:{line}; BehaviorTree.CPP registers one kind per ID",
                a_kind(kind),
                a_kind(first),
                f.path.display()
            );
            self.warn(file, el, msg);
        }
    }

    /// Child counts, as BehaviorTree.CPP verifies them, and its other
    /// checks of children.
    #[allow(clippy::too_many_arguments)]
    fn check_children(
        &self,
        version: Version,
        file: FileId,
        el: &Element,
        id: &str,
        kind: Kind,
        builtin: Option<Builtin>,
    ) -> Result<(), Located> {
        // Child counts, as BehaviorTree.CPP verifies them. Version 3's
        // VerifyXML asks for a child only of Sequence, SequenceStar, Fallback
        // and FallbackStar (by element name, xml_parsing.cpp of 3.8): a
        // ManualSelector or a custom control node may have none.
        let n = el.children.len();
        let v3_childless = version == Version::V3
            && kind == Kind::Control
            && matches!(builtin, None | Some(Builtin::ManualSelector));
        let (min, max) = match builtin {
            _ if v3_childless => (0, None),
            Some(Builtin::SubTree) => (0, Some(0)),
            Some(b) => b.spec().children,
            None => match kind {
                Kind::Action | Kind::Condition | Kind::SubTree => (0, Some(0)),
                Kind::Decorator => (1, Some(1)),
                Kind::Control => (1, None),
            },
        };
        if n < min || max.is_some_and(|m| n > m) {
            let what = match (min, max) {
                (a, Some(b)) if a == b && a == 0 => "no children".to_string(),
                (a, Some(b)) if a == b && a == 1 => "exactly one child".to_string(),
                (a, Some(b)) if a == b => format!("exactly {a} children"),
                (a, Some(b)) => format!("{a} to {b} children"),
                (a, None) => format!("at least {a} {}", if a == 1 { "child" } else { "children" }),
            };
            return Err(self.err(
                file,
                el,
                format!("{} \"{id}\" must have {what}, found {n}", kind.as_str()),
            ));
        }

        // BehaviorTree.CPP 4's verifyXML: a ReactiveSequence may hold one
        // AsyncSequence at most (by element name), or two would race.
        if version == Version::V4
            && el.tag == "ReactiveSequence"
            && el
                .children
                .iter()
                .filter(|c| c.tag == "AsyncSequence")
                .count()
                > 1
        {
            return Err(self.err(
            file,
            el,
            "A ReactiveSequence cannot have more than one async child (BehaviorTree.CPP refuses it: two AsyncSequence children would race)".to_string(),
        ));
        }
        Ok(())
    }
}

/// A node's ports, scripts and metadata (`_`-prefixed attributes), as
/// `(name, value)` for the last two.
type Attributes = (Vec<Port>, Vec<(String, String)>, Vec<(String, String)>);

/// The kind an element's tag says, in the explicit form (`<Action ID=…>`).
fn explicit_kind(tag: &str) -> Option<Kind> {
    match tag {
        "Action" => Some(Kind::Action),
        "Condition" => Some(Kind::Condition),
        "Control" => Some(Kind::Control),
        "Decorator" => Some(Kind::Decorator),
        "SubTree" | "SubTreePlus" => Some(Kind::SubTree),
        _ => None,
    }
}

/// A node's instance name, by the version's rules.
fn instance_name(version: Version, el: &Element, kind: Kind, id: &str) -> String {
    let name_attr = el.attr("name");
    if kind == Kind::SubTree {
        match (version, name_attr, el.attr("_fullpath")) {
            (Version::V4, Some(n), _) if !n.is_empty() => n.to_string(),
            // The instantiated XML of a log names a subtree by its path.
            (_, None, Some(path)) => match path.rsplit('/').next() {
                Some(last) if !last.is_empty() && !last.contains("::") => last.to_string(),
                _ => id.to_string(),
            },
            _ => id.to_string(),
        }
    } else {
        name_attr.unwrap_or(id).to_string()
    }
}
