//! `cleave bench`: time per element step and peak memory of reference problems.
//!
//! - `cube`: an elastic block, the element-pass throughput ([`cube`]);
//! - `ball`: the paper's ceramic ball on a rigid plate, with the share of contact ([`ball`]);
//! - `paper-tables`: the paper's Tables II and III ([`paper_tables`]);
//! - `fragmentation`: the fragmenting bar over a range of strain rates ([`fragmentation`]).

mod ball;
mod cube;
pub mod fragmentation;
mod paper_tables;

use cleave_core::solver::{Observer, RunError, Solver};

use crate::cli::BenchArgs;
use crate::failure::Failure;

/// An observer that writes nothing.
struct Quiet;

impl Observer for Quiet {
    fn observe(&mut self, _: &Solver) -> std::io::Result<()> {
        Ok(())
    }
}

/// The wall time of a run, and the CPU time the host took from this virtual machine meanwhile.
#[derive(Clone, Copy, Debug)]
struct Timing {
    secs: f64,
    /// Steal time over the run, all CPUs (seconds; `None` without `/proc/stat`).
    steal: Option<f64>,
}

/// What a failed benchmark run exits with.
fn run_failure(e: RunError) -> Failure {
    match e {
        RunError::Solver(e) => Failure::from(e),
        RunError::Output(e) => Failure::Other(e.to_string()),
        RunError::Device(m) => Failure::Other(m),
    }
}

/// Run `solver` to its end time on `pool`, writing nothing.
fn run_quiet(pool: &rayon::ThreadPool, solver: &mut Solver) -> Result<Timing, Failure> {
    let steal0 = steal_seconds();
    let start = std::time::Instant::now();
    pool.install(|| solver.run(&mut Quiet))
        .map_err(run_failure)?;
    let secs = start.elapsed().as_secs_f64();
    let steal = steal_seconds().zip(steal0).map(|(b, a)| b - a);
    Ok(Timing { secs, steal })
}

/// Run `solver` to its end time on the GPU of `stepper`, writing nothing (the state is read
/// back once, at `from`, and at the end), and time the steps from the simulated time `from`
/// on: the steps before it warm the GPU up (its clocks climb from idle, and the batches of
/// steps per submission grow from 4 to thousands), so that the time is of the steady run.
/// Returns the timing and the step count the timing started from.
fn run_quiet_gpu(
    stepper: &mut cleave_gpu::GpuStepper,
    solver: &mut Solver,
    from: f64,
) -> Result<(Timing, u64), Failure> {
    let mut warm = WarmUp { from, mark: None };
    stepper.run(solver, &mut warm).map_err(run_failure)?;
    let end = std::time::Instant::now();
    let (start, step0, steal0) = warm.mark.unwrap_or((end, solver.state.step, None));
    let secs = end.duration_since(start).as_secs_f64();
    let steal = steal_seconds().zip(steal0).map(|(b, a)| b - a);
    Ok((Timing { secs, steal }, step0))
}

/// An observer that writes nothing and asks for the state once, at the time `from`, where it
/// notes the moment, the step count and the steal time.
struct WarmUp {
    from: f64,
    mark: Option<(std::time::Instant, u64, Option<f64>)>,
}

impl Observer for WarmUp {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        if self.mark.is_none() {
            self.mark = Some((std::time::Instant::now(), s.state.step, steal_seconds()));
        }
        Ok(())
    }
    fn next_due(&self) -> f64 {
        match self.mark {
            None => self.from,
            Some(_) => f64::INFINITY,
        }
    }
}

/// The steal time of all CPUs so far: the time a virtual machine's CPUs were ready to run
/// but the host ran something else (`/proc/stat`, the 8th number of the `cpu` line, in
/// USER_HZ ticks of 1/100 s on Linux). A benchmark on a shared host that was stolen from is
/// slower than the machine: `cleave bench` prints it so such a run can be told apart.
fn steal_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    parse_steal(&stat)
}

fn parse_steal(stat: &str) -> Option<f64> {
    let line = stat.lines().find(|l| l.starts_with("cpu "))?;
    let ticks: u64 = line.split_whitespace().nth(8)?.parse().ok()?;
    Some(ticks as f64 / 100.0)
}

/// Print the steal time of a run ([`steal_seconds`]), when the system reports it.
fn print_steal(steal: Option<f64>) {
    if let Some(s) = steal {
        println!(
            "  host steal time during the run: {s:.2} s{}",
            if s > 0.0 {
                " (CPU time the host gave to other work: the more of it, the slower this timing is than the machine)"
            } else {
                ""
            }
        );
    }
}

pub fn bench(a: &BenchArgs) -> Result<(), Failure> {
    if a.passes && !(a.gpu && a.what == "ball") {
        return Err(Failure::Input(
            "--passes times each pass of the GPU's step over a run: it goes with `cleave bench ball --gpu` (the cube's --gpu run prints its passes' shares already)".into(),
        ));
    }
    match a.what.as_str() {
        "cube" => cube::bench_cube(a),
        "ball" => ball::bench_ball(a),
        "paper-tables" if a.gpu => Err(Failure::Input(
            "--gpu: `cleave bench paper-tables` runs on the CPU only (the paper's Tables II and III time the CPU's step); run it without --gpu, or time the ball on the GPU with `cleave bench ball --gpu`".into(),
        )),
        "fragmentation" if a.gpu => Err(Failure::Input(
            "--gpu: `cleave bench fragmentation` runs on the CPU only (its sweep times the CPU's threads); run it without --gpu, or run one of its decks with `cleave run --gpu` (`cleave example fragmenting-bar`)".into(),
        )),
        "paper-tables" => paper_tables::bench_paper_tables(a),
        "fragmentation" => fragmentation::bench_fragmentation(a),
        other => Err(Failure::Input(format!(
            "unknown benchmark '{other}'; available: cube, ball, paper-tables, fragmentation"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steal_is_the_eighth_number_of_the_cpu_line() {
        let stat = "cpu  10 20 30 40 50 60 70 123 0 0\ncpu0 1 2 3 4 5 6 7 8 0 0\n";
        assert_eq!(parse_steal(stat), Some(1.23));
        assert_eq!(parse_steal("cpu0 1 2 3\n"), None);
        assert_eq!(parse_steal("cpu  1 2 x 4 5 6 7 8\n"), Some(0.08));
        assert_eq!(parse_steal("cpu  1 2 3 4 5 6 7 y\n"), None);
    }
}
