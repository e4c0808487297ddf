//! `cleave bench ball --elements N [--end-time T] [--no-separation] --threads K`: the ceramic
//! ball of `cleave example ball-impact` (section 4.1 of the paper) run in process over a fixed
//! window of simulated time (default 50 us: it touches the plate at 1.3 us; the contact and
//! the first fractures fall inside), with no output written. It reports the time per element
//! step, the peak memory, and the share of each phase of the step, contact in particular (the
//! issue's target: contact at most 30% of the step).

use cleave_core::contact::times::ContactTimes;
use cleave_core::contact::ContactStats;
use cleave_core::model::Model;
use cleave_io::output::peak_rss_mb;

use crate::cli::BenchArgs;
use crate::example::ball_impact;
use crate::failure::Failure;

/// The default window of simulated time.
pub const WINDOW: f64 = 50e-6;

/// What one ball run measured.
#[derive(Clone, Copy, Debug)]
pub struct BallRun {
    /// Elements and solved nodes of the ball alone (the paper's counts).
    pub ball_elements: usize,
    pub ball_nodes: usize,
    /// Elements of the model (the ball and the plate's 25 bricks).
    pub elements: usize,
    pub nodes: usize,
    pub nodes_solved: usize,
    pub steps: u64,
    pub us_per_element_step: f64,
    pub peak_rss_mb: f64,
    /// Shares of the step: elements, interfaces, contact, the rest.
    pub shares: [f64; 4],
    pub failed_interfaces: usize,
    /// Contact search statistics at the end (closed cracks, releases, builds).
    pub contact: ContactStats,
    /// Seconds in each phase of the contact's steps.
    pub contact_times: ContactTimes,
    /// Seconds of the interfaces' phase: in all, releasing the failed ones and splitting their
    /// sets, summing the split sets again.
    pub interface_times: [f64; 3],
    /// Steal time during the run (s), where the system reports it (`bench::steal_seconds`).
    pub steal: Option<f64>,
}

/// The ball-impact model with `elements` elements to `end_time`, its separation card kept or
/// dropped.
fn ball_model(elements: usize, end_time: f64, separation: bool) -> Result<Model, Failure> {
    let mut model = ball_impact(elements, end_time).map_err(Failure::Input)?;
    if !separation {
        model.separations.clear();
    }
    Ok(model)
}

/// Run the ball model with `elements` elements for `end_time`.
pub fn run_ball(
    elements: usize,
    end_time: f64,
    separation: bool,
    threads: usize,
) -> Result<BallRun, Failure> {
    let model = ball_model(elements, end_time, separation)?;
    let nodes = model.num_nodes();
    let pool = crate::run::thread_pool(Some(threads))?;
    let prepared = crate::run::prepare(model);
    let (mut solver, _) = crate::run::start_solver(&prepared.model, prepared.interfaces)?;
    let timing = super::run_quiet(&pool, &mut solver)?;
    let secs = timing.secs;
    let steps = solver.state.step + 1;
    let ne = prepared.model.num_elements();
    let pm = &prepared.model;
    let mut in_ball = vec![false; pm.num_nodes()];
    let mut ball_elements = 0;
    for (c, &p) in pm.conn.iter().zip(&pm.elem_part) {
        if p == 0 {
            ball_elements += 1;
            for &n in c {
                in_ball[n as usize] = true;
            }
        }
    }
    let t = solver.times;
    let total = t.total();
    Ok(BallRun {
        ball_elements,
        ball_nodes: in_ball.iter().filter(|&&b| b).count(),
        elements: ne,
        nodes,
        nodes_solved: solver.positions().len(),
        steps,
        us_per_element_step: 1e6 * secs / (steps as f64 * ne as f64),
        peak_rss_mb: peak_rss_mb(),
        shares: [t.elements, t.interfaces, t.contact, t.nodal].map(|x| x / total),
        failed_interfaces: solver.separation().map_or(0, |s| s.num_failed()),
        contact: solver.contact().map(|c| c.stats()).unwrap_or_default(),
        contact_times: solver.contact().map(|c| c.times()).unwrap_or_default(),
        interface_times: [
            t.interfaces,
            solver.separation().map_or(0.0, |s| s.release_seconds),
            t.split_sums,
        ],
        steal: timing.steal,
    })
}

impl BallRun {
    /// The measurements as a JSON object.
    pub fn to_json(self) -> serde_json::Value {
        serde_json::json!({
            "ball_elements": self.ball_elements,
            "ball_nodes": self.ball_nodes,
            "elements": self.elements,
            "nodes": self.nodes,
            "nodes_solved": self.nodes_solved,
            "steps": self.steps,
            "us_per_element_step": self.us_per_element_step,
            "peak_rss_mb": self.peak_rss_mb,
            "shares": self.shares,
            "failed_interfaces": self.failed_interfaces,
            "closed_cracks": self.contact.closed,
            "released_cracks": self.contact.released,
            "contact_times": self.contact_times,
            "interface_times": self.interface_times,
            "steal_s": self.steal,
        })
    }

    /// Read back what [`BallRun::to_json`] wrote.
    pub fn from_json(v: &serde_json::Value) -> Option<Self> {
        let u = |k: &str| v[k].as_u64();
        let f = |k: &str| v[k].as_f64();
        let sh = v["shares"].as_array()?;
        Some(Self {
            ball_elements: u("ball_elements")? as usize,
            ball_nodes: u("ball_nodes")? as usize,
            elements: u("elements")? as usize,
            nodes: u("nodes")? as usize,
            nodes_solved: u("nodes_solved")? as usize,
            steps: u("steps")?,
            us_per_element_step: f("us_per_element_step")?,
            peak_rss_mb: f("peak_rss_mb")?,
            shares: [0, 1, 2, 3].map(|i| sh.get(i).and_then(|x| x.as_f64()).unwrap_or(f64::NAN)),
            failed_interfaces: u("failed_interfaces")? as usize,
            contact: ContactStats {
                closed: u("closed_cracks").unwrap_or(0) as usize,
                released: u("released_cracks").unwrap_or(0),
                ..Default::default()
            },
            contact_times: serde_json::from_value(v["contact_times"].clone()).unwrap_or_default(),
            interface_times: serde_json::from_value(v["interface_times"].clone())
                .unwrap_or_default(),
            steal: f("steal_s"),
        })
    }
}

pub fn bench_ball(a: &BenchArgs) -> Result<(), Failure> {
    let end = a.end_time.unwrap_or(WINDOW);
    if a.gpu {
        return bench_ball_gpu(a, end);
    }
    let r = run_ball(a.elements.unwrap_or(2800), end, !a.no_separation, a.threads)?;
    if a.json {
        println!("{}", r.to_json());
        return Ok(());
    }
    println!(
        "bench ball: {} elements (ball and plate), {} nodes, {} solved, {} steps to {end:e} s, {} thread(s), {}",
        r.elements,
        r.nodes,
        r.nodes_solved,
        r.steps,
        a.threads,
        if a.no_separation {
            "no separation".to_string()
        } else {
            format!("{} interfaces failed", r.failed_interfaces)
        }
    );
    println!("  {:.4} us per element step", r.us_per_element_step);
    println!("  peak memory {:.1} MB", r.peak_rss_mb);
    let [e, i, c, n] = r.shares.map(|x| 100.0 * x);
    println!(
        "  step shares: elements {e:.1}%, interface checks {i:.1}%, contact {c:.1}%, nodal and the rest {n:.1}%"
    );
    println!("  contact / element work: {:.2}", r.shares[2] / r.shares[0]);
    let s = r.contact;
    println!(
        "  contact: {} closed cracks, {} released to the search; {} full searches, {} incremental",
        s.closed, s.released, s.rebuilds, s.updates
    );
    let [all, releases, sums] = r.interface_times;
    if releases > 0.0 {
        println!(
            "  interface checks {all:.3} s: releases and set splits {releases:.3} s, the split sets summed again {sums:.3} s, the checks {:.3} s",
            all - releases - sums
        );
    }
    let t = r.contact_times;
    if t.total() > 0.0 {
        println!(
            "  contact phases: node checks {:.3} s, full builds {:.3} s, incremental searches {:.3} s, closed cracks {:.3} s (their forces {:.3} s, beside the searches and checks), motion tracking {:.3} s, pair forces {:.3} s, crack activation {:.3} s",
            t.node_checks,
            t.full_builds,
            t.incremental,
            t.closed_cracks,
            t.closed_forces,
            t.tracking,
            t.pair_forces,
            t.activation
        );
    }
    super::print_steal(r.steal);
    Ok(())
}

/// `cleave bench ball --gpu`: the ball on the GPU, breaking (or unbroken with
/// `--no-separation`), as `cleave run --gpu` runs it. What the GPU step lacks is refused by
/// name, as `cleave run --gpu` refuses the deck, never run on the CPU instead. Timed from a
/// tenth of the run on (the first batches grow the submissions), after each pass's share is
/// taken from 10 steps with device timestamps (the first steps: before anything breaks).
fn bench_ball_gpu(a: &BenchArgs, end: f64) -> Result<(), Failure> {
    let model = ball_model(a.elements.unwrap_or(2800), end, !a.no_separation)?;
    let prepared = crate::run::prepare(model);
    let (mut solver, _) = crate::run::start_solver(&prepared.model, prepared.interfaces)?;
    if let Some(what) = cleave_gpu::support::unsupported(&prepared.model, &solver.setup) {
        return Err(cleave_gpu::GpuError::Unsupported(what).into());
    }
    let mut g = cleave_gpu::GpuStepper::new(cleave_gpu::Gpu::new()?, &mut solver)?;
    let shares = g.profile(&mut solver, 10);
    let timed = a.passes && g.time_passes(true);
    let timed_from = solver.state.step;
    let (timing, step0) = super::run_quiet_gpu(&mut g, &mut solver, 0.1 * end)?;
    let steps = solver.state.step - step0;
    let ne = prepared.model.num_elements();
    let us = 1e6 * timing.secs / (steps as f64 * ne as f64);
    let pairs = solver
        .contact()
        .map_or(0, |c| c.forces().iter().map(|f| f.pairs).sum());
    let broken = match solver.separation() {
        Some(sep) => format!("{} interfaces failed", sep.num_failed()),
        None => "no separation".into(),
    };
    println!(
        "bench ball: {ne} elements (ball and plate), {} nodes, {steps} steps timed of {} to {end:e} s, GPU {}, {broken}",
        prepared.model.num_nodes(),
        solver.state.step,
        g.gpu().describe()
    );
    println!("  {us:.4} us per element step ({:.3} ns)", 1e3 * us);
    println!(
        "  device memory {:.1} MB in buffers",
        g.device_bytes() as f64 / 1048576.0
    );
    match shares {
        Some(shares) => {
            let parts: Vec<String> = (shares.iter())
                .map(|(name, f)| format!("{name} {:.1}%", 100.0 * f))
                .collect();
            println!(
                "  GPU passes (10 steps, device timestamps): {}",
                parts.join(", ")
            );
        }
        None => println!("  GPU passes: not timed (no timestamp queries on the device)"),
    }
    let halts: Vec<String> = (g.host_halts().iter())
        .zip(["sets split", "erosions", "cracks released"])
        .filter(|((n, _), _)| *n > 0)
        .map(|((n, secs), what)| format!("{n} {what}, {:.2} ms each", 1e3 * secs / *n as f64))
        .collect();
    if !halts.is_empty() {
        println!(
            "  steps halted for the host over the run: {} (the host's work at each, wall clock)",
            halts.join("; ")
        );
    }
    let splits = g.host_halts()[0].0;
    if splits > 0 {
        let [read, tables, rest] = g.split_parts().map(|s| 1e3 * s / splits as f64);
        println!(
            "  a split's host time: {read:.2} ms waiting for its read-back, {tables:.2} ms the contact's tables, {rest:.2} ms the rest"
        );
    }
    if a.passes {
        match g.pass_times().filter(|_| timed) {
            Some(secs) => {
                let steps = solver.state.step - timed_from;
                let total: f64 = secs.iter().map(|s| s.1).sum();
                let parts: Vec<String> = (secs.iter())
                    .map(|(name, s)| format!("{name} {:.1}%", 100.0 * s / total.max(1e-300)))
                    .collect();
                println!(
                    "  GPU passes over the whole run ({steps} steps, device timestamps, each pass in its own compute pass): {:.1} us of device time a step; {}",
                    1e6 * total / steps.max(1) as f64,
                    parts.join(", ")
                );
            }
            None => println!(
                "  GPU passes over the run: not timed (no timestamp queries on the device)"
            ),
        }
    }
    println!("  contact pairs at the end: {pairs}");
    super::print_steal(timing.steal);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `--json` writes reads back, the contact's phase times with it (`bench
    /// paper-tables` runs each ball in its own process and reads its JSON).
    #[test]
    fn json_reads_back() {
        let r = BallRun {
            ball_elements: 2800,
            ball_nodes: 3000,
            elements: 2825,
            nodes: 3100,
            nodes_solved: 20000,
            steps: 1761,
            us_per_element_step: 0.3,
            peak_rss_mb: 13.3,
            shares: [0.6, 0.05, 0.33, 0.02],
            failed_interfaces: 1686,
            contact: ContactStats {
                closed: 1328,
                released: 358,
                ..Default::default()
            },
            contact_times: ContactTimes {
                tracking: 0.1,
                closed_cracks: 0.2,
                closed_forces: 0.3,
                incremental: 0.4,
                full_builds: 0.5,
                node_checks: 0.6,
                pair_forces: 0.7,
                activation: 0.8,
            },
            interface_times: [1.0, 0.25, 0.125],
            steal: Some(0.01),
        };
        let back = BallRun::from_json(&r.to_json()).expect("reads back");
        assert_eq!(back.contact_times, r.contact_times);
        assert_eq!(back.interface_times, r.interface_times);
        assert_eq!(back.failed_interfaces, 1686);
        assert_eq!(back.contact.closed, 1328);
        assert_eq!(back.shares, r.shares);
    }
}
