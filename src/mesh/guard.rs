//! Containment of panics inside third-party mesh readers. The gltf crate indexes
//! lists with numbers taken from the file during validation and reading, and a
//! malformed file can make it panic; the importers run such code through
//! [`quietly`], which turns the panic into an error message and keeps the default
//! panic hook from printing a backtrace for a problem that is the file's, not
//! traxer's.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    /// Whether this thread is inside [`quietly`] (its panics are expected).
    static CONTAINED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`; a panic becomes `Err(its message)`, printed by nobody.
pub(crate) fn quietly<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let default = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !CONTAINED.with(Cell::get) {
                default(info);
            }
        }));
    });
    let outer = CONTAINED.with(|c| c.replace(true));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    CONTAINED.with(|c| c.set(outer));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown failure".to_string())
    })
}
