//! Arrays larger than the device binds are bound in parts (`split.rs`): with the binding limit
//! lowered until most arrays of a model are split, a run gives the same bits as with every
//! array bound whole (the same operations in the same order; only the addressing differs).
//!
//! Needs a device with f64 shaders (lavapipe on a machine without a GPU); without any, each test
//! says SKIPPED and passes.

mod common;

use cleave_core::model::{Hourglass, Model, SeparationDef};
use cleave_core::separation::interfaces::Separation;
use cleave_core::separation::split::split_model;
use cleave_core::solver::{Observer, Solver};
use cleave_gpu::{Gpu, GpuStepper};

use common::{block, gpu};

/// The state at each output: step, time, positions, velocities, stresses, energies (as bits).
struct Record {
    every: f64,
    next: f64,
    rows: Vec<(u64, Vec<u64>)>,
    /// Interfaces failed by the last output.
    failed: usize,
}

impl Observer for Record {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        if s.state.t < self.next * (1.0 - 1e-12) && !s.is_finished() {
            return Ok(());
        }
        self.next = s.state.t + self.every;
        let e = s.state.energy;
        let mut bits: Vec<u64> = vec![s.state.t.to_bits()];
        let fields = (s.positions().to_vec().iter().flatten())
            .chain(s.velocities().to_vec().iter().flatten())
            .chain(s.state.stress.iter().flatten())
            .chain(
                [
                    e.kinetic,
                    e.internal,
                    e.hourglass,
                    e.external_work,
                    e.fracture,
                ]
                .iter(),
            )
            .map(|v| v.to_bits())
            .collect::<Vec<_>>();
        bits.extend(fields);
        if let Some(sep) = s.separation() {
            self.failed = sep.failed_interfaces().count();
            bits.extend(sep.failed_interfaces().map(|i| i as u64));
        }
        self.rows.push((s.state.step, bits));
        Ok(())
    }
    fn next_due(&self) -> f64 {
        self.next
    }
}

fn solver(split: &cleave_core::separation::split::SplitModel, m: &Model) -> Solver<'static> {
    // the split model lives for the test (leaked: a few kB)
    let split: &'static _ = Box::leak(Box::new(split.clone()));
    let mut s = Solver::new(&split.model).unwrap();
    if !m.separations.is_empty() {
        s.attach_separation(Separation::new(split).unwrap());
    }
    s
}

type Rows = Vec<(u64, Vec<u64>)>;

/// Runs `m` on `g` (with `g.force_split`): the rows at 20 outputs (the interfaces failed by
/// the end last) and the arrays split.
fn run(g: Gpu, m: &Model) -> (Rows, Vec<(String, usize)>, Gpu) {
    let mut s = solver(&split_model(m), m);
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let parts = st.split_arrays().to_vec();
    let mut r = Record {
        every: m.control.end_time / 20.0,
        next: 0.0,
        rows: Vec::new(),
        failed: 0,
    };
    st.run(&mut s, &mut r).unwrap();
    r.rows.push((u64::MAX, vec![r.failed as u64]));
    (r.rows, parts, st.into_gpu())
}

/// A stepper for `m` with array `name` bound in the fewest parts the device allows past one
/// (parts of 256 bytes, doubled while the parts need more bindings than the device has):
/// the stepper's split arrays, and the part size.
fn split_one(g: Gpu, m: &Model, name: &str) -> (Gpu, u64, Vec<(String, usize)>) {
    let split = split_model(m);
    let mut g = g;
    let mut bytes = 256;
    loop {
        g.force_split = vec![(name.to_string(), bytes)];
        let mut s = solver(&split, m);
        match GpuStepper::new(g, &mut s) {
            Ok(st) => {
                let parts = st.split_arrays().to_vec();
                return (st.into_gpu(), bytes, parts);
            }
            Err(e) => {
                assert!(e.to_string().contains("storage bindings"), "{name}: {e}");
                g = Gpu::new().unwrap();
                bytes *= 2;
                assert!(bytes < 1 << 24, "{name} never binds");
            }
        }
    }
}

/// Each array of `arrays` split on its own: the shader with its accessors compiles, and for
/// those of `runs` the run gives the bits of the run with every array whole; at least
/// `failing` interfaces fail in the run.
fn same_bits_split(name: &str, m: &Model, arrays: &[&str], runs: &[&str], failing: u64) {
    let Some(g) = gpu() else { return };
    let (whole, none, mut g) = run(g, m);
    let failed = whole.last().unwrap().1[0];
    eprintln!("{name}: {failed} interfaces failed");
    assert!(failed >= failing, "{name}: {failed} interfaces failed");
    assert!(
        none.is_empty(),
        "{name}: nothing split at the device's limit"
    );
    for a in arrays {
        let (h, bytes, parts) = split_one(g, m, a);
        eprintln!("{name}: {a} in parts of {bytes} bytes: {parts:?}");
        assert!(
            parts.len() == 1 && parts[0].0 == *a && parts[0].1 > 1,
            "{name}: {a} alone is split"
        );
        g = h;
        if runs.contains(a) {
            let (rows, _, h) = run(g, m);
            g = h;
            assert_eq!(whole.len(), rows.len(), "{name}, {a} split: outputs");
            for (x, y) in whole.iter().zip(&rows) {
                assert_eq!(x.0, y.0, "{name}, {a} split: step");
                assert!(
                    x.1 == y.1,
                    "{name}, {a} split: the same bits at step {}",
                    x.0
                );
            }
        }
    }
}

/// The block of the GPU tests (plastic, SPC, prescribed motion, body load) with every element
/// in a MODEL 3 group (a linear cohesive law) that cracks under its shear: the interfaces and
/// the softening faces' arrays are split too.
#[test]
fn a_cracking_block_gives_the_same_bits_split() {
    let mut m = block(Hourglass::Viscous);
    m.separations.push(SeparationDef {
        material: 0,
        model: 3,
        sigmax: 250e6,
        beta: 1.0,
        gc: 2e3,
        bond: 1,
        strength: Default::default(),
    });
    let all = [
        "par", "conn", "xs", "vs", "vns", "mass", "sig", "hist", "hgf", "bq", "fe_lo", "fe_hi",
        "nptr", "ninc", "nflag", "mptr", "ifu", "ifs",
    ];
    let runs = ["xs", "vs", "sig", "fe_hi", "ninc", "ifu", "ifs"];
    same_bits_split("cracking block", &m, &all, &runs, 10);
}

/// The block with fully integrated hexahedra (ELFORM 2: 104 values per element at its Gauss
/// points, the largest array there is).
#[test]
fn fully_integrated_hexahedra_give_the_same_bits_split() {
    let mut m = block(Hourglass::Stiffness);
    m.sections[0].elform = 2;
    same_bits_split("ELFORM 2 block", &m, &["gps"], &["gps"], 0);
}

/// A model whose arrays need more parts than the device has bindings is refused with the
/// count (`GpuError::TooLarge`, exit 2 from `cleave run --gpu`), never bound short; on a
/// device with bindings enough it runs.
#[test]
fn too_many_parts_are_refused_by_count() {
    let Some(mut g) = gpu() else { return };
    let m = block(Hourglass::Viscous);
    let names = [
        "xs", "vs", "vns", "sig", "hist", "hgf", "fe_lo", "fe_hi", "par", "conn",
    ];
    g.force_split = names.iter().map(|n| (n.to_string(), 256)).collect();
    let most = g.limits.max_storage_buffers_per_shader_stage;
    let mut s = solver(&split_model(&m), &m);
    match GpuStepper::new(g, &mut s) {
        Ok(st) => {
            let parts: usize = st.split_arrays().iter().map(|p| p.1).sum();
            eprintln!("{parts} parts bound ({most} bindings)");
            assert_eq!(st.split_arrays().len(), names.len());
        }
        Err(e) => {
            let e = e.to_string();
            eprintln!("{e}");
            assert!(
                e.contains("storage bindings") && e.contains(&format!("it has {most}")),
                "{e}"
            );
        }
    }
}
