//! The progress bar of `cleave run` on stderr: simulated time, steps, failed interfaces, ETA.
//! Hidden with `--quiet` or when stderr is not a terminal (indicatif's draw target does that).

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use cleave_core::solver::Solver;

/// Resolution of the bar: simulated time is shown in 1/10000 of the end time.
const TICKS: u64 = 10_000;

pub struct Progress {
    bar: ProgressBar,
    end_time: f64,
    last: Instant,
}

impl Progress {
    pub fn new(end_time: f64, quiet: bool) -> Self {
        let target = if quiet {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        let bar = ProgressBar::with_draw_target(Some(TICKS), target);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:30} {percent:>3}% {msg} [{elapsed_precise}, eta {eta}]",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Self {
            bar,
            end_time,
            last: Instant::now() - Duration::from_secs(1),
        }
    }

    /// Redraw at most 10 times a second.
    pub fn update(&mut self, s: &Solver, failed_interfaces: usize) {
        if self.last.elapsed() < Duration::from_millis(100) && !s.is_finished() {
            return;
        }
        self.last = Instant::now();
        let frac = if self.end_time > 0.0 {
            (s.state.t / self.end_time).clamp(0.0, 1.0)
        } else {
            1.0
        };
        self.bar.set_position((frac * TICKS as f64) as u64);
        self.bar.set_message(format!(
            "t {:.4e} / {:.4e}  step {}  dt {:.3e}  failed {}",
            s.state.t, self.end_time, s.state.step, s.state.dt, failed_interfaces
        ));
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
