//! Whether the model reproduces its run, as every answer requires.

use super::*;

impl Model {
    /// Variables whose model value differs from the record: empty when the
    /// model is faithful to the run.
    pub fn unfaithful(&self) -> Vec<String> {
        let mut out = self.nodes_unfaithful();
        if let Some(d) = &self.domain {
            out.extend(self.reads_unfaithful(d));
            out.extend(self.ends_unfaithful(d));
        }
        out.sort();
        out
    }

    /// Each node's execution, status and decision, as the model has them
    /// against the run's.
    fn nodes_unfaithful(&self) -> Vec<String> {
        let mut out = Vec::new();
        for u in 1..=self.tree.len() as Uid {
            let i = u as usize - 1;
            let e = self.fact[self.e(u)].is_true();
            if e != self.facts.ticked[i] {
                out.push(format!(
                    "executed({}) is {e} in the model, {} in the run",
                    self.tree.description(u),
                    self.facts.ticked[i]
                ));
            }
            let r = self.fact[self.r(u)].status();
            if r != self.facts.returned[i] {
                out.push(format!(
                    "status({}) is {r} in the model, {} in the run",
                    self.tree.description(u),
                    self.facts.returned[i]
                ));
            }
            let Some(Val::Action(a)) = self.d(u).map(|d| &self.fact[d]) else {
                continue;
            };
            let rec = &self.facts.decisions[i];
            let same = match (a, rec) {
                (None, None) => true,
                (None, Some(x)) => x == "null",
                (Some(a), Some(x)) => a == x,
                (Some(_), None) => !self.facts.ticked[i],
            };
            if !same {
                out.push(format!(
                    "decision({}) is {a:?} in the model, {rec:?} in the run",
                    self.tree.description(u)
                ));
            }
        }
        out
    }

    /// What each leaf read of the domain's state, in the model and in the
    /// run.
    fn reads_unfaithful(&self, d: &Domain) -> Vec<String> {
        let mut out = Vec::new();
        for (i, inputs) in self.inputs_of.iter().enumerate() {
            let u = &(i as Uid + 1);
            if inputs.is_empty() || !self.facts.ticked[i] {
                continue;
            }
            let Some(before) = self.facts.state_before.get(u) else {
                continue;
            };
            for &(x, c) in inputs {
                if let (Val::Data(m), Some(r)) = (&self.fact[c], before.get(&root_entry(d, x))) {
                    if !same_value(m, r) {
                        out.push(format!(
                            "{} read by {} is {m} in the model, {r} in the run",
                            self.var_name(c),
                            self.tree.description(*u)
                        ));
                    }
                }
            }
        }
        out
    }

    /// The state at the tick's end. A derived variable's last copy is its
    /// value when last read; its parents may change after that, so only
    /// top-level ones are checked.
    fn ends_unfaithful(&self, d: &Domain) -> Vec<String> {
        let mut out = Vec::new();
        for (x, cs) in self.copies.iter().enumerate() {
            if !d.vars[x].parents.is_empty() {
                continue;
            }
            let last = *cs.last().expect("every variable has copy 0");
            let end = self.facts.state_end.get(&root_entry(d, x));
            if let (Val::Data(m), Some(r)) = (&self.fact[last], end) {
                if !same_value(m, r) {
                    out.push(format!(
                        "{} at the end of the tick is {m} in the model, {r} in the run",
                        self.var_name(last)
                    ));
                }
            }
        }
        out
    }
}

/// The root blackboard's entry of the domain's variable `x`.
fn root_entry(d: &Domain, x: usize) -> EntryId {
    EntryId {
        scope: 0,
        key: d.vars[x].name.clone(),
    }
}
