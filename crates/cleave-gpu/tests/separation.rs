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

use cleave_core::contact::ContactSet;
use cleave_core::curve::Curve;
use cleave_core::math::Vec3;
use cleave_core::mesh::{box_model, BoxMesh};
use cleave_core::model::{
    ContactDef, Hourglass, Material, MaterialKind, Model, MotionTarget, Part, PrescribedMotion,
    SeparationDef, Vad,
};
use cleave_core::separation::interfaces::{Separation, Status};
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
    /// Kinetic, internal, hourglass, external work, fracture (cohesive laws), contact.
    energy: [f64; 6],
    /// Interfaces fully open (free).
    free: usize,
    /// With contact: closed cracks now, and released so far (contact/closure.rs).
    cracks: (usize, u64),
    /// Elements eroded so far (a material with erosion beside the group's).
    eroded: usize,
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
            energy: [
                e.kinetic,
                e.internal,
                e.hourglass,
                e.external_work,
                e.fracture,
                e.contact,
            ],
            free: {
                let sep = s.separation().unwrap();
                (sep.failed_interfaces())
                    .filter(|&i| sep.status(i) == Status::Free)
                    .count()
            },
            cracks: s
                .contact()
                .map_or((0, 0), |c| (c.stats().closed, c.stats().released)),
            eroded: s.eroded_count(),
        });
        Ok(())
    }
    fn next_due(&self) -> f64 {
        self.next
    }
}

/// The solver of a split model, with its contact when the deck has one.
fn solver(split: &SplitModel) -> Solver<'_> {
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(split).unwrap());
    if !split.model.contacts.is_empty() {
        s.attach_contact(ContactSet::new(&split.model, Some(&split.origin)).unwrap());
    }
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
    let (rows, st, _, ()) = run_gpu_after(g, split, every, |_| ());
    (rows, st.into_gpu())
}

/// A GPU run of `split` with its stepper set by `set` first: the rows, the stepper and the
/// solver after the run, and what `set` gave.
fn run_gpu_after<'a, R>(
    g: Gpu,
    split: &'a SplitModel,
    every: f64,
    set: impl FnOnce(&mut GpuStepper) -> R,
) -> (Vec<Row>, GpuStepper, Solver<'a>, R) {
    let mut s = solver(split);
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let got = set(&mut st);
    let mut r = Record {
        every,
        next: 0.0,
        rows: Vec::new(),
    };
    st.run(&mut s, &mut r).unwrap();
    (r.rows, st, s, got)
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
    compare_rows(split, every, name).map(|(cpu, _)| cpu)
}

/// [`compare`], returning the CPU's rows and the GPU's.
fn compare_rows(split: &SplitModel, every: f64, name: &str) -> Option<(Vec<Row>, Vec<Row>)> {
    let g = gpu()?;
    let cpu = run_cpu(split, every);
    let (gpu1, g) = run_gpu(g, split, every);
    let (gpu2, _) = run_gpu(g, split, every);
    assert!(gpu1 == gpu2, "{name}: two GPU runs differ");
    assert_eq!(cpu.len(), gpu1.len(), "{name}: the same output times");
    let mut worst = [0.0f64; 4];
    for (a, b) in cpu.iter().zip(&gpu1) {
        assert_eq!(a.step, b.step, "{name}: step at t = {}", a.t);
        // (the time sums the steps, which the cohesive springs may set: 1e-9 as the fields)
        assert!(
            (a.t - b.t).abs() <= 1e-9 * a.t,
            "{name}: t {} vs {}",
            a.t,
            b.t
        );
        assert_eq!(
            a.failed, b.failed,
            "{name}: failed interfaces at t = {}",
            a.t
        );
        assert_eq!(a.free, b.free, "{name}: open interfaces at t = {}", a.t);
        assert_eq!(
            a.cracks, b.cracks,
            "{name}: closed and released cracks at t = {}",
            a.t
        );
        assert_eq!(a.eroded, b.eroded, "{name}: eroded elements at t = {}", a.t);
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
    Some((cpu, gpu1))
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
    pulled_bar_with(1, 0.0, 0.9)
}

/// The pulled bar with separation MODEL `model` (GC `gc`), run to `ends` times L / c.
fn pulled_bar_with(model: i32, gc: f64, ends: f64) -> Model {
    let h = BAR_L / BAR_N as f64;
    let c = (YOUNG / RHO).sqrt();
    let mat = Material {
        id: 1,
        density: RHO,
        young: YOUNG,
        poisson: 0.0,
        kind: MaterialKind::Elastic,
    };
    let mut m = box_model([BAR_N, 1, 1], [BAR_L, h, h], mat, ends * BAR_L / c);
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0],
        y: vec![1.0],
    });
    for (x, sf) in [(0.0, -PULL), (BAR_L, PULL)] {
        for node in m.nodes_where(0, x, 1e-12) {
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(0),
                vad: Vad::Velocity,
                curve: 0,
                sf,
            });
        }
    }
    m.separations.push(SeparationDef {
        material: 0,
        model,
        sigmax: 1.5 * RHO * c * PULL,
        beta: 1.0,
        gc,
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

/// The CPU's broken bar pushed back (cleave-core tests/contact.rs `bar_pushed_back`): the
/// pulled bar with single surface contact, pulled at 10 m/s until 15 us (it breaks in the
/// middle at 9.9 us), then pushed back at 10 m/s, so that the compression waves close the
/// crack at about 25 us and its faces push on each other through the closed crack's pairs
/// (contact/closure.rs), to 70 us.
fn bar_pushed_back() -> Model {
    let mut m = pulled_bar();
    m.control.end_time = 70e-6;
    m.curves[0] = Curve {
        id: 1,
        t: vec![0.0, 15e-6, 16e-6, 1.0],
        y: vec![1.0, 1.0, -1.0, -1.0],
    };
    m.contacts.push(ContactDef::single_surface_all(0.0, 0.0));
    m
}

/// The broken bar pushed back on the GPU as on the CPU: the crack opens in the same step, its
/// faces join the contact and close on each other, with the CPU's positions, velocities,
/// stresses and energies (the contact's among them) to round-off, and on the GPU they do not
/// pass through each other: the largest interpenetration of the crack's node pairs is below 5% of the
/// element (the CPU test's bound, from the penalty's own estimate of 4.4%; without contact
/// the pieces pass through each other by a whole element).
#[test]
fn broken_bar_pushed_back_closes_as_on_the_cpu() {
    let split = split_model(&bar_pushed_back());
    let every = split.model.control.end_time / 35.0;
    let Some((_, gpu)) = compare_rows(&split, every, "bar pushed back") else {
        return;
    };
    let last = gpu.last().unwrap();
    assert!(!last.failed.is_empty(), "it breaks");
    // the crack's pairs: the copies of one deck node, left (lower x at the start) and right
    let h = BAR_L / BAR_N as f64;
    let mut worst = 0.0f64;
    for r in &gpu {
        for d in 0..split.origin.iter().max().map_or(0, |&d| d + 1) {
            let copies: Vec<usize> = (0..split.origin.len())
                .filter(|&i| split.origin[i] == d)
                .collect();
            for &a in &copies {
                for &b in &copies {
                    let (ea, eb) = (elem_x(&split, a), elem_x(&split, b));
                    if ea < eb {
                        worst = worst.max(r.x[a][0] - r.x[b][0]);
                    }
                }
            }
        }
    }
    let contact = last.energy[5];
    eprintln!(
        "bar pushed back: interpenetration {:.4} h, contact energy {contact:.3e} J",
        worst / h
    );
    assert!(contact > 0.0, "the crack's faces pushed on each other");
    assert!(worst < 0.05 * h, "the faces pass through: {} h", worst / h);
}

/// The x of the centre of the element of node copy `i` of a split model (each copy belongs to
/// one element).
fn elem_x(split: &SplitModel, i: usize) -> f64 {
    let m = &split.model;
    let e = (m.conn.iter())
        .position(|c| c.contains(&(i as u32)))
        .expect("a copy of an element");
    m.conn[e].iter().map(|&a| m.x0[a as usize][0]).sum::<f64>() / 8.0
}

/// A solver that keeps a position for every node copy (`attach_separation_per_node`) is
/// refused by name: the GPU steps each coincident set as one slot.
#[test]
fn a_solver_with_a_position_per_copy_is_refused() {
    let Some(g) = gpu() else { return };
    let split = split_model(&pulled_bar());
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation_per_node(Separation::new(&split).unwrap());
    match GpuStepper::new(g, &mut s) {
        Err(cleave_gpu::GpuError::Unsupported(what)) => assert!(
            what.contains("a position kept for every node copy"),
            "{what}"
        ),
        Err(e) => panic!("refused otherwise: {e}"),
        Ok(_) => panic!("accepted"),
    }
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

/// The cracking block with single surface contact and friction: its crack faces join the
/// surface in the step they fail and close on each other, the closed cracks that slide or open
/// apart are released to the node-to-face contact, and only the leads of the coincident sets
/// are checked. The same failures, closed and released cracks in the same steps as on the
/// CPU, the fields and energies (the contact's among them) to round-off.
#[test]
fn cracking_block_in_contact_as_on_the_cpu() {
    let split = split_model(&cracking_block_in_contact());
    let every = split.model.control.end_time / 40.0;
    let Some((_, gpu)) = compare_rows(&split, every, "cracking block in contact") else {
        return;
    };
    let last = gpu.last().unwrap();
    eprintln!(
        "cracking block in contact: {} failed, closed cracks {}, released {}, contact energy {:.3e} J",
        last.failed.len(),
        last.cracks.0,
        last.cracks.1,
        last.energy[5]
    );
    assert!(last.failed.len() >= 20);
    assert!(
        last.cracks.0 + last.cracks.1 as usize >= 20,
        "{:?}",
        last.cracks
    );
}

/// Timing each pass over a run (`GpuStepper::time_passes`, `cleave bench ball --gpu
/// --passes`: each pass in a compute pass of its own, the steps that halt for a split or a
/// crack's release and the rest of such a step included) changes no result: the cracking block
/// in contact gives the same rows bit for bit. The times are of every pass, each finite and
/// not negative, with device time in the element pass and the node checks (on a device without
/// timestamp queries there are none, and the test says so). The host's halts are counted: at
/// least one split and one release, no more than the interfaces failed and cracks released.
#[test]
fn timing_each_pass_changes_no_result() {
    let Some(g) = gpu() else {
        return;
    };
    let split = split_model(&cracking_block_in_contact());
    let every = split.model.control.end_time / 40.0;
    let (plain, g) = run_gpu(g, &split, every);
    let (rows, st, s, timed) = run_gpu_after(g, &split, every, |st| st.time_passes(true));
    assert!(rows == plain, "timing the passes changed the run");
    let last = plain.last().unwrap();
    assert!(
        last.failed.len() >= 20 && last.cracks.1 > 0,
        "{:?}",
        last.cracks
    );
    // the host's halts: each split releases an interface at least, each release a crack; no
    // erosion in this deck
    let [split, eroded, released] = st.host_halts();
    eprintln!("host halts: splits {split:?}, erosions {eroded:?}, releases {released:?}");
    assert!(split.0 >= 1 && split.0 as usize <= last.failed.len() && split.1 > 0.0);
    assert!(released.0 >= 1 && released.0 <= last.cracks.1 && released.1 > 0.0);
    assert_eq!(eroded, (0, 0.0));
    if !timed {
        eprintln!("SKIPPED the times: the device has no timestamp queries");
        assert!(st.pass_times().is_none());
        return;
    }
    let times = st.pass_times().unwrap();
    eprintln!("pass times over {} steps: {times:?}", s.state.step);
    assert!(times.iter().all(|(_, t)| t.is_finite() && *t >= 0.0));
    for name in ["elements", "interfaces", "c_detect", "c_close", "nodes"] {
        let t = times.iter().find(|p| p.0 == name).map(|p| p.1);
        assert!(t.is_some_and(|t| t > 0.0), "{name}: {t:?}");
    }
}

/// A step's failures read back in two parts (the head with the rest of the split's read-back,
/// here one failure, then the others) give the run of one part, bit for bit; some step of this
/// deck releases more than one interface, so the second part is read.
#[test]
fn a_long_failure_list_is_read_in_two_parts() {
    let Some(g) = gpu() else {
        return;
    };
    let split = split_model(&cracking_block_in_contact());
    let every = split.model.control.end_time / 40.0;
    let (plain, g) = run_gpu(g, &split, every);
    let (rows, st, ..) = run_gpu_after(g, &split, every, |st| st.set_failure_list_head(1));
    assert!(
        rows == plain,
        "reading the failures in two parts changed the run"
    );
    let [split, ..] = st.host_halts();
    let failed = plain.last().unwrap().failed.len();
    eprintln!("{failed} interfaces failed in {} splits", split.0);
    assert!((split.0 as usize) < failed);
}

/// New contact tables (at each split and crack release) are written into the buffers of the
/// ones before, whose grid and work arrays hold what the last step left at the old tables'
/// offsets; they are zeroed by the first commands recorded after, before any contact pass
/// (`ContactGpu::clear`). Poisoned at every such write (7 in every word: counts that must not
/// start from it), the cracking block in contact gives the same rows bit for bit.
#[test]
fn the_contact_grid_is_zeroed_after_new_tables() {
    let Some(g) = gpu() else {
        return;
    };
    let split = split_model(&cracking_block_in_contact());
    let every = split.model.control.end_time / 40.0;
    let (plain, g) = run_gpu(g, &split, every);
    let (rows, mut st, ..) = run_gpu_after(g, &split, every, |st| {
        st.poison_contact_grid(Some(7));
    });
    let poisoned = st.poison_contact_grid(None);
    eprintln!("{poisoned} buffers of the grid and work arrays poisoned");
    assert!(poisoned >= 10);
    assert!(rows == plain, "a poisoned grid changed the run");
}

/// The cracking block with single surface contact with friction (FS 0.3, FD 0.2).
fn cracking_block_in_contact() -> Model {
    let mut m = cracking_block();
    m.contacts.push(ContactDef::single_surface_all(0.3, 0.2));
    m
}

/// A steel block (3 x 3 x 3 elements of 4/3 mm) in a MODEL 1 group (SIGMAX 1 GPa) at 300 m/s
/// onto a steel plate (6 x 6 x 3 elements of 2 mm, clamped at its rim) whose elements erode at
/// a pressure of 2 GPa (`*MAT_ADD_EROSION` MXPRES), single surface contact with friction: the
/// block cracks as the plate's elements under it erode, so the host changes the surfaces for
/// both (HALT 5, the faces of the eroded elements leaving and those they covered joining;
/// HALT 4, the sets split and the crack faces joining), in two steps both (measured: 4
/// elements erode, in steps 9, 10 and 13; 23 interfaces fail, in steps 10 and 13 among others).
/// (The order of the two halts in such a step cannot show here: with erosion in another
/// material than the group's the split reads nothing of it.)
fn cracking_block_on_an_eroding_plate() -> Model {
    let (mut m, hard) = common::block_on_an_eroding_plate("cracking block on an eroding plate", 3);
    m.separations.push(SeparationDef {
        material: hard,
        model: 1,
        sigmax: 1e9,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    });
    m.contacts.push(ContactDef::single_surface_all(0.2, 0.2));
    m
}

/// A device lost as a halt reads the state (destroyed as the k-th read of the run starts: an
/// output's, an erosion's or a split's, whichever comes k-th) stops the run with the device's
/// error, without a panic (wgpu's `create_buffer_init`, which the halts' writes used, panics
/// on a lost device), and nothing of what the lost device read back reaches the host: its
/// positions stay finite and no element is taken for eroded (a NaN erosion flag reads as set).
#[test]
fn a_device_lost_in_a_halts_read_stops_the_run_with_its_error() {
    let split = split_model(&cracking_block_on_an_eroding_plate());
    // (outputs at the start and the end only: the reads between are the halts')
    let every = split.model.control.end_time;
    for k in 1..=5 {
        let Some(g) = gpu() else { return };
        let mut s = solver(&split);
        let mut st = GpuStepper::new(g, &mut s).unwrap();
        st.lose_device_in_read(k);
        let mut r = Record {
            every,
            next: 0.0,
            rows: Vec::new(),
        };
        let run = st.run(&mut s, &mut r);
        let Err(cleave_core::solver::RunError::Device(msg)) = run else {
            panic!("read {k}: the run goes on or fails otherwise: {run:?}");
        };
        assert!(msg.contains("the device was lost"), "read {k}: {msg}");
        assert!(
            (s.positions().iter().flatten()).all(|v| v.is_finite()),
            "read {k}: positions"
        );
        // (4 elements erode in the whole run)
        assert!(
            s.eroded_count() <= 4,
            "read {k}: {} eroded",
            s.eroded_count()
        );
    }
}

/// Erosion beside element separation on the GPU as on the CPU: the same elements erode and the
/// same interfaces fail in the same steps, the same cracks close and are released, the fields
/// and energies to round-off; and the run taken up from its state saved midway, between
/// erosions and failures, ends in the same bits. (With the closed cracks' states not taken
/// from the GPU before an erosion's halt remakes the contact's tables, the velocities were 1e-3
/// off after the first one.)
#[test]
fn a_cracking_block_on_an_eroding_plate_as_on_the_cpu() {
    let split = split_model(&cracking_block_on_an_eroding_plate());
    let every = split.model.control.end_time / 40.0;
    let Some((cpu, _)) = compare_rows(&split, every, "cracking block on an eroding plate") else {
        return;
    };
    let last = cpu.last().unwrap();
    let first_eroded = cpu.iter().position(|r| r.eroded > 0);
    let first_failed = cpu.iter().position(|r| !r.failed.is_empty());
    eprintln!(
        "cracking block on an eroding plate: {} eroded (first by output {first_eroded:?}), {} interfaces failed (first by output {first_failed:?}), cracks closed and released {:?}",
        last.eroded,
        last.failed.len(),
        last.cracks
    );
    assert!(last.eroded >= 3, "{} eroded", last.eroded);
    assert!(last.failed.len() >= 10, "{} failed", last.failed.len());
    // the state is taken after the first erosion and failures (at the first halt at or after
    // 1.7 us), and both go on after it
    let at = 0.17;
    let then = cpu
        .iter()
        .find(|r| r.t >= at * split.model.control.end_time)
        .unwrap();
    assert!(
        then.eroded > 0 && then.eroded < last.eroded,
        "{}",
        then.eroded
    );
    assert!(then.failed.len() < last.failed.len());
    assert!(continues_from_its_saved_state(
        "cracking block on an eroding plate",
        &split,
        at
    ));
}

/// Takes the GPU's state once, at the first halt at or after `due`, and records as [`Record`].
struct TakeState {
    record: Record,
    due: f64,
    /// The time, the number of failed interfaces and of softening ones, and the GPU's state.
    taken: Option<(f64, usize, usize, Vec<u8>)>,
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
        let sep = s.separation().unwrap();
        let softening = (sep.failed_interfaces())
            .filter(|&i| sep.status(i) == Status::Softening)
            .count();
        self.taken = Some((s.state.t, sep.num_failed(), softening, gpu_state));
        self.due = f64::INFINITY;
        Ok(())
    }
}

/// A run taken up from the GPU state saved midway, after interfaces have failed (with the
/// interfaces and sets as they have split, the softening faces' state, the contact's surfaces,
/// closed cracks and pairs, `GpuStepper::save`), ends in the same bits as the run that went
/// through: the cracking block (MODEL 2, with interfaces yet to fail), the spinning BETA 8
/// block (MODEL 3, with faces softening) and the cracking block in contact (with cracks closed
/// and yet to be released; and later, with cracks let go on the device in place since its
/// tables were last made: 5 of its 44 at 85% of the run, by a count added for one review run).
#[test]
fn a_cracking_run_continues_from_its_saved_state() {
    // (the spinning block's 45 interfaces fail by 5% of its run and open fully by 10%)
    for (name, m, at) in [
        ("cracking block", cracking_block(), 0.5),
        ("BETA 8 block", spinning_block(), 0.07),
        (
            "cracking block in contact",
            cracking_block_in_contact(),
            0.6,
        ),
        (
            "cracking block in contact, cracks let go in place",
            cracking_block_in_contact(),
            0.85,
        ),
    ] {
        if !continues_from_its_saved_state(name, &split_model(&m), at) {
            return;
        }
    }
}

/// [`a_cracking_run_continues_from_its_saved_state`] for one model; false without a GPU.
fn continues_from_its_saved_state(name: &str, split: &SplitModel, at: f64) -> bool {
    let Some(g) = gpu() else { return false };
    let end = split.model.control.end_time;
    let every = end / 40.0;
    let record = || Record {
        every,
        next: 0.0,
        rows: Vec::new(),
    };
    let mut s = solver(split);
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut obs = TakeState {
        record: record(),
        due: at * end,
        taken: None,
    };
    st.run_checkpointed(&mut s, &mut obs).unwrap();
    let through = obs.record.rows.last().unwrap().clone();
    let (t, failed_then, softening, state) = obs.taken.expect("a state taken midway");
    assert!(
        failed_then > 0,
        "{name}: interfaces failed before the state was taken"
    );
    // the state holds what the rest of the run changes: interfaces yet to fail, or faces
    // still softening
    assert!(
        through.failed.len() > failed_then || softening > 0,
        "{name}: nothing left to happen"
    );
    let mut s2 = solver(split);
    let mut st2 = GpuStepper::new(st.into_gpu(), &mut s2).unwrap();
    st2.load(&mut s2, &state).unwrap();
    assert_eq!(s2.state.t, t);
    assert_eq!(s2.separation().unwrap().num_failed(), failed_then);
    let mut r = record();
    r.next = t;
    st2.run(&mut s2, &mut r).unwrap();
    let again = r.rows.last().unwrap();
    eprintln!(
        "{name}: continued from t = {t:e} ({failed_then} interfaces failed then, {softening} softening): {} at the end",
        again.failed.len()
    );
    assert!(
        *again == through,
        "{name}: the continued run ends elsewhere"
    );
    true
}

/// The cohesive bar of the CPU tests (cleave-core tests/separation.rs `cohesive_bar`): the
/// pulled bar whose two middle elements alone form the group (BOND 0: one cohesive plane),
/// SIGMAX = 1.5 rho c v, GC = SIGMAX 50 um / 2, the ends also driven sideways at -/+ `slide`
/// (mixed mode), to 1.8 L / c.
fn cohesive_bar(model: i32, slide: f64) -> Model {
    let c = (YOUNG / RHO).sqrt();
    let sigmax = 1.5 * RHO * c * PULL;
    let mut bar = pulled_bar_with(model, sigmax * 50e-6 / 2.0, 1.8);
    for (x, sf) in [(0.0, -slide), (BAR_L, slide)] {
        for node in bar.nodes_where(0, x, 1e-12) {
            bar.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(1),
                vad: Vad::Velocity,
                curve: 0,
                sf,
            });
        }
    }
    bar.materials.push(Material {
        id: 2,
        ..bar.materials[0].clone()
    });
    bar.parts.push(Part {
        id: 2,
        title: "middle".into(),
        section: 0,
        material: 1,
        hourglass: None,
    });
    for e in [BAR_N / 2 - 1, BAR_N / 2] {
        bar.elem_part[e] = 1;
    }
    bar.separations[0].material = 1;
    bar.separations[0].bond = 0;
    bar
}

/// The cohesive laws on the GPU: the linear law (MODEL 3) in mode I and the exponential one
/// (MODEL 4) in mixed mode open the middle plane in the same steps as on the CPU, with the
/// same fracture energy (the cohesive work, to 1e-9), which is GC times the crack area within
/// 2% once the crack is fully open (the CPU test's bound: the trapezoid work is exact but for
/// the steps of onset and full opening).
#[test]
fn cohesive_laws_open_as_on_the_cpu() {
    for (model, slide) in [(3, 0.0), (4, 3.0)] {
        let bar = cohesive_bar(model, slide);
        let split = split_model(&bar);
        assert_eq!(split.interfaces, 1);
        let every = bar.control.end_time / 40.0;
        let name = format!("cohesive bar, MODEL {model}, slide {slide} m/s");
        let Some(cpu) = compare(&split, every, &name) else {
            return;
        };
        let last = cpu.last().unwrap();
        let h = BAR_L / BAR_N as f64;
        let gc = bar.separations[0].gc;
        let fracture = last.energy[4];
        eprintln!(
            "{name}: fracture energy {fracture:.6e} J, GC x area {:.6e} J",
            gc * h * h
        );
        assert_eq!(last.free, 1, "{name}: the crack opens fully");
        assert!((fracture - gc * h * h).abs() < 0.02 * gc * h * h, "{name}");
    }
}

/// 6 x 3 x 3 alumina elements thrown spinning, all in one MODEL 3 group of BETA 8 (the CPU
/// tests' stiff sliding law).
fn spinning_block() -> Model {
    let mat = Material {
        id: 1,
        density: 3900.0,
        young: 370e9,
        poisson: 0.22,
        kind: MaterialKind::Elastic,
    };
    let (lx, ly, lz) = (0.06, 0.03, 0.03);
    let mut m = box_model([6, 3, 3], [lx, ly, lz], mat, 20e-6);
    m.control.tssfac = 0.2;
    let centre = [lx / 2.0, ly / 2.0, lz / 2.0];
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        let r = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
        *v = [-2000.0 * r[1] + 300.0 * r[0], 2000.0 * r[0], 0.0];
    }
    m.separations.push(SeparationDef {
        material: 0,
        model: 3,
        sigmax: 100e6,
        beta: 8.0,
        gc: 40.0,
        bond: 1,
        strength: Default::default(),
    });
    m
}

/// Steps on the CPU whose time step is the cohesive springs' (observed every step).
struct BoundSteps(usize);
impl Observer for BoundSteps {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        let coh = s.separation().unwrap().cohesive_time_step();
        self.0 += (s.state.dt == coh) as usize;
        Ok(())
    }
}

/// The spinning block ([`spinning_block`], cleave-core tests/separation.rs, the stiff sliding
/// law), whose sliding springs bound the time step after release. On the GPU the same interfaces fail and
/// open in the same steps as on the CPU (so the springs' step is taken as there), with the
/// same fracture energy.
#[test]
fn a_stiff_sliding_law_bounds_the_step_as_on_the_cpu() {
    let m = spinning_block();
    let split = split_model(&m);
    let mut bound = BoundSteps(0);
    solver(&split).run(&mut bound).unwrap();
    let every = m.control.end_time / 40.0;
    let Some(cpu) = compare(&split, every, "BETA 8 block") else {
        return;
    };
    let last = cpu.last().unwrap();
    eprintln!(
        "BETA 8 block: {} steps, {} of them at the cohesive springs' step; {} interfaces failed, {} open",
        last.step,
        bound.0,
        last.failed.len(),
        last.free
    );
    assert!(bound.0 > 0, "the springs bound the step");
    assert!(last.failed.len() > 10 && last.free > 0);
}

/// Separation on tetrahedra and wedges (interfaces of 3 node pairs where a face is a
/// triangle): the cracking block (MODEL 2) and the spinning block (MODEL 3, cohesive faces
/// of 3 points) cut into tetrahedra (ELFORM 10) and into wedges fail, soften and open as on
/// the CPU.
#[test]
fn tetrahedra_and_wedges_separate_as_on_the_cpu() {
    type Cut = fn(&BoxMesh) -> BoxMesh;
    let cuts: [(&str, Cut, i32); 2] = [
        ("tetrahedra", BoxMesh::split_tets, 10),
        ("wedges", BoxMesh::split_wedges, 1),
    ];
    for (shape, cut, elform) in cuts {
        // the spinning block's first quarter (its pieces then fly apart for 1500 steps more,
        // in which the round-off of the springs' opening grows to 5e-9 in the stresses)
        let mut spinning = spinning_block();
        spinning.control.end_time *= 0.25;
        for (name, mut m, dims) in [
            (
                "cracking block",
                cracking_block(),
                ([3, 3, 6], [0.03, 0.03, 0.06]),
            ),
            ("BETA 8 block", spinning, ([6, 3, 3], [0.06, 0.03, 0.03])),
        ] {
            let mesh = cut(&BoxMesh::new(dims.0, dims.1));
            assert_eq!(mesh.x.len(), m.x0.len(), "the same nodes");
            let ne = mesh.conn.len();
            m.conn = mesh.conn;
            m.elem_ids = (1..=ne as i64).collect();
            m.elem_part = vec![0; ne];
            m.sections[0].elform = elform;
            let split = split_model(&m);
            let every = m.control.end_time / 30.0;
            let name = format!("{name} of {shape}");
            let Some(cpu) = compare(&split, every, &name) else {
                return;
            };
            let last = cpu.last().unwrap();
            assert!(!last.failed.is_empty(), "{name}: nothing failed");
            if name.starts_with("BETA") {
                assert!(last.free > 0, "{name}: nothing opened");
            }
        }
    }
}

/// A closed crack's release lets it go on the device in place (its state zeroed and marked, the
/// chain labels written again: `ContactGpu::release_in_place`) where the contact's tables were
/// made again before: the cracking block in contact (14 releases) gives the same rows bit for
/// bit either way.
#[test]
fn cracks_released_in_place_run_as_with_new_tables() {
    let Some(g) = gpu() else {
        return;
    };
    let split = split_model(&cracking_block_in_contact());
    let every = split.model.control.end_time / 40.0;
    let (rows, mut st, ..) = run_gpu_after(g, &split, every, |_| ());
    let [in_place, remade] = st.contact_releases(false);
    eprintln!("{in_place} releases in place, {remade} with new tables");
    assert!(in_place >= 10 && remade == 0, "{in_place} {remade}");
    let (again, mut st, ..) = run_gpu_after(st.into_gpu(), &split, every, |st| {
        st.contact_releases(true);
    });
    assert_eq!(st.contact_releases(false), [0, in_place]);
    assert!(rows == again, "the releases in place changed the run");
}

/// The contact's candidate lists with element separation (the lists made again after the
/// splits, chain labels written again as closed cracks let go in place): the cracking block in
/// contact gives the same rows bit for bit with the lists as with none (every node against its
/// cell every step), and since the last tables each list held every face whose search sphere
/// held its node (checked against the node's cell every step).
#[test]
fn the_candidate_lists_change_no_bit_of_a_cracking_run() {
    let Some(g) = gpu() else {
        return;
    };
    let split = split_model(&cracking_block_in_contact());
    let every = split.model.control.end_time / 40.0;
    let (rows, st, ..) = run_gpu_after(g, &split, every, |st| st.set_contact_cands(64, true));
    let [builds, missed, sought] = st.contact_lists();
    eprintln!("lists made {builds} times, {sought} faces sought");
    assert!(
        builds >= 1 && missed == 0 && sought > 100,
        "lists made {builds} times, {missed} of {sought} faces not on them"
    );
    let (none, ..) = run_gpu_after(st.into_gpu(), &split, every, |st| {
        st.set_contact_cands(0, false)
    });
    assert!(rows == none, "the lists changed the run");
}
