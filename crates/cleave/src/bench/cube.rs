//! `cleave bench cube --elements N --steps S --threads T`: an elastic steel cube of about N
//! elements (n^3), its top face moving at 1 m/s so every element deforms, with the default
//! viscous hourglass control, bulk viscosity and the energy balance on. No output is written;
//! the time is that of `Solver::run` alone. With `--separation` every element is in a
//! separation group whose strength nothing reaches: the same motion on 8 nodes per element,
//! with the coincident-set averaging and the failure check of every interface each step (run
//! the two variants as separate processes: peak memory is per process). With `--gpu` the S
//! timed steps come after S more, untimed, that warm the GPU up (its clocks climb from idle
//! and the batches of steps per submission grow from 4 steps to thousands: without them a
//! 2,000-step run at 100k elements read 1.5-2.3 ns per element step where a 10,000-step one
//! read 1.15-1.2 on the same H100).

use cleave_core::mesh::box_model;
use cleave_core::model::{Material, MaterialKind, SeparationDef};
use cleave_io::output::peak_rss_mb;

use crate::cli::BenchArgs;
use crate::failure::Failure;

/// Steps taken with every GPU pass timed on its own, before the timed run (`--gpu`).
const PROFILED_STEPS: usize = 10;

pub fn bench_cube(a: &BenchArgs) -> Result<(), Failure> {
    let n = ((a.elements.unwrap_or(100_000) as f64).cbrt().round() as usize).max(1);
    let steel = Material {
        id: 1,
        density: 7850.0,
        young: 210e9,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    };
    let mut model = box_model([n, n, n], [0.1, 0.1, 0.1], steel, 1.0);
    for (v, x) in model.v0.iter_mut().zip(&model.x0) {
        *v = [0.0, 0.0, 10.0 * x[2] / 0.1];
    }
    // a fixed number of steps: the end time from the stable step of the undeformed cube
    let (dt, _) = cleave_core::setup::estimate_time_step(&model)
        .ok_or_else(|| Failure::Other("no time step".into()))?;
    // (on a GPU as many steps again first, untimed: run_quiet_gpu)
    let runs = if a.gpu { 2.0 } else { 1.0 };
    model.control.end_time = runs * dt * a.steps as f64;
    let pool = crate::run::thread_pool(Some(a.threads))?;
    if a.separation {
        model.separations.push(SeparationDef {
            material: 0,
            model: 1,
            sigmax: 1e30,
            beta: 1.0,
            gc: 0.0,
            bond: 1,
            strength: Default::default(),
        });
    }
    let prepared = crate::run::prepare(model);
    let (mut solver, _) = crate::run::start_solver(&prepared.model, prepared.interfaces)?;
    let mut device = String::new();
    let mut gpu_lines = Vec::new();
    let mut step0 = 0;
    let timing = if a.gpu {
        let mut g = cleave_gpu::GpuStepper::new(cleave_gpu::Gpu::new()?, &mut solver)?;
        device = format!(", GPU {}", g.gpu().describe());
        gpu_lines.push(format!(
            "  device memory {:.1} MB in buffers",
            g.device_bytes() as f64 / 1048576.0
        ));
        if !g.split_arrays().is_empty() {
            let parts: Vec<String> = (g.split_arrays().iter())
                .map(|(name, chunks)| format!("{name} in {chunks}"))
                .collect();
            gpu_lines.push(format!(
                "  arrays larger than the device binds, bound in parts: {}",
                parts.join(", ")
            ));
        }
        // each pass's share, from 10 steps with a timestamp around every pass (not timed)
        if let Some(shares) = g.profile(&mut solver, PROFILED_STEPS) {
            let parts: Vec<String> = (shares.iter())
                .map(|(name, f)| format!("{name} {:.1}%", 100.0 * f))
                .collect();
            gpu_lines.push(format!(
                "  GPU passes ({PROFILED_STEPS} steps, device timestamps): {}",
                parts.join(", ")
            ));
        } else {
            gpu_lines.push(
                "  GPU passes: not timed (no timestamp queries on the device, or the run ended within the profiled steps)"
                    .into(),
            );
        }
        // S steps to warm the GPU up, then S timed
        let (timing, warm) = super::run_quiet_gpu(&mut g, &mut solver, dt * a.steps as f64)?;
        step0 = warm;
        // the same steps with every pass returning at once: what the dispatches cost
        let idle = g.idle_step_seconds(a.steps as usize);
        // (a device that failed in any of it gave no figure worth printing)
        if let Some(m) = g.gpu().failure() {
            return Err(Failure::Other(format!(
                "the GPU failed in the benchmark: {m}"
            )));
        }
        gpu_lines.push(format!(
            "  idle step {:.1} us ({} steps in one submission, every pass dispatched and returning at its halt test)",
            1e6 * idle,
            a.steps
        ));
        timing
    } else {
        super::run_quiet(&pool, &mut solver)?
    };
    let secs = timing.secs;
    let result = solver.state.step - step0;
    let ne = n * n * n;
    let us = 1e6 * secs / (result as f64 * ne as f64);
    let rss = peak_rss_mb();
    println!(
        "bench cube: {ne} elements, {} nodes solved, {result} steps timed, {} thread(s){device}{}",
        solver.positions().len(),
        a.threads,
        if a.separation {
            ", every element in a separation group"
        } else {
            ""
        }
    );
    if a.gpu {
        // a GPU's step is a few nanoseconds: four decimals of a microsecond are too few
        println!("  {us:.4} us per element step ({:.3} ns)", 1e3 * us);
    } else {
        println!("  {us:.4} us per element step");
    }
    for l in &gpu_lines {
        println!("{l}");
    }
    println!(
        "  peak memory {rss:.1} MB ({:.0} bytes per element)",
        rss * 1048576.0 / ne as f64
    );
    super::print_steal(timing.steal);
    Ok(())
}
