//! The domain's functions as the simulator runs them and the causal model
//! re-evaluates them: a variable derived from its parents, a leaf's
//! decision, status and effect, and an intervention's propagation.

use super::*;

impl Domain {
    pub fn var(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    /// The initial state: declared values, then derived ones computed.
    pub fn initial_state(&self) -> Result<State, Located> {
        let mut s: State = self.vars.iter().map(|v| v.initial.clone()).collect();
        for &i in &self.order.clone() {
            if self.vars[i].initial.is_null() {
                s[i] = self.derive(i, &s)?;
            }
        }
        Ok(s)
    }

    pub fn derive(&self, var: usize, state: &State) -> Result<Value, Located> {
        let key = self.key(0, var, &self.vars[var].parents, state, None);
        match self.memoised(key, || self.derive_now(var, state).map(Memoed::Value))? {
            Memoed::Value(v) => Ok(v),
            other => unreachable!("{other:?}"),
        }
    }

    pub(super) fn derive_now(&self, var: usize, state: &State) -> Result<Value, Located> {
        let v = &self.vars[var];
        let f = v
            .function
            .as_ref()
            .expect("derived variables have functions");
        let mut scope = self.scope_for(v.parents.iter().copied(), state);
        let out = dynamic_to_json(self.eval(f, &mut scope)?);
        let out = self.conform(&v.ty, out);
        self.check_value(&v.ty, &out)
            .map_err(|m| self.at_script(f, format!("{} returned {m}", f.what)))?;
        Ok(out)
    }

    /// The leaf's decision (d_i): an action name, or `None` for the null action.
    pub fn decide(&self, leaf: usize, state: &State) -> Result<Option<String>, Located> {
        let key = self.key(
            1,
            leaf,
            self.leaves[leaf].reads(LeafFn::Decide),
            state,
            None,
        );
        match self.memoised(key, || self.decide_now(leaf, state).map(Memoed::Action))? {
            Memoed::Action(a) => Ok(a),
            other => unreachable!("{other:?}"),
        }
    }

    pub(super) fn decide_now(&self, leaf: usize, state: &State) -> Result<Option<String>, Located> {
        let l = &self.leaves[leaf];
        let Some(script) = &l.decide else {
            return Ok(None);
        };
        let mut scope = self.scope_for(l.inputs.iter().copied(), state);
        let r = self.eval(script, &mut scope)?;
        if r.is_unit() {
            return Ok(None);
        }
        let a = r.into_string().map_err(|t| {
            self.at_script(
                script,
                format!("{} returned a {t}, not an action name", script.what),
            )
        })?;
        if !l.actions.is_empty() && !l.actions.contains(&a) {
            return Err(self.at_script(
                script,
                format!(
                    "{} chose \"{a}\", which is not in actions {:?}",
                    script.what, l.actions
                ),
            ));
        }
        Ok(Some(a))
    }

    pub(super) fn action_scope(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Scope<'static> {
        let l = &self.leaves[leaf];
        let mut scope = self.scope_for(l.inputs.iter().copied(), state);
        scope.push(
            "action",
            action.clone().map_or(Dynamic::UNIT, Dynamic::from),
        );
        scope
    }

    /// The leaf's return status (r_i) for a state and a decision.
    pub fn status(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Status, Located> {
        let reads = self.leaves[leaf].reads(LeafFn::Status);
        let key = self.key(2, leaf, reads, state, Some(action));
        match self.memoised(key, || {
            self.status_now(leaf, state, action).map(Memoed::Status)
        })? {
            Memoed::Status(s) => Ok(s),
            other => unreachable!("{other:?}"),
        }
    }

    pub(super) fn status_now(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Status, Located> {
        let l = &self.leaves[leaf];
        let mut scope = self.action_scope(leaf, state, action);
        let r = self.eval(&l.status, &mut scope)?;
        let s = r.clone().into_string().ok().and_then(|s| Status::parse(&s));
        match s {
            Some(s @ (Status::Success | Status::Failure | Status::Running)) => Ok(s),
            _ => Err(self.at_script(
                &l.status,
                format!(
                    "{} returned {r}, not SUCCESS, FAILURE or RUNNING",
                    l.status.what
                ),
            )),
        }
    }

    /// The leaf's direct effect (p_i): new values of its outputs.
    pub fn effect(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Vec<(usize, Value)>, Located> {
        let reads = self.leaves[leaf].reads(LeafFn::Effect);
        let key = self.key(3, leaf, reads, state, Some(action));
        match self.memoised(key, || {
            self.effect_now(leaf, state, action).map(Memoed::Effect)
        })? {
            Memoed::Effect(e) => Ok(e),
            other => unreachable!("{other:?}"),
        }
    }

    pub(super) fn effect_now(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Vec<(usize, Value)>, Located> {
        let l = &self.leaves[leaf];
        let Some(script) = &l.effect else {
            return Ok(Vec::new());
        };
        let mut scope = self.action_scope(leaf, state, action);
        let r = self.eval(script, &mut scope)?;
        if r.is_unit() {
            return Ok(Vec::new());
        }
        let map = r.try_cast::<rhai::Map>().ok_or_else(|| {
            self.at_script(
                script,
                format!("{} must return a map #{{ var: value }} or ()", script.what),
            )
        })?;
        let mut out = Vec::new();
        for (k, v) in map {
            let Some(i) = self.var(k.as_str()).filter(|i| l.outputs.contains(i)) else {
                return Err(self.at_script(
                    script,
                    format!(
                        "{} sets \"{k}\", which is not one of its outputs",
                        script.what
                    ),
                ));
            };
            let v = self.conform(&self.vars[i].ty, dynamic_to_json(v));
            self.check_value(&self.vars[i].ty, &v).map_err(|m| {
                self.at_script(script, format!("{} sets {k} to a value {m}", script.what))
            })?;
            out.push((i, v));
        }
        Ok(out)
    }

    /// Recomputes derived variables after `changed` changed, parents first,
    /// leaving alone the ones the leaf set itself.
    pub fn propagate(
        &self,
        state: &mut State,
        changed: &[usize],
        set_by_leaf: &[usize],
    ) -> Result<Vec<usize>, Located> {
        let mut dirty = vec![false; self.vars.len()];
        for &c in changed {
            dirty[c] = true;
        }
        let mut updated = Vec::new();
        for &i in &self.order {
            if set_by_leaf.contains(&i) || !self.vars[i].parents.iter().any(|&p| dirty[p]) {
                continue;
            }
            let v = self.derive(i, state)?;
            if v != state[i] {
                state[i] = v;
                dirty[i] = true;
                updated.push(i);
            }
        }
        Ok(updated)
    }

    /// Which leaf definition drives a tree leaf (path, name, ID, default).
    pub fn leaf_for(&self, tree: &Tree, uid: Uid) -> Option<usize> {
        crate::run::leaf_keys(tree, uid)
            .iter()
            .find_map(|k| self.leaves.iter().position(|l| l.key == *k))
    }
}
