//! summary.json of a run: written at the end, and every few seconds while the run goes on
//! (status "running"), each time whole (through a renamed temporary file), so that a run that
//! is killed leaves a valid summary of where it stood.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use cleave_core::solver::Solver;
use cleave_io::output::{peak_rss_mb, Summary};

/// Wall time between two summaries written during a run.
const EVERY: Duration = Duration::from_secs(5);

/// What summary.json says besides the solver's and the output's figures.
pub struct RunStatus {
    pub path: PathBuf,
    /// Nodes of the deck (before splitting).
    pub deck_nodes: usize,
    pub threads: usize,
    /// "cpu" or "gpu: NAME".
    pub device: String,
    pub warnings: Vec<String>,
    /// When the command started, and its time-step loop.
    pub started: Instant,
    pub loop_start: Instant,
    /// The step the loop started from (0, or a restart file's).
    pub first_step: u64,
    last: Instant,
    first: bool,
}

impl RunStatus {
    pub fn new(
        path: PathBuf,
        deck_nodes: usize,
        threads: usize,
        device: String,
        warnings: Vec<String>,
        started: Instant,
    ) -> Self {
        let now = Instant::now();
        Self {
            path,
            deck_nodes,
            threads,
            device,
            warnings,
            started,
            loop_start: now,
            first_step: 0,
            last: now,
            first: true,
        }
    }

    /// Whether a summary is due: at the first state, then every few seconds of wall time.
    pub fn due(&mut self) -> bool {
        let now = Instant::now();
        let due = self.first || now.duration_since(self.last) >= EVERY;
        if due {
            self.last = now;
            self.first = false;
        }
        due
    }

    /// The summary of the state `s` (`fragments`, `energy_ratio`, the crack's times: from the
    /// output's last rows); `us_per_element_step` counts the steps of this command's loop.
    pub fn summary(
        &self,
        s: &Solver,
        fragments: usize,
        energy_ratio: f64,
        crack: (Option<f64>, Option<f64>),
        status: &str,
    ) -> Summary {
        let steps = s.state.step + u64::from(s.is_finished());
        let ne = s.model.num_elements();
        let looped = steps.saturating_sub(self.first_step).max(1) as f64;
        Summary {
            elements: ne,
            nodes: self.deck_nodes,
            nodes_solved: s.positions().len(),
            interfaces: s.separation().map_or(0, |x| x.num_interfaces()),
            failed_interfaces: s.separation().map_or(0, |x| x.num_failed()),
            fragments,
            eroded_elements: s.eroded_count(),
            crack_initiation_time: crack.0,
            crack_speed_mean: crack.1,
            steps,
            end_time: s.state.t,
            wall_seconds: self.started.elapsed().as_secs_f64(),
            us_per_element_step: 1e6 * self.loop_start.elapsed().as_secs_f64()
                / (looped * ne.max(1) as f64),
            peak_rss_mb: peak_rss_mb(),
            threads: self.threads,
            device: self.device.clone(),
            energy_ratio,
            status: status.into(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            warnings: self.warnings.clone(),
        }
    }
}
