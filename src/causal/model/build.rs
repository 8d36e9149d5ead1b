//! Building the model of a tick (Love et al. Alg. 1–5, 7, 8): the control
//! flow, the tree's structure, the domain's state copies, the graph.

use super::flows::*;
use super::*;

pub(super) struct Builder {
    pub(super) vars: Vec<VarInfo>,
    pub(super) edges: HashSet<(VarId, VarId)>,
    pub(super) edge_list: Vec<(VarId, VarId)>,
    pub(super) extension: usize,
}

impl Builder {
    pub(super) fn var(
        &mut self,
        kind: VarKind,
        range: Vec<Val>,
        intervene: bool,
        func: Func,
    ) -> VarId {
        self.vars.push(VarInfo {
            kind,
            range,
            intervene,
            func,
        });
        self.vars.len() - 1
    }

    pub(super) fn edge(&mut self, a: VarId, b: VarId) -> bool {
        if self.edges.insert((a, b)) {
            self.edge_list.push((a, b));
            true
        } else {
            false
        }
    }

    pub(super) fn extra(&mut self, a: VarId, b: VarId) {
        if self.edge(a, b) {
            self.extension += 1;
        }
    }
}

/// The tree's variables and edges (Algorithm 7, and btx's control flow
/// beyond it): E, r and d per node.
pub(super) struct Structure {
    pub(super) e_of: Vec<VarId>,
    pub(super) r_of: Vec<VarId>,
    pub(super) d_of: Vec<Option<VarId>>,
    pub(super) leaf_of: Vec<Option<usize>>,
}

/// The state's temporal copies (Algorithms 3–5 and 8).
pub(super) struct StateCopies {
    pub(super) copies: Vec<Vec<VarId>>,
    pub(super) inputs_of: Vec<Vec<(usize, VarId)>>,
    pub(super) tau_after: Vec<(Uid, Vec<u32>)>,
}

/// The variables as a graph, in an order to evaluate them in.
pub(super) struct Assembled {
    pub(super) graph: DiGraph<VarId, ()>,
    pub(super) parents: Vec<Vec<VarId>>,
    pub(super) deps: Vec<Vec<VarId>>,
    pub(super) topo: Vec<VarId>,
    pub(super) topo_pos: Vec<usize>,
}

/// Stage "attempts": how each control node goes on in the tick, from where
/// it resumed, and how Retry and Repeat spend attempts within the tick.
pub(super) fn control_flows(tree: &Tree, facts: &TickFacts) -> Vec<Flow> {
    (1..=tree.len() as Uid)
        .map(|u| {
            if decided_by_precondition(tree, facts, u) {
                return Flow::Gated;
            }
            if tree.node(u).builtin == Some(Builtin::RecoveryNode) {
                return recovery_flow(tree, u, facts);
            }
            loop_of(tree, u).unwrap_or_else(|| flow_of(tree, u, &facts.flows[u as usize - 1]))
        })
        .collect()
}

/// A node whose pre-condition script (`_skipIf`, `_successIf`,
/// `_failureIf`, `_while`) decided its status in the tick: it was ticked
/// and none of its children was. What it returned is the recorded choice
/// (the script reads the blackboard, which the model does not hold).
pub(super) fn decided_by_precondition(tree: &Tree, facts: &TickFacts, u: Uid) -> bool {
    let n = tree.node(u);
    !n.children.is_empty()
        && has_script(n, &PRE_CONDITIONS)
        && facts.ticked[u as usize - 1]
        && n.children.iter().all(|&c| !facts.ticked[c as usize - 1])
}

/// Stage "structure": Algorithm 7's variables and structural edges.
pub(super) fn structure(
    tree: &Tree,
    domain: &Option<Arc<Domain>>,
    order: &[Uid],
    flows: &[Flow],
    copy_of: &[Option<crate::causal::attempts::Copy>],
    b: &mut Builder,
) -> Structure {
    let n = tree.len();
    let mut s = Structure {
        e_of: vec![usize::MAX; n],
        r_of: vec![usize::MAX; n],
        d_of: vec![None; n],
        leaf_of: vec![None; n],
    };
    for &u in order {
        node_vars(tree, domain, copy_of, u, b, &mut s);
    }
    for &u in order {
        structural_edges(tree, flows, u, b, &s);
    }
    s
}

/// Algorithm 7's variables of node `u`: whether it executed, its status,
/// and an action's decision where a domain's leaf decides one.
fn node_vars(
    tree: &Tree,
    domain: &Option<Arc<Domain>>,
    copy_of: &[Option<crate::causal::attempts::Copy>],
    u: Uid,
    b: &mut Builder,
    s: &mut Structure,
) {
    let node = tree.node(u);
    let i = u as usize - 1;
    let is_leaf = node.kind.is_leaf();
    let leaf = if is_leaf && node.builtin.is_none() {
        // A copy is the leaf it copies (its name says the attempt).
        let origin = copy_of.get(i).copied().flatten().map_or(u, |c| c.origin);
        domain.as_ref().and_then(|d| d.leaf_for(tree, origin))
    } else {
        None
    };
    s.leaf_of[i] = leaf;
    let e_func = match node.parent {
        None => Func::Root,
        Some(p) => Func::ExecChild {
            parent: p,
            index: tree
                .node(p)
                .children
                .iter()
                .position(|&c| c == u)
                .unwrap_or(0),
        },
    };
    s.e_of[i] = b.var(
        VarKind::Executed(u),
        vec![Val::Bool(true), Val::Bool(false)],
        true,
        e_func,
    );
    let r_func = if is_leaf {
        Func::LeafStatus { uid: u, leaf }
    } else {
        Func::CompositeStatus { uid: u }
    };
    // A built-in leaf other than Sleep is synchronous: BehaviorTree.CPP
    // throws if it returns RUNNING, so no explanation may suppose it.
    let mut range = status_range(node.kind);
    if is_leaf && node.builtin.is_some_and(|b| b != Builtin::Sleep) {
        range.retain(|x| *x != Val::Status(Status::Running));
    }
    if let Some(can) = returns(node) {
        range.retain(|x| matches!(x, Val::Status(s) if *s == Status::Idle || can.contains(s)));
    }
    s.r_of[i] = b.var(VarKind::Status(u), range, true, r_func);
    if let (Some(l), Kind::Action) = (leaf, node.kind) {
        let d = domain.as_ref().expect("a leaf has a domain");
        let mut range: Vec<Val> = d.leaves[l]
            .actions
            .iter()
            .map(|a| Val::Action(Some(a.clone())))
            .collect();
        range.push(Val::Action(None));
        s.d_of[i] = Some(b.var(
            VarKind::Decision(u),
            range,
            true,
            Func::Decision { uid: u, leaf: l },
        ));
    }
}

/// Algorithm 7's edges into node `u`'s variables: from its children and
/// its decision to its status, and to its being executed from its parent
/// and the sibling before it (in a RoundRobin, before it in that turn),
/// with the extra edges its parent's flow needs.
fn structural_edges(tree: &Tree, flows: &[Flow], u: Uid, b: &mut Builder, s: &Structure) {
    let (e_of, r_of) = (&s.e_of, &s.r_of);
    let node = tree.node(u);
    let i = u as usize - 1;
    b.edge(e_of[i], r_of[i]);
    if let Some(d) = s.d_of[i] {
        b.edge(e_of[i], d);
        b.edge(d, r_of[i]);
    }
    for &c in &node.children {
        b.edge(r_of[c as usize - 1], r_of[i]);
    }
    let Some(p) = node.parent else { return };
    let siblings = &tree.node(p).children;
    let k = siblings.iter().position(|&c| c == u).unwrap_or(0);
    let ep = e_of[p as usize - 1];
    // A RoundRobin ticks its children in turn from where it stopped:
    // each depends on those before it in that turn, not in the tree.
    if let Flow::RoundRobin { start, .. } = flows[p as usize - 1] {
        let n = siblings.len();
        let pos = (k + n - start) % n;
        let at = |j: usize| r_of[siblings[(start + j) % n] as usize - 1];
        if pos == 0 {
            b.edge(ep, e_of[i]);
        } else {
            b.edge(at(pos - 1), e_of[i]);
            b.extra(ep, e_of[i]);
            for j in 0..pos - 1 {
                b.extra(at(j), e_of[i]);
            }
        }
        return;
    }
    if k == 0 {
        b.edge(ep, e_of[i]);
    } else {
        b.edge(r_of[siblings[k - 1] as usize - 1], e_of[i]);
    }
    match flows[p as usize - 1] {
        Flow::Sequential { start, .. } | Flow::Branch { start } if start == k && k > 0 => {
            b.extra(ep, e_of[i])
        }
        Flow::Parallel { .. } | Flow::ParallelAll { .. } if k > 0 => {
            b.extra(ep, e_of[i]);
            for &s in &siblings[..k - 1] {
                b.extra(r_of[s as usize - 1], e_of[i]);
            }
        }
        Flow::Branch { .. } if k == 2 => b.extra(r_of[siblings[0] as usize - 1], e_of[i]),
        Flow::Gated | Flow::Map(_) | Flow::Pipeline { .. } | Flow::Recovery { .. } if k > 0 => {
            b.extra(ep, e_of[i])
        }
        _ => {}
    }
}

/// Stage "attempts", its variables: each RetryUntilSuccessful's and
/// Repeat's attempts spent before its first copy in the tick (the count it
/// resumed with, and attempts no copy stands for). It decides what the loop
/// returns and whether each further copy of its child is ticked.
pub(super) fn attempt_counts(
    tree: &Tree,
    facts: &TickFacts,
    flows: &[Flow],
    folded: &[i64],
    st: &Structure,
    b: &mut Builder,
) -> Vec<Option<VarId>> {
    let mut a_of = vec![None; tree.len()];
    for (i, f) in flows.iter().enumerate() {
        let Flow::Map(Mapping::Loop { max, .. }) = *f else {
            continue;
        };
        let u = i as Uid + 1;
        let spent = facts.flows[i].count + folded[i];
        // Every count the node can resume with, when there are few. A loop
        // that started afresh in the tick (or whose last call did: inside
        // another loop's child) used none before: that is not a cause
        // anything could have changed.
        let resumed = facts.start[i] == Status::Running && facts.calls[i] == 1;
        let (range, intervene) = if resumed && (1..=ATTEMPTS_RANGE_MAX).contains(&max) {
            ((0..max).map(|k| Val::Data(Value::from(k))).collect(), true)
        } else {
            (vec![Val::Data(Value::from(spent))], false)
        };
        let a = b.var(VarKind::Attempts(u), range, intervene, Func::Exo);
        b.edge(a, st.r_of[i]);
        for &c in tree.node(u).children.iter().skip(1) {
            b.edge(a, st.e_of[c as usize - 1]);
        }
        a_of[i] = Some(a);
    }
    a_of
}

/// A loop's attempts variable has one value per count up to this many
/// attempts; past it (or with no limit) it is not intervened on.
pub(super) const ATTEMPTS_RANGE_MAX: i64 = 100;

/// Stage "domain": the state's temporal copies, read and written by the
/// leaves in tree order (Algorithms 3–5 and 8).
pub(super) fn state_copies(
    tree: &Tree,
    domain: &Option<Arc<Domain>>,
    order: &[Uid],
    st: &Structure,
    b: &mut Builder,
) -> StateCopies {
    let mut out = StateCopies {
        copies: Vec::new(),
        inputs_of: vec![Vec::new(); tree.len()],
        tau_after: Vec::new(),
    };
    let Some(d) = &domain else {
        return out;
    };
    let nv = d.vars.len();
    out.copies = vec![Vec::new(); nv];
    let mut tau = vec![0u32; nv];
    let ancestors = state_ancestors(d);
    for x in 0..nv {
        ensure_copy(d, b, &mut out.copies, x, 0);
    }
    for &u in order {
        let Some(l) = st.leaf_of[u as usize - 1] else {
            continue;
        };
        let def = &d.leaves[l];
        let mut touched: Vec<usize> = Vec::new();
        for &x in &def.inputs {
            let xc = leaf_reads(d, b, &mut out.copies, &tau, &ancestors[x], x);
            let i = u as usize - 1;
            b.edge(xc, st.r_of[i]);
            if let Some(dv) = st.d_of[i] {
                b.edge(xc, dv);
            }
            out.inputs_of[i].push((x, xc));
            touched.extend(ancestors[x].iter().copied());
            touched.push(x);
        }
        touched.sort_unstable();
        touched.dedup();
        for x in touched {
            tau[x] += 1;
        }
        leaf_writes(d, b, &mut out.copies, &tau, st, u, &def.outputs);
        out.tau_after.push((u, tau.clone()));
    }
    carry_forward(d, &out.copies, b);
    out
}

/// Each state variable's ancestors in the state graph, each once, by id.
fn state_ancestors(d: &Domain) -> Vec<Vec<usize>> {
    let nv = d.vars.len();
    (0..nv)
        .map(|x| {
            let mut seen = vec![false; nv];
            let mut out = Vec::new();
            let mut stack: Vec<usize> = d.vars[x].parents.clone();
            while let Some(a) = stack.pop() {
                if !seen[a] {
                    seen[a] = true;
                    out.push(a);
                    stack.extend(d.vars[a].parents.iter().copied());
                }
            }
            out.sort_unstable();
            out
        })
        .collect()
}

/// Copy `k` of state variable `x`, made (with the copies before it) if
/// it is not yet.
fn ensure_copy(d: &Domain, b: &mut Builder, copies: &mut [Vec<VarId>], x: usize, k: u32) -> VarId {
    while copies[x].len() <= k as usize {
        let c = copies[x].len() as u32;
        let v = &d.vars[x];
        let id = b.var(
            VarKind::State { var: x, copy: c },
            state_range(&v.ty),
            v.intervene && v.ty != VarType::Any,
            Func::Copy {
                var: x,
                prev: None,
                sparents: Vec::new(),
                writers: Vec::new(),
            },
        );
        copies[x].push(id);
    }
    copies[x][k as usize]
}

/// A leaf reads input `x`: its current copy, and those of its ancestors
/// (`anc`) joined by the state graph's edges. The copy read.
fn leaf_reads(
    d: &Domain,
    b: &mut Builder,
    copies: &mut [Vec<VarId>],
    tau: &[u32],
    anc: &[usize],
    x: usize,
) -> VarId {
    let xc = ensure_copy(d, b, copies, x, tau[x]);
    let mut set = anc.to_vec();
    set.push(x);
    for &a in anc {
        ensure_copy(d, b, copies, a, tau[a]);
    }
    for &y in &set {
        for &p in &d.vars[y].parents {
            if set.contains(&p) {
                let (pc, yc) = (copies[p][tau[p] as usize], copies[y][tau[y] as usize]);
                if b.edge(pc, yc) {
                    if let Func::Copy { sparents, .. } = &mut b.vars[yc].func {
                        sparents.push((p, pc));
                    }
                }
            }
        }
    }
    xc
}

/// Leaf `u` writes `outputs`: their next copies depend on its being
/// executed and on its decision.
fn leaf_writes(
    d: &Domain,
    b: &mut Builder,
    copies: &mut [Vec<VarId>],
    tau: &[u32],
    st: &Structure,
    u: Uid,
    outputs: &[usize],
) {
    let i = u as usize - 1;
    for &y in outputs {
        let yc = ensure_copy(d, b, copies, y, tau[y]);
        b.edge(st.e_of[i], yc);
        if let Some(dv) = st.d_of[i] {
            b.edge(dv, yc);
        }
        if let Func::Copy { writers, .. } = &mut b.vars[yc].func {
            if !writers.contains(&u) {
                writers.push(u);
            }
        }
    }
}

/// Algorithm 8: top-level variables carry their value from copy to copy;
/// a copy nothing computes or writes is exogenous.
pub(super) fn carry_forward(d: &Domain, copies: &[Vec<VarId>], b: &mut Builder) {
    // Algorithm 8: top-level variables carry their value forward.
    // A copy of a derived variable that a leaf writes and nothing
    // recomputes carries its previous copy too (btx's addition).
    for (x, cs) in copies.iter().enumerate() {
        let top = d.vars[x].parents.is_empty();
        for k in 1..cs.len() {
            let (a, c) = (cs[k - 1], cs[k]);
            let needs = match &b.vars[c].func {
                Func::Copy {
                    sparents, writers, ..
                } => top || (sparents.is_empty() && !writers.is_empty()),
                _ => false,
            };
            if needs {
                if top {
                    b.edge(a, c);
                } else {
                    b.extra(a, c);
                }
                if let Func::Copy { prev, .. } = &mut b.vars[c].func {
                    *prev = Some(a);
                }
            }
        }
    }
    for cs in copies {
        for &c in cs {
            if let Func::Copy {
                prev: None,
                sparents,
                writers,
                ..
            } = &b.vars[c].func
            {
                if sparents.is_empty() && writers.is_empty() {
                    b.vars[c].func = Func::Exo;
                }
            }
        }
    }
}

/// The graph of the variables, its topological order, and what each
/// variable's function reads.
pub(super) fn assemble(
    b: &Builder,
    inputs_of: &[Vec<(usize, VarId)>],
) -> Result<Assembled, Located> {
    let nvars = b.vars.len();
    let mut graph = DiGraph::<VarId, ()>::with_capacity(nvars, b.edge_list.len());
    for v in 0..nvars {
        graph.add_node(v);
    }
    let mut parents = vec![Vec::new(); nvars];
    for &(a, c) in &b.edge_list {
        graph.add_edge(NodeIndex::new(a), NodeIndex::new(c), ());
        parents[c].push(a);
    }
    let topo: Vec<VarId> = petgraph::algo::toposort(&graph, None)
        .map_err(|c| {
            model_err(format!(
                "the explanation model has a cycle through variable {}",
                c.node_id().index()
            ))
        })?
        .into_iter()
        .map(|n| n.index())
        .collect();
    let mut deps = parents.clone();
    for (v, info) in b.vars.iter().enumerate() {
        if let Func::Copy { writers, .. } = &info.func {
            for w in writers {
                for &(_, c) in &inputs_of[*w as usize - 1] {
                    if !deps[v].contains(&c) {
                        deps[v].push(c);
                    }
                }
            }
        }
    }
    let mut topo_pos = vec![0; nvars];
    for (i, &v) in topo.iter().enumerate() {
        topo_pos[v] = i;
    }
    Ok(Assembled {
        graph,
        parents,
        deps,
        topo,
        topo_pos,
    })
}

impl Model {
    /// Builds the model of the tick in `facts`, stage by stage: the control
    /// flow of the tick, the tree's structure, the domain's state copies,
    /// the graph, then the facts (every variable's value with no change).
    /// Without a domain, the model has the tree's structure only and leaf
    /// outcomes are exogenous.
    pub fn build(
        tree: &Tree,
        domain: Option<Arc<Domain>>,
        facts: TickFacts,
    ) -> Result<Model, Located> {
        let session_len = tree.len();
        let crate::causal::attempts::Unrolled {
            tree: unrolled,
            facts,
            copy_of,
            folded,
        } = crate::causal::attempts::unroll(tree, facts);
        let tree = &unrolled;
        let n = tree.len();
        let order = tree.preorder();
        let mut pre_pos = vec![0; n];
        for (i, &u) in order.iter().enumerate() {
            pre_pos[u as usize - 1] = i;
        }
        let mut b = Builder {
            vars: Vec::new(),
            edges: HashSet::new(),
            edge_list: Vec::new(),
            extension: 0,
        };
        let flows = control_flows(tree, &facts);
        let st = structure(tree, &domain, &order, &flows, &copy_of, &mut b);
        let a_of = attempt_counts(tree, &facts, &flows, &folded, &st, &mut b);
        let sc = state_copies(tree, &domain, &order, &st, &mut b);
        let g = assemble(&b, &sc.inputs_of)?;
        let leaf_of = st.leaf_of;
        let inputs_of = sc.inputs_of;
        let reads_of = inputs_of
            .iter()
            .zip(&leaf_of)
            .map(|(inputs, l)| {
                let def = domain.as_ref().zip(*l).map(|(d, l)| &d.leaves[l]);
                [LeafFn::Status, LeafFn::Decide, LeafFn::Effect].map(|f| {
                    inputs
                        .iter()
                        .filter(|(x, _)| def.is_some_and(|def| def.reads(f).contains(x)))
                        .copied()
                        .collect()
                })
            })
            .collect();
        let mut m = Model {
            tree: unrolled,
            domain,
            facts,
            vars: b.vars,
            graph: g.graph,
            parents: g.parents,
            deps: g.deps,
            topo: g.topo,
            topo_pos: g.topo_pos,
            e_of: st.e_of,
            r_of: st.r_of,
            d_of: st.d_of,
            flows,
            leaf_of,
            inputs_of,
            reads_of,
            copies: sc.copies,
            tau_after: sc.tau_after,
            fact: Vec::new(),
            pre_pos,
            extension_edges: b.extension,
            a_of,
            copy_of,
            folded,
            session_len,
            descriptions: Default::default(),
            loop_above: Default::default(),
        };
        // Stage "facts": every variable's value with no intervention.
        m.fact = m.evaluate_all()?;
        Ok(m)
    }
}
