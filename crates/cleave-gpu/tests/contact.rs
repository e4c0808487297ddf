//! Automatic contact on the GPU against the CPU (issue 30, stage 3): every history value of a
//! run with contact within 1e-9 of the CPU's (the criterion for runs without
//! fracture), and a repeated GPU run bit for bit.
//!
//! The cases: a sphere hitting a rigid plate (surface to surface, PENOPT 1 and 2, the rigid
//! body's faces), two blocks meeting at an angle with friction (single surface, both bodies
//! deformable), and the same of tetrahedra (triangular faces) and of wedges. Measured on
//! lavapipe: every field within 1e-12 of the CPU's (the test prints the figures).
//!
//! On lavapipe (CI): `cargo test --release -p cleave-gpu --test contact -- --nocapture`.

mod common;

use cleave_core::contact::ContactSet;
use cleave_core::math::Vec3;
use cleave_core::mesh::{ogrid_sphere, Assembly, BoxMesh};
use cleave_core::model::{
    ContactDef, ContactSurface, Hourglass, Material, MaterialKind, Model, PenaltyRule,
};
use cleave_core::solver::{Observer, Solver};
use cleave_gpu::{Gpu, GpuStepper};
use common::gpu;

#[derive(Clone, Debug, PartialEq)]
struct Row {
    t: f64,
    step: u64,
    /// Kinetic, internal, hourglass, contact energy, external work.
    energy: [f64; 5],
    /// The first definition's force, sum of |f_n| and pairs.
    force: Vec3,
    normal: f64,
    pairs: usize,
    x: Vec<Vec3>,
    v: Vec<Vec3>,
    eroded: Vec<bool>,
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
        let c = s.contact().expect("contact").forces()[0];
        self.rows.push(Row {
            t,
            step: s.state.step,
            energy: [
                e.kinetic,
                e.internal,
                e.hourglass,
                e.contact,
                e.external_work,
            ],
            force: c.force,
            normal: c.normal,
            pairs: c.pairs,
            x: s.positions().iter().copied().collect(),
            v: s.velocities().iter().copied().collect(),
            eroded: s.state.eroded.clone(),
        });
        Ok(())
    }
    fn next_due(&self) -> f64 {
        self.next
    }
}

fn solver(m: &Model) -> Solver<'_> {
    let mut s = Solver::new(m).unwrap();
    s.attach_contact(ContactSet::new(m, None).unwrap());
    s
}

fn run_cpu(m: &Model, every: f64) -> Vec<Row> {
    let mut r = Record {
        every,
        next: 0.0,
        rows: vec![],
    };
    solver(m).run(&mut r).unwrap();
    r.rows
}

fn run_gpu(g: Gpu, m: &Model, every: f64, lists: Option<[u32; 3]>) -> (Vec<Row>, Gpu) {
    let mut s = solver(m);
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    if let Some([short, long, reverse]) = lists {
        st.set_contact_lists(short, long, reverse != 0);
    }
    let mut r = Record {
        every,
        next: 0.0,
        rows: vec![],
    };
    st.run(&mut s, &mut r).unwrap();
    (r.rows, st.into_gpu())
}

/// Largest |a - b| over the largest |a| of a field.
fn rel(a: impl Iterator<Item = f64> + Clone, b: impl Iterator<Item = f64>) -> f64 {
    let scale = a.clone().fold(0.0f64, |m, x| m.max(x.abs()));
    let d = a.zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    d / scale.max(f64::MIN_POSITIVE)
}

/// The GPU's run of `m` against the CPU's: the same steps and times, every position,
/// velocity, energy and contact resultant within `tol` (relative to the field's largest
/// value); contact must have happened (`min_pairs` pairs at some output). Then the GPU run
/// again: the same bits. Returns the device.
fn compare(g: Gpu, m: &Model, every: f64, tol: f64, min_pairs: usize, name: &str) -> Gpu {
    compare_lists(g, m, (every, tol, min_pairs), name, None)
}

/// [`compare`], the lists of the nodes pushing on a face taking the paths of `lists` (the
/// longest one thread sorts and adds, the longest a group sorts in its own memory, 1 to fill
/// them from their end).
fn compare_lists(
    g: Gpu,
    m: &Model,
    (every, tol, min_pairs): (f64, f64, usize),
    name: &str,
    lists: Option<[u32; 3]>,
) -> Gpu {
    let cpu = run_cpu(m, every);
    let (gpu, g) = run_gpu(g, m, every, lists);
    assert_eq!(cpu.len(), gpu.len(), "{name}: outputs");
    let most = cpu.iter().map(|r| r.pairs).max().unwrap();
    let mut worst = [0.0f64; 5];
    for (a, b) in cpu.iter().zip(&gpu) {
        assert_eq!(a.step, b.step, "{name}: steps");
        assert!(
            (a.t - b.t).abs() <= tol * a.t,
            "{name}: times {} {}",
            a.t,
            b.t
        );
        if std::env::var("DEBUG_CONTACT").is_ok() {
            let (k, d) = (a.v.iter().zip(&b.v).enumerate())
                .map(|(k, (p, q))| (k, (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f64::max)))
                .fold((0, 0.0), |m, x| if x.1 > m.1 { x } else { m });
            println!(
                "t {} node {k} v cpu {:?} gpu {:?} (d {d}); x {:?} {:?}; f {:?} {:?}",
                a.t, a.v[k], b.v[k], a.x[k], b.x[k], a.force, b.force
            );
        }
        assert_eq!(a.pairs, b.pairs, "{name}: pairs at t = {}", a.t);
        assert!(
            a.eroded == b.eroded,
            "{name}: eroded elements at t = {}",
            a.t
        );
        let flat = |v: &[Vec3]| v.iter().flatten().copied().collect::<Vec<_>>();
        let d = [
            rel(flat(&a.x).into_iter(), flat(&b.x).into_iter()),
            rel(flat(&a.v).into_iter(), flat(&b.v).into_iter()),
            rel(a.energy.iter().copied(), b.energy.iter().copied()),
            // (single surface: the forces of the two bodies' nodes on each other cancel in
            // the resultant, so its scale is the total normal force)
            (0..3)
                .map(|k| (a.force[k] - b.force[k]).abs())
                .fold(0.0, f64::max)
                / a.normal.max(f64::MIN_POSITIVE),
            rel([a.normal].into_iter(), [b.normal].into_iter()),
        ];
        for (w, d) in worst.iter_mut().zip(d) {
            *w = w.max(d);
        }
    }
    let last = cpu.last().unwrap();
    println!(
        "{name}: {} steps, {} outputs, at most {most} pairs, {} elements eroded, contact energy {:.4e} J; GPU against CPU: x {:.1e}, v {:.1e}, energies {:.1e}, force {:.1e}, |f_n| {:.1e}",
        last.step,
        cpu.len(),
        last.eroded.iter().filter(|&&e| e).count(),
        last.energy[3],
        worst[0],
        worst[1],
        worst[2],
        worst[3],
        worst[4]
    );
    assert!(most >= min_pairs, "{name}: {most} pairs at most");
    for (what, w) in ["x", "v", "energies", "force", "|f_n|"].iter().zip(worst) {
        assert!(w <= tol, "{name}: {what} differ by {w:.3e}");
    }
    let (again, g) = run_gpu(g, m, every, lists);
    assert!(again == gpu, "{name}: a repeated GPU run differs");
    g
}

fn steel() -> Material {
    Material {
        id: 0,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    }
}

fn rigid() -> Material {
    Material {
        kind: MaterialKind::Rigid {
            cmo: 1,
            con1: 7,
            con2: 7,
        },
        young: 2000e9,
        ..steel()
    }
}

fn def(master: Option<usize>, fs: f64, fd: f64, dc: f64) -> ContactDef {
    ContactDef {
        id: 1,
        single_surface: master.is_none(),
        one_way: false,
        slave: if master.is_some() {
            ContactSurface::Part(0)
        } else {
            ContactSurface::All
        },
        master: master.map(ContactSurface::Part),
        fs,
        fd,
        dc,
    }
}

/// A steel sphere (radius 10 mm, O-grid of 10 x 3) at 20 m/s onto a fixed rigid plate,
/// surface to surface (slave: the sphere), SLSFAC 2, through the impact and the rebound.
///
/// Off the plate's centre by a fraction of an element: with the sphere's pole right above a
/// node of the plate, that node finds the sphere's four faces around the pole at gaps equal
/// but for round-off, and which one it takes (their normals tilt apart) is decided by the last
/// bit, which the GPU's arithmetic (another order of sums, fused multiply-adds) does not
/// reproduce. Such ties are knife edges of the geometry, not of the contact law.
fn sphere_on_plate() -> Model {
    let r = 0.01;
    let mut a = Assembly::new("sphere on plate", 1.0);
    let m = a.material(steel());
    let ball = a.part("sphere", m);
    let mut s = ogrid_sphere(r, 10, 3);
    s.translate([3.7e-4, r + 2e-5, 2.1e-4]);
    let (nodes, _) = a.mesh(s, |_| ball);
    let pm = a.material(rigid());
    let plate = a.part("plate", pm);
    let mut p = BoxMesh::new([6, 1, 6], [0.016, 0.002, 0.016]);
    p.translate([-0.008, -0.002, -0.008]);
    a.mesh(p, |_| plate);
    let mut m = a.finish();
    for i in nodes {
        m.v0[i as usize] = [0.0, -20.0, 0.0];
    }
    m.control.slsfac = 2.0;
    m.control.hourglass = Hourglass::Stiffness;
    m.control.end_time = 2.0e-5;
    m.contacts.push(def(Some(plate), 0.0, 0.0, 0.0));
    m
}

/// Two steel blocks (8 x 4 x 4 elements of 2.5 mm cut by `cut`) meeting face to face, the left
/// one at 10 m/s along x and 4 m/s along y: single surface contact with friction (FS 0.3,
/// FD 0.2, DC 50 s/m) while it slides along the other. The left block is offset by a fraction of
/// an element in y and z, so that no node lands on an edge of the other's faces (the ties of
/// [`sphere_on_plate`]).
fn blocks(cut: fn(BoxMesh) -> BoxMesh) -> Model {
    blocks_of(cut, [8, 4, 4])
}

/// [`blocks`] of `cells` elements each.
fn blocks_of(cut: fn(BoxMesh) -> BoxMesh, cells: [usize; 3]) -> Model {
    let l = 0.02;
    let mut a = Assembly::new("blocks", 1.0);
    let mat = a.material(steel());
    let left = a.part("left", mat);
    let right = a.part("right", mat);
    let mut bl = BoxMesh::new(cells, [l, 0.01, 0.01]);
    bl.translate([-l - 1e-5, 0.002, 0.0013]);
    let (ln, _) = a.mesh(cut(bl), |_| left);
    a.mesh(cut(BoxMesh::new(cells, [l, 0.01, 0.01])), |_| right);
    let mut m = a.finish();
    for i in ln {
        m.v0[i as usize] = [10.0, 4.0, 0.0];
    }
    m.control.end_time = 1.2e-5;
    m.contacts.push(def(None, 0.3, 0.2, 50.0));
    m
}

#[test]
fn sphere_on_a_rigid_plate_matches_the_cpu() {
    let Some(g) = gpu() else { return };
    compare(g, &sphere_on_plate(), 2e-6, 1e-9, 5, "sphere on plate");
}

#[test]
fn blocks_with_friction_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let g = compare(g, &blocks(|b| b), 1e-6, 1e-9, 25, "blocks, hexahedra");
    let g = compare(
        g,
        &blocks(|b| b.split_tets()),
        1e-6,
        1e-9,
        25,
        "blocks, tetrahedra",
    );
    compare(
        g,
        &blocks(|b| b.split_wedges()),
        1e-6,
        1e-9,
        25,
        "blocks, wedges",
    );
}

/// A fine block (n/2 x n x n elements, 10 mm a side) at 10 m/s onto one face of a coarse one
/// (one element, its face 20 x 20 mm), single surface contact with friction: the (n + 1)^2 nodes
/// of the fine face all push on the one coarse face, offset so that none lands on its edges.
fn fine_on_coarse(n: usize) -> Model {
    let mut a = Assembly::new("fine on coarse", 1.0);
    let mat = a.material(steel());
    let fine = a.part("fine", mat);
    let coarse = a.part("coarse", mat);
    let mut b = BoxMesh::new([n / 2, n, n], [0.01, 0.01, 0.01]);
    b.translate([-0.01 - 1e-5, 0.0052, 0.0047]);
    let (nodes, _) = a.mesh(b, |_| fine);
    a.mesh(BoxMesh::new([1, 1, 1], [0.01, 0.02, 0.02]), |_| coarse);
    let mut m = a.finish();
    for i in nodes {
        m.v0[i as usize] = [10.0, 0.0, 0.0];
    }
    m.control.end_time = 1.2e-5;
    m.contacts.push(def(None, 0.3, 0.2, 50.0));
    m
}

/// The reactions on a face that many nodes push on (289, 81: more than one thread adds, 16),
/// each face's list of those nodes sorted in a group's memory and added by the group's
/// threads, or, when longer than the group holds (here made 1), sorted in place by one thread
/// first; and on the finer blocks every list, however short, on the group's path (98 faces in
/// lists: each of the 32 groups takes several in turn). The sums are in an order of their own,
/// so the runs agree with the CPU's to the tolerance of the others, and a repeated run bit for
/// bit. Blocks of 16 x 8 x 8 elements, their 1280 faces in 4096 cells, take more than one group
/// in each scan (1024 a group) with contact all over their faces.
#[test]
fn long_lists_of_pushing_nodes_match_the_cpu() {
    let Some(g) = gpu() else { return };
    let g = compare(g, &fine_on_coarse(16), 1e-6, 1e-9, 289, "fine on coarse");
    let finer = blocks_of(|b| b, [16, 8, 8]);
    let g = compare(g, &finer, 1e-6, 1e-9, 81, "finer blocks");
    let g = compare_lists(
        g,
        &fine_on_coarse(8),
        (1e-6, 1e-9, 81),
        "fine on coarse, sorted in place",
        Some([16, 1, 0]),
    );
    compare_lists(
        g,
        &finer,
        (1e-6, 1e-9, 81),
        "finer blocks, every list by a group",
        Some([0, 1024, 0]),
    );
}

/// The order the lists of the nodes pushing on a face are filled in (by atomics: any) does not
/// change a bit of a run: filled from their end, each path's sorts give the same sums (one
/// thread's insertion sort of the 16 nodes on the coarse face of a 1 x 3 x 3 block, a group's
/// bitonic sort and the heap sort in place of the 81 of a 4 x 8 x 8 one).
#[test]
fn the_lists_order_does_not_change_the_run() {
    let Some(g) = gpu() else { return };
    let mut g = g;
    for (m, every, lists) in [
        (fine_on_coarse(3), 1e-6, [16, 1024]),
        (fine_on_coarse(8), 1e-6, [16, 1024]),
        (fine_on_coarse(8), 1e-6, [16, 1]),
    ] {
        let (a, g1) = run_gpu(g, &m, every, Some([lists[0], lists[1], 0]));
        let (b, g2) = run_gpu(g1, &m, every, Some([lists[0], lists[1], 1]));
        assert!(a.iter().any(|r| r.pairs > 0), "contact");
        assert!(
            a == b,
            "lists {lists:?}: filled from the end, the run differs"
        );
        g = g2;
    }
}

/// The candidate lists (contact.wgsl c_scan, c_detect) change no bit of a run: the blocks
/// sliding with friction (ten times as fast) and the sphere on its plate give the same rows
/// with lists as they are (64 faces), with lists of 2 (most nodes past theirs, checked against
/// their cells every step) and with none (every node against its cell every step). With lists,
/// the runs made them again as the motion passed the margin, not at every step, and at every
/// step each list held every face whose search sphere held its node (checked against the
/// node's cell: thousands looked for, none missed).
#[test]
fn the_candidate_lists_change_no_bit_of_a_run() {
    let Some(mut g) = gpu() else { return };
    // the blocks ten times as fast (100 m/s along x, 40 along y), to pass the margin often
    let mut fast = blocks(|b| b);
    fast.v0.iter_mut().flatten().for_each(|v| *v *= 10.0);
    for (name, m, every) in [("blocks", fast, 1e-6), ("sphere", sphere_on_plate(), 2e-6)] {
        let mut runs = vec![];
        for (cands, verify) in [(64, true), (64, false), (2, false), (0, false)] {
            let mut s = solver(&m);
            let mut st = GpuStepper::new(g, &mut s).unwrap();
            st.set_contact_cands(cands, verify);
            let mut r = Record {
                every,
                next: 0.0,
                rows: vec![],
            };
            st.run(&mut s, &mut r).unwrap();
            runs.push((r.rows, st.contact_lists(), s.state.step));
            g = st.into_gpu();
        }
        let (rows, [builds, missed, sought], steps) = &runs[0];
        assert!(rows.iter().any(|r| r.pairs > 0), "{name}: contact");
        assert!(
            *builds >= 2 && 4 * *builds < *steps,
            "{name}: the lists made {builds} times in {steps} steps"
        );
        assert!(
            *missed == 0 && *sought > 1000,
            "{name}: {missed} of {sought} faces not on the lists"
        );
        assert_eq!(runs[3].1[0], 0, "{name}: no lists of 0 faces");
        for (k, (other, _, _)) in runs.iter().enumerate().skip(1) {
            assert!(rows == other, "{name}: run {k} differs from the first");
        }
        eprintln!("{name}: lists made {builds} times in {steps} steps, {sought} faces sought");
    }
}

/// PENOPT 2 (each pair the face's stiffness) on the sphere.
#[test]
fn penopt_2_matches_the_cpu() {
    let Some(g) = gpu() else { return };
    let mut m = sphere_on_plate();
    m.control.penalty = PenaltyRule::Face;
    m.control.end_time = 1.5e-5;
    compare(g, &m, 3e-6, 1e-9, 5, "sphere on plate, PENOPT 2");
}

/// Takes the GPU state once, at `due`, while it records.
struct TakeState {
    record: Record,
    due: f64,
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

impl cleave_gpu::Checkpointing for TakeState {
    fn checkpoint_due(&self) -> f64 {
        self.due
    }
    fn stop_asked(&mut self) -> bool {
        false
    }
    fn checkpoint(&mut self, s: &Solver, gpu_state: Vec<u8>) -> std::io::Result<()> {
        let pairs = s.contact().unwrap().forces()[0].pairs;
        self.taken = Some((s.state.t, pairs, gpu_state));
        self.due = f64::INFINITY;
        Ok(())
    }
}

/// A run taken up from the GPU state saved while the blocks are in contact (the pairs'
/// engagement and friction forces, the last step's contact forces: `GpuStepper::save`) ends
/// in the same bits as the run that went through; so does the eroding plate's, taken up
/// between two erosions (the surfaces as they have changed, from the host's state).
#[test]
fn a_run_in_contact_continues_from_its_saved_state() {
    let Some(g) = gpu() else { return };
    let g = continues("blocks", g, &blocks(|b| b), 0.6);
    continues("eroding plate", g, &eroding_plate(), 0.25);
}

/// [`a_run_in_contact_continues_from_its_saved_state`] for model `m`, its state taken at
/// `at` of its run.
fn continues(name: &str, g: Gpu, m: &Model, at: f64) -> Gpu {
    let every = 1e-6;
    let record = || Record {
        every,
        next: 0.0,
        rows: vec![],
    };
    let mut s = solver(m);
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut obs = TakeState {
        record: record(),
        due: at * m.control.end_time,
        taken: None,
    };
    st.run_checkpointed(&mut s, &mut obs).unwrap();
    let through = obs.record.rows.last().unwrap().clone();
    let (t, pairs, state) = obs.taken.expect("a state taken midway");
    assert!(pairs > 0, "{name}: in contact when the state was taken");
    let eroded = |r: &Row| r.eroded.iter().filter(|&&e| e).count();
    let then = (obs.record.rows.iter())
        .rfind(|r| r.t <= t)
        .map_or(0, eroded);
    let mut s2 = solver(m);
    let mut st2 = GpuStepper::new(st.into_gpu(), &mut s2).unwrap();
    st2.load(&mut s2, &state).unwrap();
    assert_eq!(s2.state.t, t);
    let mut r = record();
    r.next = t;
    st2.run(&mut s2, &mut r).unwrap();
    let again = r.rows.last().unwrap();
    eprintln!(
        "{name}: continued from t = {t:e} with {pairs} pairs in contact, {then} elements eroded: {} pairs, {} eroded, contact energy {:e} J at the end",
        again.pairs,
        eroded(again),
        again.energy[3]
    );
    assert!(
        *again == through,
        "{name}: the continued run ends elsewhere"
    );
    st2.into_gpu()
}

/// A steel block (2 x 2 x 2 elements of 2 mm) at 300 m/s onto a plate (6 x 6 x 3 elements of 2
/// mm, clamped at its rim) whose elements erode at a pressure of 2 GPa (`*MAT_ADD_EROSION`
/// MXPRES): as the elements under the block erode their faces leave the
/// surface and the faces they covered join it (the GPU halts in those steps and the host
/// changes the surfaces), and the block goes on against the layer below. (Measured: 2 elements
/// erode by 2.3 us, 3 by 3.4 us; the block is in contact from 1 to 7 us.)
fn eroding_plate() -> Model {
    let (mut m, _) = common::block_on_an_eroding_plate("eroding plate", 2);
    m.contacts.push(def(None, 0.1, 0.1, 0.0));
    m
}

#[test]
fn contact_on_an_eroding_plate_matches_the_cpu() {
    let Some(g) = gpu() else { return };
    let m = eroding_plate();
    compare(g, &m, 1e-6, 1e-9, 4, "eroding plate");
    // the elements eroded, and the block was in contact after the last of them did: with
    // the faces below them, which erosion exposed
    let rows = run_cpu(&m, 1e-6);
    let eroded = |r: &Row| r.eroded.iter().filter(|&&e| e).count();
    let n = eroded(rows.last().unwrap());
    assert!(n >= 3, "{n} eroded");
    assert!(
        rows.iter().any(|r| eroded(r) == n && r.pairs > 0),
        "no contact after the last erosion"
    );
}
