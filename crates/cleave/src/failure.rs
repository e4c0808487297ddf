//! The error of a command, carrying its exit code.

use std::fmt;

/// Why a command failed; the variant decides the exit code.
#[derive(Debug)]
pub enum Failure {
    /// Bad input: deck, options, model (exit code 2).
    Input(String),
    /// The run failed numerically (exit code 3).
    Numerical(String),
    /// Anything else: I/O, internal (exit code 1).
    Other(String),
    /// The run stopped on a signal after writing its restart file and output (exit code 128 +
    /// the signal's number: 130 for SIGINT, 143 for SIGTERM).
    Interrupted(String, i32),
}

impl Failure {
    pub fn exit_code(&self) -> i32 {
        match self {
            Failure::Input(_) => 2,
            Failure::Numerical(_) => 3,
            Failure::Other(_) => 1,
            Failure::Interrupted(_, sig) => 128 + sig,
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Input(m)
            | Failure::Numerical(m)
            | Failure::Other(m)
            | Failure::Interrupted(m, _) => f.write_str(m),
        }
    }
}

impl From<cleave_io::deck::DeckError> for Failure {
    fn from(e: cleave_io::deck::DeckError) -> Self {
        Failure::Input(e.to_string())
    }
}

impl From<cleave_gpu::GpuError> for Failure {
    /// A feature or size the GPU step does not take is bad input for `--gpu` (exit 2); no
    /// usable GPU, or one that failed, is the machine's (exit 1).
    fn from(e: cleave_gpu::GpuError) -> Self {
        match e {
            cleave_gpu::GpuError::NoDevice(_) | cleave_gpu::GpuError::Failed(_) => {
                Failure::Other(e.to_string())
            }
            _ => Failure::Input(e.to_string()),
        }
    }
}

impl From<cleave_core::error::SolverError> for Failure {
    fn from(e: cleave_core::error::SolverError) -> Self {
        if e.is_numerical() {
            Failure::Numerical(e.to_string())
        } else {
            Failure::Input(e.to_string())
        }
    }
}

/// An I/O error with what was being done.
pub fn io_failure(what: &str, path: &std::path::Path, e: std::io::Error) -> Failure {
    Failure::Other(format!("{what} {}: {e}", path.display()))
}
