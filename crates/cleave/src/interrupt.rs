//! SIGINT and SIGTERM during a run: the first asks the run to stop after the step it is in,
//! write a restart file and its output, and exit 128 + the signal's number (130, 143); a
//! second one ends the process at once with that code (the files written so far stay valid).
//! Outside the time-step loop the signals keep their default action.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// The signals a run listens to, once [`Interrupt::listen`] has been called.
pub struct Interrupt {
    which: Arc<AtomicUsize>,
}

impl Interrupt {
    /// Listen to SIGINT and SIGTERM from now on.
    pub fn listen() -> std::io::Result<Self> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let asked = Arc::new(AtomicBool::new(false));
        let which = Arc::new(AtomicUsize::new(0));
        for sig in [SIGINT, SIGTERM] {
            // the second signal: exit at once (registered first, so it sees the flag unset
            // the first time)
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&asked))?;
            signal_hook::flag::register(sig, Arc::clone(&asked))?;
            signal_hook::flag::register_usize(sig, Arc::clone(&which), sig as usize)?;
        }
        Ok(Self { which })
    }

    /// The signal received, if any.
    pub fn received(&self) -> Option<i32> {
        match self.which.load(Ordering::Relaxed) {
            0 => None,
            s => Some(s as i32),
        }
    }
}

/// The name of a signal the run listens to.
pub fn signal_name(sig: i32) -> &'static str {
    match sig {
        signal_hook::consts::SIGINT => "SIGINT",
        signal_hook::consts::SIGTERM => "SIGTERM",
        _ => "a signal",
    }
}
