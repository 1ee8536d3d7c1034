//! Values built on first use and kept for the process, by key: the render pipelines (and the
//! shader modules they are specialised from) of the shading module, the post-process passes
//! and the SSAO passes. A driver compiles a pipeline once per process this way, not once per
//! frame or render.

use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex, MutexGuard};

/// A map from keys to values built on first use.
pub(crate) struct BuiltOnce<K, V> {
    map: Mutex<HashMap<K, Arc<V>>>,
}

impl<K: Eq + Hash + Clone, V> BuiltOnce<K, V> {
    /// Empty.
    pub(crate) fn new() -> Self {
        BuiltOnce {
            map: Mutex::new(HashMap::new()),
        }
    }

    /// The map, usable after a panic on another thread (a value is inserted whole or not at
    /// all, so none is ever half-built).
    fn lock(&self) -> MutexGuard<'_, HashMap<K, Arc<V>>> {
        self.map.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The value of `key`, built by `build` on first use while the map is locked: callers that
    /// want it at once wait for the one build.
    pub(crate) fn get_or_build(&self, key: &K, build: impl FnOnce() -> V) -> Arc<V> {
        let mut map = self.lock();
        if let Some(v) = map.get(key) {
            return v.clone();
        }
        map.entry(key.clone())
            .or_insert_with(|| Arc::new(build()))
            .clone()
    }

    /// The value of `key` if it is built.
    pub(crate) fn get(&self, key: &K) -> Option<Arc<V>> {
        self.lock().get(key).cloned()
    }

    /// Whether `key` is built.
    pub(crate) fn contains(&self, key: &K) -> bool {
        self.lock().contains_key(key)
    }

    /// Stores `value` as `key`'s unless another thread stored one first, and returns the one
    /// kept: for values built without the lock held, so that threads build side by side.
    pub(crate) fn keep_first(&self, key: K, value: Arc<V>) -> Arc<V> {
        self.lock().entry(key).or_insert(value).clone()
    }
}
