#![no_main]
//! BehaviorTree.CPP's script language: the parser and the evaluator.

use libfuzzer_sys::fuzz_target;
use serde_json::Value;
use std::collections::HashMap;

struct Env(HashMap<String, Value>);

impl btx::run::script::Env for Env {
    fn get(&self, name: &str) -> Option<Value> {
        self.0.get(name).cloned()
    }
    fn set(&mut self, name: &str, v: Value) {
        if self.0.len() < 64 {
            self.0.insert(name.to_string(), v);
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let mut env = Env(HashMap::from([
        ("k".to_string(), Value::from(1)),
        ("s".to_string(), Value::from("text")),
        ("f".to_string(), Value::from(0.5)),
    ]));
    // Scripts run again and again in a tick: a few times each.
    for _ in 0..3 {
        let _ = btx::run::script::run(text, &mut env);
    }
});
