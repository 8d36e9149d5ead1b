//! A domain's leaves in a run: the tree's leaves ticked through the
//! domain's functions, with interventions set by the causal search.

use super::*;

/// Leaves driven by a domain. The state lives in the root blackboard, one
/// entry per variable, so `{@X_a}` ports read and write it.
pub struct DomainLeaves {
    pub domain: Arc<Domain>,
    pub state: State,
    assigned: HashMap<Uid, usize>,
    /// The first error met; the leaf then fails and the run stops.
    pub error: Option<Located>,
    /// A leaf of `end_after` ran.
    ended: bool,
    /// Interventions of a counterfactual re-run.
    pub intervene: Intervention,
}

/// What a counterfactual re-run changes within one tick: a leaf's decision
/// at one of its calls (Love's d_i), or a state variable's value right
/// after a leaf's first call (a temporal copy the leaf leaves behind).
#[derive(Debug, Clone, Default)]
pub struct Intervention {
    pub tick: u32,
    /// (leaf, which call within the tick from 1, the action it takes).
    pub actions: Vec<(Uid, u32, Option<String>)>,
    /// (place, variable, value): set before the first call of a leaf at
    /// or past that place in the tree's pre-order (a temporal copy is
    /// there whether or not the leaves around it run).
    pub sets: Vec<(usize, usize, Value)>,
    /// Each node's place in the tree's pre-order, by uid − 1.
    pub order: Vec<usize>,
    /// A variable to read once the first leaf at or past a place in the
    /// pre-order is called (or at the tick's end): (variable, place).
    pub watch: Option<(usize, Option<usize>)>,
    /// What the watched variable was then.
    pub seen: Option<Value>,
    calls: HashMap<Uid, u32>,
    applied: Vec<bool>,
}

impl DomainLeaves {
    /// Every leaf of the tree must be described (or covered by a default).
    pub fn new(domain: Arc<Domain>, tree: &Tree) -> Result<DomainLeaves, Located> {
        let mut assigned = HashMap::new();
        let mut missing = Vec::new();
        for n in &tree.nodes {
            if n.kind.is_leaf() && n.builtin.is_none() {
                match domain.leaf_for(tree, n.uid) {
                    Some(l) => {
                        assigned.insert(n.uid, l);
                    }
                    None => missing.push(format!("{} #{}", tree.description(n.uid), n.uid)),
                }
            }
        }
        if !missing.is_empty() {
            return Err(Located::file(&domain.path, format!("no [leaf] for {}", missing.join(", ")))
                .with_help("add [leaf.\"NAME\"] tables, or [leaf.\"@default_action\"] / [leaf.\"@default_condition\"]"));
        }
        let state = domain.initial_state()?;
        Ok(DomainLeaves {
            domain,
            state,
            assigned,
            error: None,
            ended: false,
            intervene: Intervention::default(),
        })
    }

    /// Starts the run with `NAME=VALUE` for a variable without a function
    /// (a top-level one, or one only leaves write), then recomputes what
    /// derives from it. VALUE is JSON (`0.0`, `true`, `"a"`) or a bare word.
    pub fn set(&mut self, assignment: &str) -> Result<(), String> {
        let (name, raw) = assignment
            .split_once('=')
            .ok_or_else(|| format!("--set {assignment}: write NAME=VALUE"))?;
        let (name, raw) = (name.trim(), raw.trim());
        let d = &self.domain;
        let k = d.var(name).ok_or_else(|| {
            let names: Vec<&str> = d.vars.iter().map(|v| v.name.as_str()).collect();
            format!(
                "--set {name}: the domain has no such variable; it has {}",
                names.join(", ")
            )
        })?;
        if d.vars[k].function.is_some() {
            return Err(format!(
                "--set {name}: it is computed from {} by the domain's function; set one of those instead",
                d.vars[k]
                    .parents
                    .iter()
                    .map(|&p| d.vars[p].name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let v: Value = serde_json::from_str(raw).unwrap_or_else(|_| Value::from(raw));
        d.check_value(&d.vars[k].ty, &v)
            .map_err(|e| format!("--set {name}: {e}"))?;
        self.state[k] = v;
        d.propagate(&mut self.state, &[k], &[])
            .map_err(|e| format!("--set {name}: {e}"))?;
        Ok(())
    }

    /// Notes the watched variable's value now.
    fn watch_now(&mut self) {
        if let Some((x, _)) = self.intervene.watch {
            self.intervene.seen = Some(self.state[x].clone());
        }
    }

    /// Sets a state variable as an intervention does (what derives from it
    /// is recomputed, what it derives from is not): the variables changed.
    pub fn apply(&mut self, var: usize, v: Value) -> Result<Vec<usize>, Located> {
        self.state[var] = v;
        let d = Arc::clone(&self.domain);
        let mut changed = vec![var];
        changed.extend(d.propagate(&mut self.state, &[var], &[var])?);
        Ok(changed)
    }

    /// The state as root-blackboard entries.
    pub fn entries(&self) -> Vec<(EntryId, Value)> {
        self.domain
            .vars
            .iter()
            .zip(&self.state)
            .map(|(v, x)| {
                (
                    EntryId {
                        scope: 0,
                        key: v.name.clone(),
                    },
                    x.clone(),
                )
            })
            .collect()
    }

    fn step(&mut self, call: &mut LeafCall) -> Result<LeafOutcome, Located> {
        let leaf = self.leaf_of(call)?;
        let d = Arc::clone(&self.domain);
        if d.end_after.contains(&d.leaves[leaf].key) {
            self.ended = true;
        }
        let call_no = self.intervened_call(call);
        let forced = self
            .intervene
            .actions
            .iter()
            .find(|(u, k, _)| *u == call.uid && *k == call_no)
            .map(|(_, _, a)| a.clone());
        let derived_early = if call_no > 0 {
            self.apply_due_sets(call.uid)?
        } else {
            Vec::new()
        };
        let action = match forced {
            Some(a) => a,
            None => d.decide(leaf, &self.state)?,
        };
        let status = d.status(leaf, &self.state, &action)?;
        let effect = d.effect(leaf, &self.state, &action)?;
        let mut changed = Vec::new();
        for (i, v) in effect {
            if self.state[i] != v {
                self.state[i] = v;
                changed.push(i);
            }
        }
        let derived = d.propagate(&mut self.state, &changed, &d.leaves[leaf].outputs)?;
        for i in derived_early.into_iter().chain(changed).chain(derived) {
            call.write_entry(
                EntryId {
                    scope: 0,
                    key: d.vars[i].name.clone(),
                },
                self.state[i].clone(),
            );
        }
        let decision = if d.leaves[leaf].decide.is_some() {
            Some(action.unwrap_or_else(|| "null".into()))
        } else {
            None
        };
        Ok(LeafOutcome { status, decision })
    }

    /// The domain's `[leaf]` that `call`'s node executes.
    fn leaf_of(&mut self, call: &LeafCall) -> Result<usize, Located> {
        if let Some(&l) = self.assigned.get(&call.uid) {
            return Ok(l);
        }
        let l = self.domain.leaf_for(call.tree, call.uid).ok_or_else(|| {
            Located::file(
                &self.domain.path,
                format!(
                    "no [leaf] for {} #{}",
                    call.tree.description(call.uid),
                    call.uid
                ),
            )
        })?;
        self.assigned.insert(call.uid, l);
        Ok(l)
    }

    /// Which call of its node within the intervened tick `call` is, from 1;
    /// 0 in every other tick.
    fn intervened_call(&mut self, call: &LeafCall) -> u32 {
        if call.tick != self.intervene.tick {
            return 0;
        }
        let c = self.intervene.calls.entry(call.uid).or_insert(0);
        *c += 1;
        *c
    }

    /// Sets the intervention's values due before `uid`'s call: those placed
    /// at or before the watched place first, then the watched value is
    /// read, then the rest. The variables they change, with what follows
    /// from them.
    fn apply_due_sets(&mut self, uid: Uid) -> Result<Vec<usize>, Located> {
        let iv = &mut self.intervene;
        iv.applied.resize(iv.sets.len(), false);
        let here = iv.order.get(uid as usize - 1).copied().unwrap_or(0);
        let boundary = match iv.watch {
            Some((_, Some(b))) if iv.seen.is_none() && here >= b => Some(b),
            _ => None,
        };
        let mut due: Vec<usize> = (0..iv.sets.len())
            .filter(|&i| !iv.applied[i] && iv.sets[i].0 <= here)
            .collect();
        due.sort_by_key(|&i| boundary.is_some_and(|b| iv.sets[i].0 > b));
        let mut changed = Vec::new();
        let mut watched = false;
        for i in due {
            let (place, x, v) = self.intervene.sets[i].clone();
            if !watched && boundary.is_some_and(|b| place > b) {
                self.watch_now();
                watched = true;
            }
            self.intervene.applied[i] = true;
            changed.extend(self.apply(x, v)?);
        }
        if !watched && boundary.is_some() {
            self.watch_now();
        }
        Ok(changed)
    }
}

impl Leaves for DomainLeaves {
    fn enums(&self) -> &[(String, i64)] {
        &self.domain.enums
    }

    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        self.entries()
    }

    fn take_error(&mut self) -> Option<Located> {
        self.error.take()
    }

    fn run_over(&mut self, root: Status) -> bool {
        if self.domain.end_after.is_empty() {
            root != Status::Running
        } else {
            self.ended
        }
    }

    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        match self.step(call) {
            Ok(o) => o,
            Err(e) => {
                if self.error.is_none() {
                    self.error = Some(e);
                }
                LeafOutcome {
                    status: Status::Failure,
                    decision: None,
                }
            }
        }
    }
}
