//! What SIGINT, SIGTERM and SIGHUP do. Normally: remove the temporary files and
//! staging folders of results being written (previous results stay as they
//! were) and exit with 130 at once. During a trace that keeps a checkpoint
//! (`--checkpoint-every`): ask the photon loop to stop after its current batch,
//! write the checkpoint and exit with 130 (a second signal stops at once).
//!
//! Every one of these signals gives 130, the code of Ctrl-C: a job script tests
//! one code whatever stopped the run (the shell's convention of 128 + N would
//! give 143 for SIGTERM and 129 for SIGHUP; the README says which we chose).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// What to say when a signal stops the command at once.
static STOP_MESSAGE: Mutex<Option<String>> = Mutex::new(None);

/// A checkpointing trace is running: signals ask it to stop.
static CHECKPOINTING: AtomicBool = AtomicBool::new(false);
/// A signal asked the checkpointing trace to stop.
static STOP: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once, at start).
pub fn stop_cleanly_on_signals() {
    let _ = ctrlc::set_handler(|| {
        if CHECKPOINTING.load(Ordering::SeqCst) && !STOP.swap(true, Ordering::SeqCst) {
            tell!("stopping after the current batch of photons to write a checkpoint (signal again to stop at once, losing the photons since the last checkpoint)");
            return;
        }
        traxer::files::temporaries::remove_all();
        match STOP_MESSAGE.try_lock().ok().and_then(|m| m.clone()) {
            Some(m) => tell!("{m}"),
            None => tell!("stopped: no results were written"),
        }
        std::process::exit(130);
    });
}

/// Whether signals stop the run gracefully (checkpoint first) from now on.
pub fn checkpoint_on_signals(on: bool) {
    CHECKPOINTING.store(on, Ordering::SeqCst);
}

/// Whether a signal asked the run to stop.
pub fn stop_requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// What a signal that stops the command at once says (instead of "no results
/// were written"), e.g. how to continue.
pub fn set_stop_message(message: String) {
    if let Ok(mut m) = STOP_MESSAGE.lock() {
        *m = Some(message);
    }
}
