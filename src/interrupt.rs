//! Ctrl-C and SIGTERM: what the binary's one signal handler does ([`on_signal`]).
//!
//! Normally the process is abandoned: [`crate::output::file::abandon_and_exit`] removes the
//! outputs being written, and the process exits with 130. While a render that can stop early
//! runs ([`accept_stops`]), the first signal only asks it to stop ([`stop_requested`]): at the
//! end of the camera samples of the sample block in progress, or within a light-tracing block
//! of 512 paths, abandoning the block's passes (a part holds whole passes); it then writes the
//! samples done as a part and exits non-zero. A second signal abandons it as above. (Two atomics are the one piece of global state here: a
//! signal handler has no other way to reach a render.)

use std::sync::atomic::{AtomicBool, Ordering};

/// A render is running that stops when asked.
static ACCEPTING: AtomicBool = AtomicBool::new(false);
/// A stop was asked for.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Handles Ctrl-C, SIGTERM or SIGHUP (see the module documentation). Exits the process unless a
/// render accepts a stop and none was asked for yet.
pub fn on_signal() {
    if ACCEPTING.load(Ordering::SeqCst) && !REQUESTED.swap(true, Ordering::SeqCst) {
        eprintln!(
            "\ninterrupted: stopping to write the samples done (light passes in progress are \
             abandoned; interrupt again to abandon it all)"
        );
        return;
    }
    eprintln!(
        "\ninterrupted{}: abandoning the outputs being written; nothing more is written",
        if REQUESTED.load(Ordering::SeqCst) { " again" } else { "" }
    );
    crate::output::file::abandon_and_exit(130);
}

/// While the returned guard lives, a signal asks the render to stop instead of exiting.
pub fn accept_stops() -> StopGuard {
    REQUESTED.store(false, Ordering::SeqCst);
    ACCEPTING.store(true, Ordering::SeqCst);
    StopGuard(())
}

/// Ends [`accept_stops`] when dropped.
pub struct StopGuard(());

impl Drop for StopGuard {
    fn drop(&mut self) {
        ACCEPTING.store(false, Ordering::SeqCst);
    }
}

/// True once a stop was asked for while a render accepted stops.
pub fn stop_requested() -> bool {
    ACCEPTING.load(Ordering::SeqCst) && REQUESTED.load(Ordering::SeqCst)
}
