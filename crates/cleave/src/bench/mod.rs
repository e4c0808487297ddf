//! `cleave bench`: time per element step and peak memory of reference problems.
//!
//! - `cube`: an elastic block, the element-pass throughput ([`cube`]);
//! - `ball`: the paper's ceramic ball on a rigid plate, with the share of contact ([`ball`]);
//! - `paper-tables`: the paper's Tables II and III ([`paper_tables`]).

mod ball;
mod cube;
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

/// Run `solver` to its end time on `pool`, writing nothing; returns the wall seconds.
fn run_quiet(pool: &rayon::ThreadPool, solver: &mut Solver) -> Result<f64, Failure> {
    let start = std::time::Instant::now();
    pool.install(|| solver.run(&mut Quiet))
        .map_err(|e| match e {
            RunError::Solver(e) => Failure::from(e),
            RunError::Output(e) => Failure::Other(e.to_string()),
        })?;
    Ok(start.elapsed().as_secs_f64())
}

pub fn bench(a: &BenchArgs) -> Result<(), Failure> {
    match a.what.as_str() {
        "cube" => cube::bench_cube(a),
        "ball" => ball::bench_ball(a),
        "paper-tables" => paper_tables::bench_paper_tables(a),
        other => Err(Failure::Input(format!(
            "unknown benchmark '{other}'; available: cube, ball, paper-tables"
        ))),
    }
}
