//! What answers computed from a session and may use again (the replay of a
//! run kept at some of its ticks), held beside it. It is not part of the
//! session: a copy of the session starts with an empty one.

use std::any::Any;
use std::sync::Mutex;

#[derive(Default)]
pub struct Scratch(Mutex<Option<Box<dyn Any + Send>>>);

impl Scratch {
    /// Runs `f` on the value of type `T` kept here, made if there is none
    /// (or one of another type). Keep `f` short: the store is locked.
    pub fn with<T: Any + Send + Default, R>(&self, f: impl FnOnce(&mut T) -> R) -> R {
        let mut slot = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if !slot.as_ref().is_some_and(|b| b.is::<T>()) {
            *slot = Some(Box::new(T::default()));
        }
        let value = slot
            .as_mut()
            .and_then(|b| b.downcast_mut::<T>())
            .expect("made above");
        f(value)
    }
}

impl Clone for Scratch {
    fn clone(&self) -> Scratch {
        Scratch::default()
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Scratch")
    }
}

#[cfg(test)]
mod tests {
    use super::Scratch;

    #[test]
    fn a_value_is_kept_by_its_type_and_a_copy_starts_empty() {
        let s = Scratch::default();
        s.with(|v: &mut Vec<u32>| v.push(7));
        assert_eq!(s.with(|v: &mut Vec<u32>| v.clone()), vec![7]);
        assert_eq!(s.clone().with(|v: &mut Vec<u32>| v.len()), 0);
        // Another type replaces it.
        assert_eq!(s.with(|v: &mut String| v.len()), 0);
        assert_eq!(s.with(|v: &mut Vec<u32>| v.len()), 0);
    }
}
