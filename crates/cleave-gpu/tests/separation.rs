//! Element separation on the GPU against the CPU: the same interfaces fail in the same step,
//! the pieces move as on the CPU to round-off, and a GPU run repeated gives the same bits.
//!
//! Needs a device with f64 shaders (on a machine without a GPU, Mesa's lavapipe, which
//! `.ci/run` installs); without any, each test says SKIPPED and passes.
//!
//! Tolerance: as in `against_cpu.rs`, the two steps differ by round-off (fused multiply-adds on
//! the GPU, the sums of a coincident set's forces taken in element order there and in colour
//! order on the CPU), 1e-16 relative per operation, grown linearly over a few hundred steps:
//! 1e-9 of each field's largest value. An interface whose failure index came within that of 1
//! could fail a step apart on the two (the measured differences are printed); on these decks
//! none does, and the tests ask for the same failures in the same steps.

use cleave_core::curve::Curve;
use cleave_core::math::Vec3;
use cleave_core::mesh::box_model;
use cleave_core::model::{
    Hourglass, Material, MaterialKind, Model, MotionTarget, PrescribedMotion, SeparationDef, Vad,
};
use cleave_core::separation::interfaces::Separation;
use cleave_core::separation::split::{split_model, SplitModel};
use cleave_core::solver::{Observer, Solver};
use cleave_gpu::{Checkpointing, Gpu, GpuStepper};
mod common;
use common::{block, gpu};

/// What a run showed at each output: step, time, the failed interfaces, positions, velocities
/// (per node of the split model), stresses, energies.
#[derive(Clone, Debug, PartialEq)]
struct Row {
    step: u64,
    t: f64,
    failed: Vec<usize>,
    x: Vec<Vec3>,
    v: Vec<Vec3>,
    stress: Vec<[f64; 6]>,
    energy: [f64; 4],
}

struct Record {
    every: f64,
    next: f64,
    rows: Vec<Row>,
}

impl Observer for Record {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        let t = s.state.t;
        if t < self.next * (1.0 - 1e-12) && !s.is_finished() {
            return Ok(());
        }
        self.next = t + self.every;
        let e = s.state.energy;
        self.rows.push(Row {
            step: s.state.step,
            t,
            failed: s.separation().unwrap().failed_interfaces().collect(),
            x: s.positions().to_vec(),
            v: s.velocities().to_vec(),
            stress: s.state.stress.clone(),
            energy: [e.kinetic, e.internal, e.hourglass, e.external_work],
        });
        Ok(())
    }
    fn next_due(&self) -> f64 {
        self.next
    }
}

fn solver(split: &SplitModel) -> Solver<'_> {
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(split).unwrap());
    s
}

fn run_cpu(split: &SplitModel, every: f64) -> Vec<Row> {
    let mut s = solver(split);
    let mut r = Record {
        every,
        next: 0.0,
        rows: Vec::new(),
    };
    s.run(&mut r).unwrap();
    r.rows
}

fn run_gpu(g: Gpu, split: &SplitModel, every: f64) -> (Vec<Row>, Gpu) {
    let mut s = solver(split);
    let mut st = GpuStepper::new(g, &s).unwrap();
    let mut r = Record {
        every,
        next: 0.0,
        rows: Vec::new(),
    };
    st.run(&mut s, &mut r).unwrap();
    (r.rows, st.into_gpu())
}

/// Largest |a - b| over the largest |a|.
fn rel<const N: usize>(a: &[[f64; N]], b: &[[f64; N]]) -> f64 {
    let scale = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let d =
        (a.iter().flatten().zip(b.iter().flatten())).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    d / scale.max(f64::MIN_POSITIVE)
}

/// Run `split` on the CPU and twice on the GPU, outputs every `every`: the GPU runs agree bit
/// for bit, and with the CPU in steps, times and failed interfaces at every output and in the
/// fields to 1e-9. Returns the CPU's rows.
fn compare(split: &SplitModel, every: f64, name: &str) -> Option<Vec<Row>> {
    let g = gpu()?;
    let cpu = run_cpu(split, every);
    let (gpu1, g) = run_gpu(g, split, every);
    let (gpu2, _) = run_gpu(g, split, every);
    assert!(gpu1 == gpu2, "{name}: two GPU runs differ");
    assert_eq!(cpu.len(), gpu1.len(), "{name}: the same output times");
    let mut worst = [0.0f64; 4];
    for (a, b) in cpu.iter().zip(&gpu1) {
        assert_eq!(a.step, b.step, "{name}: step at t = {}", a.t);
        assert!(
            (a.t - b.t).abs() <= 1e-12 * a.t,
            "{name}: t {} vs {}",
            a.t,
            b.t
        );
        assert_eq!(
            a.failed, b.failed,
            "{name}: failed interfaces at t = {}",
            a.t
        );
        let e = a.energy.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let de = (a.energy.iter().zip(&b.energy)).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        let d = [
            rel(&a.x, &b.x),
            rel(&a.v, &b.v),
            rel(&a.stress, &b.stress),
            de / e,
        ];
        for k in 0..4 {
            worst[k] = worst[k].max(d[k]);
        }
    }
    let last = cpu.last().unwrap();
    eprintln!(
        "{name}: {} outputs, {} interfaces failed by the end; largest relative differences GPU - CPU: x {:.1e}, v {:.1e}, stress {:.1e}, energies {:.1e}",
        cpu.len(),
        last.failed.len(),
        worst[0],
        worst[1],
        worst[2],
        worst[3]
    );
    assert!(worst.iter().all(|&d| d < 1e-9), "{name}: {worst:?}");
    Some(cpu)
}

const RHO: f64 = 7800.0;
const YOUNG: f64 = 200e9;
const BAR_L: f64 = 0.1;
const BAR_N: usize = 40;
const PULL: f64 = 10.0;

/// The CPU's pulled bar (cleave-core tests/separation.rs): 40 x 1 x 1 elastic elements
/// (Poisson 0) all in one MODEL 1 group, both ends driven outwards at 10 m/s; SIGMAX = 1.5
/// rho c v, so it breaks where the two tensile waves meet, at L / (2c).
fn pulled_bar() -> Model {
    let h = BAR_L / BAR_N as f64;
    let c = (YOUNG / RHO).sqrt();
    let mat = Material {
        id: 1,
        density: RHO,
        young: YOUNG,
        poisson: 0.0,
        kind: MaterialKind::Elastic,
    };
    let mut m = box_model([BAR_N, 1, 1], [BAR_L, h, h], mat, 0.9 * BAR_L / c);
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0],
        y: vec![1.0],
    });
    for (x, sf) in [(0.0, -PULL), (BAR_L, PULL)] {
        for node in m.nodes_where(0, x, 1e-12) {
            m.prescribed.push(PrescribedMotion {
                target: MotionTarget::Node(node),
                axis: 0,
                vad: Vad::Velocity,
                curve: 0,
                sf,
            });
        }
    }
    m.separations.push(SeparationDef {
        material: 0,
        model: 1,
        sigmax: 1.5 * RHO * c * PULL,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    });
    m
}

/// The pulled bar breaks on the GPU where and when it breaks on the CPU (the same interfaces
/// in the same steps), in the middle, no earlier than L/(2c).
#[test]
fn pulled_bar_breaks_as_on_the_cpu() {
    let split = split_model(&pulled_bar());
    let every = split.model.control.end_time / 30.0;
    let Some(cpu) = compare(&split, every, "pulled bar") else {
        return;
    };
    let c = (YOUNG / RHO).sqrt();
    let first = cpu
        .iter()
        .find(|r| !r.failed.is_empty())
        .expect("it breaks");
    assert!(first.t >= BAR_L / (2.0 * c), "broke at {}", first.t);
    assert!(!cpu.last().unwrap().failed.is_empty());
}

/// The block of the GPU tests (`common::block`: 3 x 3 x 6 elements of bilinear-plastic steel,
/// clamped at its foot (SPC), its top driven down by a velocity that ramps up, with an initial
/// shear velocity and a body load) over 200 steps, every element in a MODEL 2 group (effective stress, BETA 0.7), of a strength (250 MPa) that a few
/// interfaces reach at once, under the initial shear, and most in the second half of the run
/// (measured: 5 by the third of 39 outputs, 60 by the end).
fn cracking_block() -> Model {
    let mut m = block(Hourglass::Viscous);
    m.separations.push(SeparationDef {
        material: 0,
        model: 2,
        sigmax: 250e6,
        beta: 0.7,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    });
    // 200 steps (the block's 150 and more)
    m.control.end_time *= 200.0 / 150.0;
    m
}

/// The cracking block on the GPU: the same interfaces fail in the same steps as on the CPU,
/// under tension and shear, with SPC, prescribed motion and a body load on the pieces.
#[test]
fn cracking_block_fails_as_on_the_cpu() {
    let split = split_model(&cracking_block());
    let every = split.model.control.end_time / 40.0;
    let Some(cpu) = compare(&split, every, "cracking block") else {
        return;
    };
    let counts: Vec<usize> = cpu.iter().map(|r| r.failed.len()).collect();
    eprintln!("cracking block: failed interfaces at each output {counts:?}");
    let failed = counts[counts.len() - 1];
    let first = counts.iter().position(|&n| n > 0).expect("it cracks");
    assert!(failed >= 20, "{failed} interfaces failed");
    assert!(first < cpu.len() / 2);
    assert!(
        counts[cpu.len() / 2] < failed / 2,
        "most fail in the second half"
    );
}

/// Takes the GPU's state once, at the first halt at or after `due`, and records as [`Record`].
struct TakeState {
    record: Record,
    due: f64,
    /// The time, the number of failed interfaces and the GPU's state.
    taken: Option<(f64, usize, Vec<u8>)>,
}

impl Observer for TakeState {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.record.observe(s)
    }
    fn next_due(&self) -> f64 {
        self.record.next_due()
    }
}

impl Checkpointing for TakeState {
    fn checkpoint_due(&self) -> f64 {
        self.due
    }
    fn stop_asked(&mut self) -> bool {
        false
    }
    fn checkpoint(&mut self, s: &Solver, gpu_state: Vec<u8>) -> std::io::Result<()> {
        let failed = s.separation().unwrap().num_failed();
        self.taken = Some((s.state.t, failed, gpu_state));
        self.due = f64::INFINITY;
        Ok(())
    }
}

/// A run taken up from the GPU state saved midway, after interfaces have failed (with the
/// interfaces and sets as they have split, `GpuStepper::save`), ends in the same bits as the
/// run that went through.
#[test]
fn a_cracking_run_continues_from_its_saved_state() {
    let Some(g) = gpu() else { return };
    let split = split_model(&cracking_block());
    let end = split.model.control.end_time;
    let every = end / 40.0;
    let record = || Record {
        every,
        next: 0.0,
        rows: Vec::new(),
    };
    let mut s = solver(&split);
    let mut st = GpuStepper::new(g, &s).unwrap();
    let mut obs = TakeState {
        record: record(),
        due: 0.5 * end,
        taken: None,
    };
    st.run_checkpointed(&mut s, &mut obs).unwrap();
    let through = obs.record.rows.last().unwrap().clone();
    let (t, failed_then, state) = obs.taken.expect("a state taken midway");
    assert!(
        failed_then > 0,
        "interfaces failed before the state was taken"
    );
    assert!(through.failed.len() > failed_then, "and after");
    let mut s2 = solver(&split);
    let mut st2 = GpuStepper::new(st.into_gpu(), &s2).unwrap();
    st2.load(&mut s2, &state).unwrap();
    assert_eq!(s2.state.t, t);
    assert_eq!(s2.separation().unwrap().num_failed(), failed_then);
    let mut r = record();
    r.next = t;
    st2.run(&mut s2, &mut r).unwrap();
    let again = r.rows.last().unwrap();
    eprintln!(
        "continued from t = {t:e} ({failed_then} interfaces failed then): {} at the end",
        again.failed.len()
    );
    assert!(*again == through, "the continued run ends elsewhere");
}
