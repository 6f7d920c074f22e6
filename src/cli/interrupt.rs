//! SIGINT and SIGTERM during `prism render`. The first sets the flag the render loop reads
//! before each pass ([`crate::render::render_range`]), so the render ends with whole passes and
//! writes what it has; a second ends the process at once with the shell's status for the signal
//! (128 + its number), writing nothing more (outputs are written atomically, so an earlier
//! checkpoint stays whole).

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// The installed handlers' state.
pub struct Interrupt {
    /// Set by the first signal.
    requested: Arc<AtomicBool>,
    /// The number of the last signal received (0: none).
    signal: Arc<AtomicUsize>,
}

/// A render stopped by a signal: `main` prints the message as the command's one line and exits
/// with `status`.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct Interrupted {
    /// Exit status: 130 after SIGINT, 143 after SIGTERM.
    pub status: i32,
    /// What was done and written.
    pub message: String,
}

impl Interrupt {
    /// Installs the handlers of SIGINT and SIGTERM for the rest of the process.
    pub fn install() -> std::io::Result<Self> {
        let requested = Arc::new(AtomicBool::new(false));
        let signal = Arc::new(AtomicUsize::new(0));
        for sig in [SIGINT, SIGTERM] {
            signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize)?;
            signal_hook::flag::register(sig, Arc::clone(&requested))?;
        }
        // The second signal ends the process from a thread of its own, which may remove files
        // (a signal handler may not). Two signals in quick succession may arrive as one.
        let mut signals = Signals::new([SIGINT, SIGTERM])?;
        std::thread::spawn(move || {
            let mut seen = 0;
            for sig in signals.forever() {
                seen += 1;
                if seen >= 2 {
                    crate::io::remove_live_temporaries();
                    std::process::exit(128 + sig);
                }
            }
        });
        Ok(Self { requested, signal })
    }

    /// The flag the render loop reads.
    pub fn flag(&self) -> &AtomicBool {
        &self.requested
    }

    /// The exit status the received signal asks for (`None`: no signal yet).
    pub fn status(&self) -> Option<i32> {
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            sig => Some(128 + sig as i32),
        }
    }
}
