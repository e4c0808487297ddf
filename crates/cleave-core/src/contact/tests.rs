//! End-to-end checks of the contact engine without the solver: forces, energy, friction,
//! ties, activation of crack faces, lazy search, stable step and thread independence.

use super::*;
use crate::math::{cross, norm};
use crate::mesh::{single_part_model, BoxMesh};
use crate::model::{ContactSurface, Material, MaterialKind, Part, SegmentSet};
use crate::separation::coincident::CoincidentSets;
use crate::setup::Setup;
use penalty::FaceBounds;
use search::tests::Rng;

const E: f64 = 1.0e9;
const NU: f64 = 0.25;
/// Bulk modulus E / (3 (1 - 2 nu)).
const K: f64 = E / 1.5;

fn mat() -> Material {
    Material {
        id: 1,
        density: 1000.0,
        young: E,
        poisson: NU,
        kind: MaterialKind::Elastic,
    }
}

/// Block A (part 0) from the origin, block B (part 1) shifted by `off`.
fn two_blocks(na: [usize; 3], la: [f64; 3], nb: [usize; 3], lb: [f64; 3], off: Vec3) -> Model {
    let b = BoxMesh::new(nb, lb);
    let mut m = single_part_model(BoxMesh::new(na, la), mat(), 1.0);
    let base = m.x0.len() as u32;
    m.x0.extend(b.x.iter().map(|p| add(*p, off)));
    m.v0.resize(m.x0.len(), [0.0; 3]);
    m.node_ids = (1..=m.x0.len() as i64).collect();
    for c in &b.conn {
        m.conn.push(c.map(|n| n + base));
        m.elem_part.push(1);
    }
    m.elem_ids = (1..=m.conn.len() as i64).collect();
    m.parts.push(Part {
        id: 2,
        title: "b".into(),
        section: 0,
        material: 0,
        hourglass: None,
    });
    m
}

fn def(single: bool, fs: f64, fd: f64, dc: f64) -> ContactDef {
    ContactDef {
        id: 1,
        single_surface: single,
        one_way: false,
        slave: if single {
            ContactSurface::All
        } else {
            ContactSurface::Part(0)
        },
        master: (!single).then_some(ContactSurface::Part(1)),
        fs,
        fd,
        dc,
    }
}

fn zeros(n: usize) -> Vec<Vec3> {
    vec![[0.0; 3]; n]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A 0.2 cube (part 1, nodes 8..16) sunk by `delta` into the top of a unit cube (part 0), its
/// lower corner at (x, y).
fn small_cube_on_unit_cube(x: f64, y: f64, delta: f64) -> Model {
    two_blocks(
        [1, 1, 1],
        [1.0; 3],
        [1, 1, 1],
        [0.2; 3],
        [x, y, 1.0 - delta],
    )
}

/// A separation group on material 0: MODEL 1 of strength `sigmax`.
fn separation_group(sigmax: f64) -> crate::model::SeparationDef {
    crate::model::SeparationDef {
        material: 0,
        model: 1,
        sigmax,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    }
}

/// `deck` with material 0 in a separation group of strength `sigmax` and one frictionless
/// single-surface contact over every part, split.
fn split_with_contact(mut deck: Model, sigmax: f64) -> crate::separation::split::SplitModel {
    deck.separations.push(separation_group(sigmax));
    deck.contacts.push(def(true, 0.0, 0.0, 0.0));
    crate::separation::split::split_model(&deck)
}

/// The crack of a failed interface, as the solver names it to the contact.
fn crack_of(f: &crate::separation::split::SharedFace) -> Crack {
    Crack {
        faces: [(f.elems[0], f.faces[0]), (f.elems[1], f.faces[1])],
        nodes: [
            std::array::from_fn(|k| f.nodes[k]),
            std::array::from_fn(|k| f.nodes[4 + k]),
        ],
    }
}

/// The interface between elements a and b of a split model.
fn interface_between(sm: &crate::separation::split::SplitModel, a: u32, b: u32) -> usize {
    sm.faces[..sm.interfaces]
        .iter()
        .position(|f| f.elems == [a, b] || f.elems == [b, a])
        .expect("the elements share an interface")
}

/// The coincident set of each node of a split model whose interfaces are `intact` or not
/// (u32::MAX: untied), as the solver gives it to `compute`.
fn ties(sm: &crate::separation::split::SplitModel, intact: &[bool]) -> Vec<u32> {
    let sets = crate::separation::coincident::CoincidentSets::build(
        sm.model.num_nodes(),
        &sm.faces,
        intact,
    );
    (0..sm.model.num_nodes() as u32)
        .map(|i| sets.set_of(i).map_or(u32::MAX, |s| s[0]))
        .collect()
}

/// Remove element e from a deck (the elements after it are renumbered; nodes stay). Element 7
/// of a 2 x 2 x 2 block is its top corner (x, y, z > 1): a notch whose three faces meet at the
/// block's centre.
fn remove_element(deck: &mut Model, e: usize) {
    deck.conn.remove(e);
    deck.elem_part.remove(e);
    deck.elem_ids = (1..=deck.conn.len() as i64).collect();
}

/// Two 2x2x2 blocks of unit size, B overlapping A's top by delta = 0.01 and shifted by a
/// quarter side so no nodes coincide: 4 nodes of each block penetrate the other's faces, each
/// by delta, with k = 0.1 K A^2/V = 0.05 K (A = 0.25, V = 0.125). Both contact types give 8 pairs
/// and total normal force 8 k delta; all nodal contact forces sum to zero; surface to surface
/// reports -8 k delta e_z on the slave block A. Then both blocks approach at 1 m/s each for one
/// step of 1 ms: the energy increment is the exact spring energy 8 x 1/2 k (d2^2 - d1^2) (the
/// trapezoid is exact for a linear spring), positive. Tolerances 1e-12: round-off only.
#[test]
fn overlapping_blocks_force_and_energy() {
    let d1 = 0.01;
    let m = two_blocks(
        [2, 2, 2],
        [1.0; 3],
        [2, 2, 2],
        [1.0; 3],
        [0.25, 0.25, 1.0 - d1],
    );
    let k = 0.1 * K * 0.25 * 0.25 / 0.125;
    let na = 27;
    for single in [true, false] {
        let mut m = m.clone();
        m.contacts.push(def(single, 0.0, 0.0, 0.0));
        let mut cs = ContactSet::new(&m, None).unwrap();
        let nn = m.num_nodes();
        let mut f = zeros(nn);
        let v: Vec<Vec3> = (0..nn)
            .map(|i| {
                if i < na {
                    [0.0, 0.0, 1.0]
                } else {
                    [0.0, 0.0, -1.0]
                }
            })
            .collect();
        let st = cs.compute(&m.x0.to_vec(), &v, 0.0, &[], &mut f);
        assert_eq!(st.pairs, 8, "single {single}");
        assert_eq!(st.energy, 0.0);
        let r = cs.forces()[0];
        assert!(
            rel(r.normal, 8.0 * k * d1) < 1e-12,
            "{} vs {}",
            r.normal,
            8.0 * k * d1
        );
        let fmax = f.iter().map(|q| norm(*q)).fold(0.0, f64::max);
        let total = f.iter().fold([0.0; 3], |a, q| add(a, *q));
        assert!(norm(total) < 1e-12 * fmax, "total {total:?}");
        if !single {
            assert!(norm(sub(r.force, [0.0, 0.0, -8.0 * k * d1])) < 1e-12 * 8.0 * k * d1);
        }
        // block A's nodes are pushed down, B's up
        let fa = f[..na].iter().fold([0.0; 3], |a, q| add(a, *q));
        assert!(rel(fa[2], -8.0 * k * d1) < 1e-12);

        let dt = 1e-3;
        let x2: Vec<Vec3> =
            m.x0.iter()
                .zip(&v)
                .map(|(x, vi)| add(*x, scale(*vi, dt)))
                .collect();
        let d2 = d1 + 2.0 * dt;
        let st2 = cs.compute(&x2, &v, dt, &[], &mut zeros(nn));
        assert_eq!(st2.pairs, 8);
        let want = 8.0 * 0.5 * k * (d2 * d2 - d1 * d1);
        assert!(st2.energy > 0.0);
        assert!(rel(st2.energy, want) < 1e-12, "{} vs {want}", st2.energy);
    }
}

/// A segment-set master side (block A's top faces) gives the same pairs as the part.
#[test]
fn segment_set_side() {
    let mut m = two_blocks([2, 2, 2], [1.0; 3], [2, 2, 2], [1.0; 3], [0.25, 0.25, 0.99]);
    let top: Vec<[u32; 4]> = (4..8).map(|e| face_nodes(&m.conn[e], 1)).collect();
    m.segment_sets.push(SegmentSet {
        id: 5,
        segments: top,
    });
    m.contacts.push(ContactDef {
        slave: ContactSurface::Part(1),
        master: Some(ContactSurface::SegmentSet(0)),
        ..def(false, 0.0, 0.0, 0.0)
    });
    let mut cs = ContactSet::new(&m, None).unwrap();
    assert_eq!(cs.contacts()[0].faces(1).len(), 4);
    let st = cs.compute(
        &m.x0.to_vec(),
        &zeros(m.num_nodes()),
        0.0,
        &[],
        &mut zeros(m.num_nodes()),
    );
    assert_eq!(st.pairs, 8);
}

/// A small block (0.2 side) pressed 1 mm into the top of a unit cube, sliding along x.
/// Sliding (1 m/s over 1 ms: trial k 1e-3 > mu k 1e-3): each of its 4 bottom nodes gets
/// f_t = mu f_n against the slip with mu = FD + (FS - FD) e^(-DC |v|) = 0.3 + 0.2 e^(-2), and
/// f_n = k delta, k = 0.1 K (A = V = 1). Sticking (1e-4 m/s): f_t = -k du = -k v dt, then twice
/// that at the next step (the carried force). Energy increments are positive (dissipation).
/// Tolerance 1e-12: round-off only.
#[test]
fn friction_slides_and_sticks() {
    let delta = 1e-3;
    let (fs, fd, dc) = (0.5, 0.3, 2.0);
    let mut m = small_cube_on_unit_cube(0.4, 0.4, delta);
    m.contacts.push(ContactDef {
        slave: ContactSurface::Part(1),
        master: Some(ContactSurface::Part(0)),
        ..def(false, fs, fd, dc)
    });
    // the pair's spring: the small block's nodes (0.1 K A^2 / V = 0.1 K 0.2) are softer than
    // the big block's face (0.1 K), and a pair takes the smaller (PENOPT 1)
    let k = 0.02 * K;
    let f_n = k * delta;
    let nn = m.num_nodes();
    let bottom: Vec<usize> = (8..16).filter(|&i| m.x0[i][2] < 1.0).collect();
    assert_eq!(bottom.len(), 4);
    let dt = 1e-3;
    for (speed, sliding) in [(1.0, true), (1e-4, false)] {
        let mut cs = ContactSet::new(&m, None).unwrap();
        let v: Vec<Vec3> = (0..nn)
            .map(|i| if i >= 8 { [speed, 0.0, 0.0] } else { [0.0; 3] })
            .collect();
        // the first step engages the overlap (no slip yet: dt_prev = 0)
        assert_eq!(
            cs.compute(&m.x0.to_vec(), &v, 0.0, &[], &mut zeros(nn))
                .pairs,
            4
        );
        for step in 1..=2 {
            let mut f = zeros(nn);
            let st = cs.compute(&m.x0.to_vec(), &v, dt, &[], &mut f);
            assert_eq!(st.pairs, 4);
            assert!(st.energy > 0.0, "step {step}: energy {}", st.energy);
            let want_t = if sliding {
                -(fd + (fs - fd) * (-dc * speed).exp()) * f_n
            } else {
                -k * speed * dt * step as f64
            };
            for &i in &bottom {
                assert!(rel(f[i][2], f_n) < 1e-12, "f_n {:?}", f[i]);
                assert!(rel(f[i][0], want_t) < 1e-12, "f_t {} vs {want_t}", f[i][0]);
                assert!(f[i][1].abs() < 1e-12 * f_n);
            }
        }
    }
}

/// Near the edge of a block a node penetrates the top by delta = 0.01 and the side by its
/// distance to it (0.1 < depth 0.4): it takes the top (the nearest surface point), force
/// k delta along +z, k = 0.02 K the small block's node stiffness (below the face's 0.1 K).
#[test]
fn nearest_face_wins_near_an_edge() {
    let delta = 0.01;
    let mut m = small_cube_on_unit_cube(0.7, 0.4, delta);
    m.contacts.push(def(true, 0.0, 0.0, 0.0));
    let mut cs = ContactSet::new(&m, None).unwrap();
    let nn = m.num_nodes();
    let mut f = zeros(nn);
    let st = cs.compute(&m.x0.to_vec(), &zeros(nn), 0.0, &[], &mut f);
    assert_eq!(st.pairs, 4);
    for i in (8..16).filter(|&i| m.x0[i][2] < 1.0) {
        assert!(
            rel(f[i][2], 0.02 * K * delta) < 1e-12 && f[i][0] == 0.0,
            "{:?}",
            f[i]
        );
    }
}

/// Two unit cubes stacked in z (a 1 x 1 x 2 block), each on its own 8 nodes, without contact,
/// and the deck node of each of the 16 nodes.
fn split_stack() -> (Model, Vec<u32>) {
    let deck = single_part_model(BoxMesh::new([1, 1, 2], [1.0, 1.0, 2.0]), mat(), 1.0);
    let origin: Vec<u32> = deck.conn.iter().flatten().copied().collect();
    let mut m = deck.clone();
    m.x0 = origin.iter().map(|&o| deck.x0[o as usize]).collect();
    m.v0 = zeros(16).into();
    m.node_ids = origin.iter().map(|&o| o as i64 + 1).collect();
    m.conn = (0..2u32)
        .map(|e| std::array::from_fn(|a| 8 * e + a as u32))
        .collect();
    (m, origin)
}

/// Two unit cubes stacked in z, each on its own 8 nodes (a split model; origin maps the copies
/// to the 12 deck nodes). The upper one is pushed 0.01 into the lower one.
/// - the shared faces are not surfaces at first: no contact even when untied;
/// - once activated, tied copies (one coincident set per deck node) never contact;
/// - untied (the failure named to `activate`), the 4 + 4 nodes of the crack faces penetrate each
///   other: 8 pairs, 8 k delta with k = 0.1 K.
#[test]
fn ties_and_crack_faces() {
    let delta = 0.01;
    let (mut m, origin) = split_stack();
    m.contacts.push(def(true, 0.0, 0.0, 0.0));
    let tie: Vec<u32> = origin
        .iter()
        .map(|&o| {
            if origin.iter().filter(|&&p| p == o).count() > 1 {
                o
            } else {
                u32::MAX
            }
        })
        .collect();
    assert_eq!(tie.iter().filter(|&&t| t != u32::MAX).count(), 8);

    let mut cs = ContactSet::new(&m, Some(&origin)).unwrap();
    assert_eq!(cs.contacts()[0].faces(0).len(), 10);
    let x: Vec<Vec3> =
        m.x0.iter()
            .enumerate()
            .map(|(i, p)| {
                if i >= 8 {
                    sub(*p, [0.0, 0.0, delta])
                } else {
                    *p
                }
            })
            .collect();
    let v = zeros(16);
    let st = cs.compute(&x, &v, 0.0, &[], &mut zeros(16));
    assert_eq!(st.pairs, 0, "crack faces are not surfaces before they fail");

    assert_eq!(cs.activate(&[(0, 1), (1, 0)]), 2);
    assert_eq!(cs.activate(&[(0, 1)]), 0, "already present");
    assert_eq!(cs.contacts()[0].faces(0).len(), 12);
    let st = cs.compute(&x, &v, 0.0, &tie, &mut zeros(16));
    assert_eq!(st.pairs, 0, "tied copies never contact");

    // the interface fails: its ties break, and it is named again (nothing new to add)
    assert_eq!(cs.activate(&[(0, 1), (1, 0)]), 0);
    let mut f = zeros(16);
    let st = cs.compute(&x, &v, 0.0, &[], &mut f);
    assert_eq!(st.pairs, 8);
    let k = 0.1 * K;
    assert!(rel(cs.forces()[0].normal, 8.0 * k * delta) < 1e-12);
    for (i, fi) in f.iter().enumerate().take(8).skip(4) {
        assert!(rel(fi[2], -k * delta * 2.0) < 1e-12, "node {i}: {fi:?}");
    }
}

/// A face's own nodes are never its candidates, and a cube whose corner is pushed inside
/// (0.1 along each axis, within the depth limit of its own top face) has no contact.
#[test]
fn own_nodes_never_contact() {
    let mut m = single_part_model(BoxMesh::new([1, 1, 1], [1.0; 3]), mat(), 1.0);
    m.contacts.push(def(true, 0.0, 0.0, 0.0));
    let mut cs = ContactSet::new(&m, None).unwrap();
    let mut x = m.x0.to_vec();
    assert_eq!(x[7], [1.0; 3]); // BoxMesh numbers x fastest
    x[7] = [0.9, 0.9, 0.9];
    let st = cs.compute(&x, &zeros(8), 0.0, &[], &mut zeros(8));
    assert_eq!(st.pairs, 0);
    let c = &cs.contacts()[0];
    let side = &c.sides[0];
    for (i, &n) in side.nodes.iter().enumerate() {
        let (sched, room) = c.passes[0].cand.get(i);
        for f in sched.faces(room) {
            assert!(!side.faces[f as usize].nodes.contains(&n));
        }
    }
}

/// Positions of two perturbed 6x6x2 blocks approaching each other, step `n` of a made-up
/// motion (B moves down 0.004 per step, every node jitters by up to 0.01 per step).
fn jitter_positions(m: &Model, na: usize, steps: usize, seed: u64) -> Vec<Vec<Vec3>> {
    let mut r = Rng(seed);
    let mut x = m.x0.to_vec();
    let mut out = vec![x.clone()];
    for _ in 0..steps {
        for (i, p) in x.iter_mut().enumerate() {
            let dz = if i >= na { -0.0015 } else { 0.0 };
            *p = add(
                *p,
                [
                    r.range(-0.0035, 0.0035),
                    r.range(-0.0035, 0.0035),
                    dz + r.range(-0.0035, 0.0035),
                ],
            );
        }
        out.push(x.clone());
    }
    out
}

fn jitter_model(single: bool) -> (Model, usize) {
    let mut m = two_blocks(
        [6, 6, 2],
        [1.0, 1.0, 0.4],
        [6, 6, 2],
        [1.0, 1.0, 0.4],
        [0.05, 0.03, 0.39],
    );
    m.contacts.push(def(single, 0.4, 0.2, 1.0));
    (m, 7 * 7 * 3)
}

/// Run `steps` steps on the jittered positions; per step the sorted nodal forces and energy.
fn run_jitter(
    cs: &mut ContactSet,
    xs: &[Vec<Vec3>],
    always_rebuild: bool,
) -> Vec<(Vec<Vec3>, f64, usize)> {
    let dt = 1e-3;
    let nn = xs[0].len();
    let mut out = Vec::new();
    for n in 0..xs.len() {
        let v: Vec<Vec3> = if n == 0 {
            zeros(nn)
        } else {
            (0..nn)
                .map(|i| scale(sub(xs[n][i], xs[n - 1][i]), 1.0 / dt))
                .collect()
        };
        if always_rebuild {
            for c in &mut cs.contacts {
                c.dirty = true;
            }
        }
        let mut f = zeros(nn);
        let st = cs.compute(&xs[n], &v, if n == 0 { 0.0 } else { dt }, &[], &mut f);
        out.push((f, st.energy, st.pairs));
    }
    out
}

/// The lazy search (rebuilt only when a node moved more than half the margin) gives exactly
/// the forces of a search rebuilt every step, over 60 steps of jittered motion with contact
/// and friction, for both contact types; and it does rebuild sometimes, but not every step.
#[test]
fn lazy_search_equals_rebuilding_every_step() {
    for single in [true, false] {
        let (m, na) = jitter_model(single);
        let xs = jitter_positions(&m, na, 60, 7);
        let mut lazy = ContactSet::new(&m, None).unwrap();
        let mut eager = ContactSet::new(&m, None).unwrap();
        let a = run_jitter(&mut lazy, &xs, false);
        let b = run_jitter(&mut eager, &xs, true);
        assert_eq!(a, b, "single {single}");
        let pairs: usize = a.iter().map(|s| s.2).sum();
        assert!(pairs > 100, "contact happened: {pairs} pairs");
        let rebuilds = lazy.stats().rebuilds;
        assert!(rebuilds > 1 && rebuilds < 40, "{rebuilds} rebuilds");
        assert_eq!(eager.stats().rebuilds, 61);
    }
}

/// Bit-identical results with 1 and 4 threads.
#[test]
fn thread_count_does_not_change_results() {
    let (m, na) = jitter_model(true);
    let xs = jitter_positions(&m, na, 20, 3);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut cs = ContactSet::new(&m, None).unwrap();
            run_jitter(&mut cs, &xs, false)
        })
    };
    let one = run(1);
    assert!(one.iter().map(|s| s.2).sum::<usize>() > 0);
    assert_eq!(one, run(4));
}

/// stable_dt = sqrt(m_min / k_max): for two 2x2x2 unit blocks, m_min is a box corner's mass
/// rho V_e / 8 and k_max = 0.05 K; with SLSFAC 0.1 and nu = 0.25 it is
/// sqrt(1.2 E / (0.8 K)) = 1.5 times the element step l/c (l = 0.5): contact does not force a
/// smaller step on matching meshes.
#[test]
fn stable_step_of_the_springs() {
    let mut m = two_blocks([2, 2, 2], [1.0; 3], [2, 2, 2], [1.0; 3], [0.25, 0.25, 0.99]);
    m.contacts.push(def(false, 0.0, 0.0, 0.0));
    let cs = ContactSet::new(&m, None).unwrap();
    let mass = Setup::new(&m).unwrap().mass;
    let m_min = 1000.0 * 0.125 / 8.0;
    let k = 0.05 * K;
    let dt = cs.stable_dt(&mass);
    assert!(rel(dt, (m_min / k).sqrt()) < 1e-12, "{dt}");
    let c = mat().wave_speed();
    assert!(rel(dt / (0.5 / c), 1.5) < 1e-12, "{}", dt / (0.5 / c));
}

/// PENOPT: a pair takes the smaller of the face's and the node's stiffness (1, the default) or
/// the face's (2), and the stable step follows the rule. A 0.2 cube (nodes: m = rho 0.2^3 / 8 =
/// 1, k = 0.1 K 0.2^4 / 0.2^3 = 0.02 K) sinks by delta into a unit cube (nodes: m = 125,
/// faces and nodes: k = 0.1 K). Rule 1: 0.02 K, and dt = min sqrt(m / k) = sqrt(1 / 0.02 K)
/// (the unit cube's nodes: sqrt(1250 / K)); rule 2: 0.1 K, and dt = sqrt(m_min / k_max) =
/// sqrt(1 / 0.1 K), the light node against the stiff face.
#[test]
fn penalty_rule_sets_the_pair_spring_and_the_stable_step() {
    let delta = 0.01;
    for (rule, k, dt) in [
        (PenaltyRule::Smaller, 0.02 * K, (1.0 / (0.02 * K)).sqrt()),
        (PenaltyRule::Face, 0.1 * K, (1.0 / (0.1 * K)).sqrt()),
    ] {
        let mut m = small_cube_on_unit_cube(0.7, 0.4, delta);
        m.control.penalty = rule;
        m.contacts.push(def(true, 0.0, 0.0, 0.0));
        let mut cs = ContactSet::new(&m, None).unwrap();
        let nn = m.num_nodes();
        let mut f = zeros(nn);
        let st = cs.compute(&m.x0.to_vec(), &zeros(nn), 0.0, &[], &mut f);
        assert_eq!(st.pairs, 4, "{rule:?}");
        for i in (8..16).filter(|&i| m.x0[i][2] < 1.0) {
            assert!(rel(f[i][2], k * delta) < 1e-12, "{rule:?}: {:?}", f[i]);
        }
        // the resultant of rcforc.csv sums the same springs
        let normal = cs.forces()[0].normal;
        assert!(rel(normal, 4.0 * k * delta) < 1e-12, "{rule:?}: {normal}");
        let mass = Setup::new(&m).unwrap().mass;
        assert!(rel(mass[8], 1.0) < 1e-12);
        let got = cs.stable_dt(&mass);
        assert!(rel(got, dt) < 1e-12, "{rule:?}: {got} vs {dt}");
    }
}

/// Interfaces of a fully split 4x4x2 block fail at random steps while every node jitters: the
/// incremental search around the activated faces gives exactly the forces of a full rebuild
/// at every step (same ties, same faces), for 40 steps; and it is used (few full builds).
/// Single surface over the block, and surface to surface between its lower and upper layer
/// (two parts, one material), where faces join one side at a time.
#[test]
fn incremental_activation_equals_full_rebuild() {
    for single in [true, false] {
        incremental_vs_full(single, false);
    }
}

/// The same with the positions kept per slot of the coincident sets (the solver's storage):
/// the reference positions of the slots made since the last full build come from the sets
/// they split from ([`ContactSet::sets_split`]).
#[test]
fn incremental_activation_equals_full_rebuild_per_slot() {
    for single in [true, false] {
        incremental_vs_full(single, true);
    }
}

fn incremental_vs_full(single: bool, per_slot: bool) {
    let (pairs, st) = failing_block(
        FailingBlock {
            single,
            two_parts: true,
            seed: 21,
            steps: 40,
            fail_every: 3,
            fail_p: 0.08,
            step_dt: 0.0015,
            per_slot,
        },
        |r, _| [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)],
        |_| {},
    );
    assert!(pairs > 200, "single {single}: {pairs} pairs");
    assert!(st.updates >= 10, "single {single}: {st:?}");
    assert!(st.rebuilds < 20, "single {single}: {st:?}");
}

/// Each lead's candidates (after a step's searches) hold every face it could touch at the
/// positions `x`: every face, not held (the lead, a copy tied or chained to it) and not eroded,
/// whose search sphere and box at `x` with no margin ([`search_sphere`], [`search_box`]: both
/// needed for contact, mod.rs Search) hold the lead. Brute force over the faces.
fn lists_hold_every_reachable_face(cs: &ContactSet, x: Points, tie: &[u32], step: usize) {
    for c in cs.contacts() {
        for pass in &c.passes {
            let (ns, fs) = (&c.sides[pass.node_side], &c.sides[pass.face_side]);
            for i in 0..ns.nodes.len() {
                if ns.group.get(i).copied() != Some(i as u32) || ns.buried(i as u32) {
                    continue;
                }
                let s = ns.nodes[i];
                let p = x[s as usize];
                let set = tie.get(s as usize).copied().unwrap_or(NONE);
                let (sched, room) = pass.cand.get(i);
                let listed: Vec<u32> = sched.faces(room).collect();
                for (f, face) in fs.faces.iter().enumerate() {
                    // the search's sphere and box with no margin: the least contact needs
                    let (centre, reach) = search_sphere(face, x, 0.0);
                    let held = |a: u32| {
                        a == s || (set != NONE && tie[a as usize] == set) || c.chains.held(a, s)
                    };
                    if face.depth <= 0.0
                        || dist2(p, centre) > reach * reach
                        || !search_box(face, x, 0.0).contains(p)
                        || face.nodes.iter().any(|&a| held(a))
                    {
                        continue;
                    }
                    assert!(
                        listed.contains(&(f as u32)),
                        "step {step}: lead {s} lacks face {f} ({:?})",
                        face.nodes
                    );
                }
            }
        }
    }
}

/// How [`failing_block`] runs.
struct FailingBlock {
    single: bool,
    /// The upper layer is a second part (one material), for a surface-to-surface definition
    /// between the layers.
    two_parts: bool,
    seed: u64,
    steps: usize,
    /// Every `fail_every` steps each intact interface fails with probability `fail_p`.
    fail_every: usize,
    fail_p: f64,
    /// Each step moves every node by `step_dt` times its velocity.
    step_dt: f64,
    /// Positions and velocities kept per slot of the coincident sets, as the solver keeps
    /// them ([`crate::node_values`]): the copies of a set move as one, and a set that splits
    /// gives its new slots its position.
    per_slot: bool,
}

/// A fully split 4 x 4 x 2 block (MODEL 1, SIGMAX 1) whose interfaces fail at random while its
/// nodes move with `velocity(rng, node)`: a lazy contact set (incremental searches, skipping)
/// against a reference, set up by `reference` and told at every step that the ties changed
/// (a full rebuild). Their forces, energy and pairs are equal at every step. Returns the
/// pairs summed over the steps and the lazy set's statistics.
fn failing_block(
    run: FailingBlock,
    mut velocity: impl FnMut(&mut Rng, usize) -> Vec3,
    reference: impl FnOnce(&mut ContactSet),
) -> (usize, ContactStats) {
    use crate::separation::split::split_model;
    let mut deck = single_part_model(BoxMesh::new([4, 4, 2], [1.0, 1.0, 0.5]), mat(), 1.0);
    deck.separations.push(separation_group(1.0));
    if run.two_parts {
        deck.parts.push(Part {
            id: 2,
            title: "upper".into(),
            section: 0,
            material: 0,
            hourglass: None,
        });
        deck.elem_part = (0..32).map(|e| (e >= 16) as u32).collect();
    }
    deck.contacts.push(def(run.single, 0.3, 0.2, 0.5));
    let sm = split_model(&deck);
    let m = &sm.model;
    let nn = m.num_nodes();
    let mut intact = vec![true; sm.faces.len()];
    let mut lazy = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let mut full = ContactSet::new(m, Some(&sm.origin)).unwrap();
    reference(&mut full);
    let mut r = Rng(run.seed);
    let mut sets = CoincidentSets::build(nn, &sm.faces, &intact);
    let mut x = match run.per_slot {
        true => (0..nn)
            .filter(|&i| sets.rep(i as u32) == i as u32)
            .map(|i| m.x0[i])
            .collect(),
        false => m.x0.to_vec(),
    };
    let dt = 1e-3;
    let mut pairs = 0;
    for step in 0..run.steps {
        let mut failed = Vec::new();
        let mut released = Vec::new();
        if step % run.fail_every == 1 {
            for (k, ok) in intact.iter_mut().enumerate().take(sm.interfaces) {
                if *ok && r.unit() < run.fail_p {
                    *ok = false;
                    released.push(k);
                    let f = &sm.faces[k];
                    failed.push((f.elems[0], f.faces[0]));
                    failed.push((f.elems[1], f.faces[1]));
                }
            }
        }
        let tie = ties(&sm, &intact);
        if run.per_slot && !released.is_empty() {
            sets.split_after_failure(&sm.faces, &intact, &released);
            for &(new, from) in sets.born() {
                assert_eq!(new as usize, x.len());
                x.push(x[from as usize]);
            }
            lazy.sets_split(sets.born());
            full.sets_split(sets.born());
        }
        assert_eq!(lazy.activate(&failed), full.activate(&failed));
        full.ties_changed();
        let slots = run.per_slot.then(|| sets.slots());
        let v: Vec<Vec3> = (0..x.len()).map(|i| velocity(&mut r, i)).collect();
        if step > 0 {
            for (xi, vi) in x.iter_mut().zip(&v) {
                *xi = add(*xi, scale(*vi, run.step_dt));
            }
        }
        let (xv, vv) = (Points::new(&x, slots), Points::new(&v, slots));
        let slot = slots.unwrap_or(&[]);
        let (mut fa, mut fb) = (zeros(x.len()), zeros(x.len()));
        let sa = lazy.compute_with_slots(xv, vv, dt, &tie, slot, &mut fa);
        let sb = full.compute_with_slots(xv, vv, dt, &tie, slot, &mut fb);
        lists_hold_every_reachable_face(&lazy, xv, &tie, step);
        assert_eq!(
            (fa, sa.energy, sa.pairs),
            (fb, sb.energy, sb.pairs),
            "single {}, step {step}",
            run.single
        );
        pairs += sa.pairs;
    }
    (pairs, lazy.stats())
}

/// Skipping candidates by their clearance changes nothing: the forces, energy and pairs of
/// every step are those of a run that tests every candidate every step and drops none, over
/// 80 steps of block B coming down on block A and sliding over it (with a little noise on
/// every node), for both contact types; and the skipping run does leave candidates untested.
#[test]
fn skipping_equals_testing_every_candidate() {
    for single in [true, false] {
        let (mut m, na) = jitter_model(single);
        // B starts 0.004 above A
        for p in m.x0.iter_mut().skip(na) {
            p[2] += 0.014;
        }
        let mut r = Rng(9);
        let mut x = m.x0.to_vec();
        let mut xs = vec![x.clone()];
        for _ in 0..80 {
            for (i, p) in x.iter_mut().enumerate() {
                let (dx, dz) = if i >= na {
                    (0.0007, -0.00035)
                } else {
                    (0.0, 0.0)
                };
                *p = add(
                    *p,
                    [
                        dx + r.range(-1e-4, 1e-4),
                        r.range(-1e-4, 1e-4),
                        dz + r.range(-1e-4, 1e-4),
                    ],
                );
            }
            xs.push(x.clone());
        }
        let mut lazy = ContactSet::new(&m, None).unwrap();
        let mut full = ContactSet::new(&m, None).unwrap();
        for c in &mut full.contacts {
            c.exhaustive = true;
        }
        let a = run_jitter(&mut lazy, &xs, false);
        let b = run_jitter(&mut full, &xs, false);
        assert_eq!(a, b, "single {single}");
        assert!(a.iter().map(|s| s.2).sum::<usize>() > 100);
        let c = &lazy.contacts[0];
        let waiting: usize = c
            .passes
            .iter()
            .flat_map(|p| p.cand.rooms())
            .map(|(sched, room)| sched.waiting(room, c.motion))
            .sum();
        assert!(
            waiting > 100,
            "single {single}: {waiting} candidates waiting"
        );
    }
}

/// The same with interfaces failing (faces joining, ties breaking, the incremental search)
/// and every node jittering: the skipping run equals one that rebuilds and tests everything
/// every step.
#[test]
fn skipping_equals_testing_every_candidate_as_faces_join() {
    let (pairs, st) = failing_block(
        FailingBlock {
            single: true,
            two_parts: false,
            seed: 31,
            steps: 60,
            fail_every: 4,
            fail_p: 0.06,
            step_dt: 0.002,
            per_slot: false,
        },
        // a slow drift of each node with a little noise: pairs approach and part
        |r, i| {
            let w = (i % 7) as f64 - 3.0;
            [w * 0.3 + r.range(-0.2, 0.2), r.range(-0.2, 0.2), -w * 0.2]
        },
        |full| full.contacts[0].exhaustive = true,
    );
    assert!(pairs > 100, "{pairs} pairs");
    assert!(st.updates >= 5, "{st:?}");
}

/// Buried nodes: a 2 x 2 x 2 block of 1 x 1 x 0.25 elements, split, all 12 interfaces failing
/// as closed cracks. The 8 copies of the centre deck node each have 3 faces, all on tight
/// cracks: they are buried (no candidates); the copies on the block's surface are not. The
/// half x > 1 then moves away in x in steps of 0.015: past [`closure::TIGHT`] = 0.2 of the
/// shortest edge (0.05) its 4 cracks with the other half (1 x 0.25 faces) are no longer
/// tight, and the centre copies, each with one face on them, are searched again in that
/// step, by the incremental search (no full build; all faces within their reach hold a copy
/// chained to them, so they find no candidate).
/// Moved back, the cracks are tight again and a full build buries the copies again.
#[test]
fn buried_nodes_are_left_out_until_their_crack_opens() {
    let deck = single_part_model(BoxMesh::new([2, 2, 2], [2.0, 2.0, 0.5]), mat(), 1.0);
    let centre = deck.x0.iter().position(|p| *p == [1.0, 1.0, 0.25]).unwrap() as u32;
    let sm = split_with_contact(deck, 1e30);
    let m = &sm.model;
    let nn = m.num_nodes();
    assert_eq!(sm.interfaces, 12);
    let tie = ties(&sm, &vec![false; sm.faces.len()]);
    let cracks: Vec<Crack> = sm.faces[..sm.interfaces].iter().map(crack_of).collect();
    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    cs.activate_cracks(&cracks);
    // (centre copies buried, centre copies with candidates, other leads not buried)
    let census = |cs: &ContactSet| {
        let c = &cs.contacts()[0];
        let (side, pass) = (&c.sides[0], &c.passes[0]);
        let mut n = (0, 0, 0);
        for i in (0..side.nodes.len()).filter(|&i| side.group[i] as usize == i) {
            let listed = !pass.cand.get(i).1.is_empty();
            if sm.origin[side.nodes[i] as usize] == centre {
                n.0 += side.buried(i as u32) as usize;
                n.1 += listed as usize;
            } else {
                n.2 += !side.buried(i as u32) as usize;
            }
        }
        n
    };
    let mut x = m.x0.to_vec();
    let step = |cs: &mut ContactSet, x: &[Vec3]| {
        cs.compute(x, &zeros(nn), 1e-6, &tie, &mut zeros(nn));
        census(cs)
    };
    let at_rest = step(&mut cs, &x);
    assert_eq!((at_rest.0, at_rest.1), (8, 0), "{at_rest:?}");
    // each of the 8 elements' 7 corners off the centre is on the block's surface
    assert_eq!(at_rest.2, 56, "the surface is not buried: {at_rest:?}");
    let shift = |x: &mut Vec<Vec3>, dz: f64| {
        for e in 0..m.num_elements() {
            if m.x0[m.conn[e][0] as usize][0] >= 1.0 {
                for &n in &m.conn[e] {
                    x[n as usize][0] += dz;
                }
            }
        }
    };
    // away in steps of 0.015: the cracks stop being tight at the fourth (0.06)
    for k in 1..=5 {
        shift(&mut x, 0.015);
        let before = cs.stats();
        let now = step(&mut cs, &x);
        assert_eq!(
            cs.stats().closed,
            12,
            "opening along the normal releases nothing"
        );
        if k < 4 {
            assert_eq!((now.0, now.1), (8, 0), "shift {k}: {now:?}");
        } else {
            assert_eq!(now.0, 0, "shift {k}: {now:?}");
        }
        if k == 4 {
            let after = cs.stats();
            assert_eq!(after.rebuilds, before.rebuilds, "no full build");
            assert_eq!(after.updates, before.updates + 1, "searched again at once");
        }
    }
    shift(&mut x, -0.075);
    step(&mut cs, &x);
    cs.ties_changed();
    let shut = step(&mut cs, &x);
    assert_eq!((shut.0, shut.1), (8, 0), "{shut:?}");
}

/// The facing clearance is never crossed: random node surfaces (2 to 4 faces around the node)
/// and random faces, and whenever the clearance is positive, random motions of all the points
/// by at most half of it (so any two move relative to each other by at most the clearance):
/// the node's normal and every normal of the face (a grid over the extended face and the
/// triangle normals) still fail the facing test.
#[test]
fn facing_clearance_is_never_crossed() {
    let mut r = Rng(41);
    let quad = |r: &mut Rng, a: Vec3, size: f64| -> [Vec3; 4] {
        let u = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
        let w = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
        let jig = |r: &mut Rng| {
            scale(
                [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)],
                0.1 * size,
            )
        };
        [
            a,
            add(add(a, scale(u, size)), jig(r)),
            add(add(a, scale(add(u, w), size)), jig(r)),
            add(add(a, scale(w, size)), jig(r)),
        ]
    };
    let parts = |faces: &[[Vec3; 4]]| -> Vec<(Vec3, f64)> {
        faces
            .iter()
            .map(|p| {
                let (d1, d2) = (sub(p[2], p[0]), sub(p[3], p[1]));
                (cross(d1, d2), norm(d1) + norm(d2))
            })
            .collect()
    };
    let (mut positive, mut big) = (0, 0);
    for _ in 0..20_000 {
        let s = [0.0; 3];
        let own: Vec<[Vec3; 4]> = (0..2 + (r.unit() * 3.0) as usize)
            .map(|_| quad(&mut r, s, 1.0))
            .collect();
        let c = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
        let size = r.range(0.3, 1.5);
        let f = quad(&mut r, c, size);
        let frame = NodeFrame::of(parts(&own).into_iter());
        let b = FaceBounds::new(&f);
        let (cull, more) = Cull::new(&b, 0.2, 1e-9 * b.r);
        let d = frame.facing_clearance(&cull, &more);
        if d <= 0.0 {
            continue;
        }
        positive += 1;
        big += (d > 0.01) as usize;
        for _ in 0..4 {
            let mut jolt = |p: Vec3| {
                let m = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
                add(p, scale(m, 0.5 * d * r.unit() / norm(m).max(1e-300)))
            };
            let own2: Vec<[Vec3; 4]> = own.iter().map(|q| q.map(&mut jolt)).collect();
            let f2 = f.map(&mut jolt);
            let n_s = NodeFrame::of(parts(&own2).into_iter()).n;
            let [a0, a1, a2, a3] = {
                let [x1, x2, x3, x4] = f2;
                let q = |k: [f64; 4]| -> Vec3 {
                    std::array::from_fn(|i| {
                        0.25 * (k[0] * x1[i] + k[1] * x2[i] + k[2] * x3[i] + k[3] * x4[i])
                    })
                };
                [
                    q([1.0, 1.0, 1.0, 1.0]),
                    q([-1.0, 1.0, 1.0, -1.0]),
                    q([-1.0, -1.0, 1.0, 1.0]),
                    q([1.0, -1.0, 1.0, -1.0]),
                ]
            };
            let _ = a0;
            let e = 1.0 + penalty::INSIDE_TOL;
            for i in 0..=8 {
                for j in 0..=8 {
                    let (xi, eta) = (e * (i as f64 / 4.0 - 1.0), e * (j as f64 / 4.0 - 1.0));
                    let n = cross(add(a1, scale(a3, eta)), add(a2, scale(a3, xi)));
                    let n = scale(n, 1.0 / norm(n));
                    assert!(
                        dot(n_s, n) > -FACING,
                        "facing after moving by {d}: {own:?} {f:?} -> {own2:?} {f2:?}"
                    );
                }
            }
        }
    }
    assert!(positive > 2000 && big > 500, "{positive} {big}");
}

/// A node that gets a face (an interface at it fails) has a new normal, so the facing part of
/// its clearances is void: at the next step all its candidates are due at once.
#[test]
fn nodes_with_new_faces_are_due_at_once() {
    let deck = single_part_model(BoxMesh::new([2, 2, 2], [1.0, 1.0, 1.0]), mat(), 1.0);
    let sm = split_with_contact(deck, 1.0);
    let m = &sm.model;
    let nn = m.num_nodes();
    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let tie: Vec<u32> = vec![u32::MAX; nn];
    let mut f = zeros(nn);
    let v = zeros(nn);
    // two steps at rest: every candidate is tested once and then waits (nothing moves)
    cs.compute(&m.x0.to_vec(), &v, 0.0, &tie, &mut f);
    cs.compute(&m.x0.to_vec(), &v, 1e-3, &tie, &mut f);
    let c = &cs.contacts[0];
    let waiting = |c: &Contact| -> usize {
        c.passes[0]
            .cand
            .rooms()
            .map(|(s, room)| s.waiting(room, c.motion))
            .sum()
    };
    assert!(waiting(c) > 0);
    // and no node is looked at: each one's earliest due is ahead of the motion bound
    let looked_at = |c: &Contact| -> usize {
        let p = &c.passes[0];
        p.next
            .iter()
            .filter(|&&d| schedule::is_due(d, c.motion))
            .count()
    };
    assert_eq!(looked_at(c), 0);
    let k = 0;
    let sf = &sm.faces[k];
    let new = [(sf.elems[0], sf.faces[0]), (sf.elems[1], sf.faces[1])];
    assert_eq!(cs.activate(&new), 2);
    let c = &mut cs.contacts[0];
    let side = &c.sides[0];
    let mut renewed: Vec<u32> = side.renewed.clone();
    renewed.sort_unstable();
    renewed.dedup();
    assert_eq!(renewed.len(), 8, "the 8 corners of the two faces");
    let waiting_of = |c: &Contact| -> usize {
        renewed
            .iter()
            .map(|&i| {
                let i = i as usize;
                let (sched, room) = c.passes[0].cand.get(i);
                sched.waiting(room, c.motion)
            })
            .sum()
    };
    assert!(waiting_of(c) > 10, "{}", waiting_of(c));
    c.renew();
    assert_eq!(waiting_of(c), 0);
    // the renewed nodes' leads are looked at again
    assert!(looked_at(c) > 0 && looked_at(c) <= 8, "{}", looked_at(c));
    assert!(c.sides[0].renewed.is_empty());
}

/// A set that splits while in contact keeps its spring: a block of two split elements
/// (2 x 1 x 1) pressed 0.01 into a lower block, held still. Intact, its 6 bottom deck nodes are 6
/// surface points, each one lead with one spring (6 pairs, 6 k delta). When the interface
/// between its two elements fails, the 2 deck nodes on it become 2 points each: 8 pairs. The
/// copies that become leads take over their set's engagement, so the force is 8 k delta at
/// once and stays so (a lead starting afresh would count only the last step's approach, zero
/// here, and push nothing back until the node moved out and in again). The same holds when a
/// lower-numbered copy joins the surface and takes over the lead of a set still tied: the
/// set's force does not change.
#[test]
fn a_new_lead_carries_on_its_sets_contact() {
    let delta = 0.01;
    let mut deck = two_blocks(
        [2, 1, 1],
        [2.0, 1.0, 1.0],
        [1, 1, 1],
        [3.0, 3.0, 1.0],
        [-0.5, -1.0, -1.0],
    );
    deck.materials.push(mat());
    deck.parts[1].material = 1;
    let sm = split_with_contact(deck, 1e30);
    let m = &sm.model;
    let nn = m.num_nodes();
    let upper = |i: usize| sm.origin[i] < 12; // the deck nodes of the 2 x 1 x 1 block
    let x: Vec<Vec3> = (0..nn)
        .map(|i| {
            if upper(i) {
                sub(m.x0[i], [0.0, 0.0, delta])
            } else {
                m.x0[i]
            }
        })
        .collect();
    let v = zeros(nn);
    let mut intact = vec![true; sm.faces.len()];
    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    // the pairs' spring: the lower block's top face has SLSFAC K A^2 / V = 0.1 K 9^2 / 9, the
    // upper block's nodes 0.1 K (unit cubes), and a pair takes the smaller
    let k = 0.1 * K;
    let mut tie = ties(&sm, &intact);
    for (step, dt) in [0.0, 1e-3, 1e-3].into_iter().enumerate() {
        let st = cs.compute(&x, &v, dt, &tie, &mut zeros(nn));
        assert_eq!(st.pairs, 6, "intact, step {step}");
        assert!(rel(cs.forces()[0].normal, 6.0 * k * delta) < 1e-12);
    }
    // the interface between the two elements fails
    let inner = interface_between(&sm, 0, 1);
    intact[inner] = false;
    let f = &sm.faces[inner];
    cs.activate(&[(f.elems[0], f.faces[0]), (f.elems[1], f.faces[1])]);
    tie = ties(&sm, &intact);
    for step in 0..3 {
        let mut fa = zeros(nn);
        let st = cs.compute(&x, &v, 1e-3, &tie, &mut fa);
        assert_eq!(st.pairs, 8, "split, step {step}");
        assert!(
            rel(cs.forces()[0].normal, 8.0 * k * delta) < 1e-12,
            "split, step {step}: {} against {}",
            cs.forces()[0].normal,
            8.0 * k * delta
        );
        let up: f64 = (0..nn).filter(|&i| upper(i)).map(|i| fa[i][2]).sum();
        assert!(rel(up, 8.0 * k * delta) < 1e-12, "{up}");
    }
}

/// The other way a lead changes: a 2 x 2 x 2 block with one corner element removed, split,
/// and a unit block pressed 0.01 into the notch, onto the deck node at the block's centre. The
/// interface between elements 0 and 1 fails: its faces join the surface, and with them a copy
/// of the centre node with a lower number than the lead of its set, which stays tied. That
/// copy becomes the lead and carries on the set's contact: the pairs and the force do not
/// change.
#[test]
fn a_lower_copy_joining_the_surface_carries_on_its_sets_contact() {
    let delta = 0.01;
    let mut deck = two_blocks(
        [2, 2, 2],
        [2.0, 2.0, 2.0],
        [1, 1, 1],
        [1.0, 1.0, 1.0],
        [1.0, 1.0, 1.0 - delta],
    );
    remove_element(&mut deck, 7);
    deck.materials.push(mat());
    deck.parts[1].material = 1;
    let sm = split_with_contact(deck, 1e30);
    let m = &sm.model;
    let nn = m.num_nodes();
    let mut intact = vec![true; sm.faces.len()];
    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let x = m.x0.to_vec();
    let v = zeros(nn);
    let tie = ties(&sm, &intact);
    let mut before = (0, 0.0);
    for dt in [0.0, 1e-3, 1e-3] {
        let st = cs.compute(&x, &v, dt, &tie, &mut zeros(nn));
        before = (st.pairs, cs.forces()[0].normal);
    }
    assert!(before.0 > 0 && before.1 > 0.0, "{before:?}");
    let k = interface_between(&sm, 0, 1);
    intact[k] = false;
    let f = &sm.faces[k];
    let leads_before = cs.contacts()[0].sides[0].group.clone();
    cs.activate(&[(f.elems[0], f.faces[0]), (f.elems[1], f.faces[1])]);
    let tie = ties(&sm, &intact);
    for step in 0..3 {
        let st = cs.compute(&x, &v, 1e-3, &tie, &mut zeros(nn));
        let after = (st.pairs, cs.forces()[0].normal);
        assert_eq!(after.0, before.0, "step {step}");
        assert!(
            rel(after.1, before.1) < 1e-12,
            "step {step}: {after:?} {before:?}"
        );
    }
    // a lead did change (the case this test is for)
    let side = &cs.contacts()[0].sides[0];
    let changed = leads_before
        .iter()
        .enumerate()
        .filter(|&(i, &g)| {
            g != NONE && side.nodes[g as usize] != side.nodes[side.group[i] as usize]
        })
        .count();
    assert!(changed > 0);
}

/// A 2 x 2 x 2 cube with its corner element 7 removed (a notch), split, with single-surface
/// contact and every interface intact: the split model, its ties, and the deck node at the
/// centre (1, 1, 1).
fn notched_cube() -> (crate::separation::split::SplitModel, Vec<u32>, u32) {
    let mut deck = single_part_model(BoxMesh::new([2, 2, 2], [2.0; 3]), mat(), 1.0);
    remove_element(&mut deck, 7);
    let centre = deck.x0.iter().position(|p| *p == [1.0; 3]).unwrap() as u32;
    let sm = split_with_contact(deck, 1e30);
    let tie = ties(&sm, &vec![true; sm.faces.len()]);
    (sm, tie, centre)
}

/// The contact of a split model after one step at rest.
fn first_step<'m>(sm: &'m crate::separation::split::SplitModel, tie: &[u32]) -> ContactSet<'m> {
    let m = &sm.model;
    let nn = m.num_nodes();
    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    cs.compute(&m.x0.to_vec(), &zeros(nn), 0.0, tie, &mut zeros(nn));
    cs
}

/// A lead's normal is its deck node's: a 2 x 2 x 2 unit block with its top corner element
/// (x, y, z > 1) removed and every element split. The centre deck node (1, 1, 1) is on the
/// notch's three faces, each on a different copy: the floor (+z, on the element below the
/// notch), and the two walls (+x, +y). Its lead's normal sums all three, (1, 1, 1)/sqrt 3; the
/// lead's own faces alone would give one axis.
#[test]
fn a_leads_normal_is_its_deck_nodes() {
    let (sm, tie, centre) = notched_cube();
    let cs = first_step(&sm, &tie);
    let side = &cs.contacts()[0].sides[0];
    let on_side: Vec<usize> = (0..side.nodes.len())
        .filter(|&i| sm.origin[side.nodes[i] as usize] == centre)
        .collect();
    assert_eq!(on_side.len(), 3, "the copies with a face on the notch");
    let lead = side.group[on_side[0]] as usize;
    assert!(on_side.iter().all(|&i| side.group[i] as usize == lead));
    let x0 = sm.model.x0.to_vec();
    let n = side.frame(lead, (&x0).into()).n;
    let d = 1.0 / 3f64.sqrt();
    for v in n {
        assert!((v - d).abs() < 1e-12, "{n:?}");
    }
    // each copy's own faces point along one axis only
    let own = NodeFrame::of(
        side.node_faces
            .of(lead as u32)
            .map(|f| side.faces[f as usize].normal_terms((&x0).into())),
    );
    assert!(
        own.n.iter().filter(|v| v.abs() > 0.99).count() == 1,
        "{:?}",
        own.n
    );
}

/// A lead's member chain, and so its normal (summed along the chain), does not depend on
/// where the side keeps its nodes: a full build puts them in space order only when many
/// joined, so the same run may see them in other places.
#[test]
fn member_chains_do_not_depend_on_the_places() {
    let (sm, tie, _) = notched_cube();
    let cs = first_step(&sm, &tie);
    let side = &cs.contacts()[0].sides[0];
    let x0 = sm.model.x0.to_vec();
    // the chains as model numbers, by lead
    let chains = |s: &Side| {
        let mut c: Vec<Vec<u32>> = (0..s.nodes.len() as u32)
            .filter(|&i| s.group[i as usize] == i)
            .map(|i| s.members(i).map(|k| s.nodes[k as usize]).collect())
            .collect();
        c.sort();
        c
    };
    // the same side with its nodes in reverse places, grouped again
    let mut rev = side.clone();
    let n = rev.nodes.len();
    let order: Vec<(u64, u32)> = (0..n).map(|k| (k as u64, (n - 1 - k) as u32)).collect();
    rev.group.fill(NONE);
    rev.next.fill(NONE);
    rev.permute(&order);
    for k in 0..n {
        rev.local[rev.nodes[k] as usize] = k as u32;
    }
    rev.group.fill(NONE);
    rev.regroup(&tie, &mut Vec::new(), &mut Vec::new(), &mut Vec::new());
    let (a, b) = (chains(side), chains(&rev));
    assert!(a.iter().any(|c| c.len() >= 3), "a set of three on the side");
    assert_eq!(a, b);
    for i in (0..n).filter(|&i| side.group[i] as usize == i) {
        let j = rev.local[side.nodes[i] as usize] as usize;
        let (p, q) = (side.frame(i, (&x0).into()).n, rev.frame(j, (&x0).into()).n);
        assert_eq!(p.map(f64::to_bits), q.map(f64::to_bits), "lead {i}");
    }
}

/// The 1 x 1 x 2 block of [`ties_and_crack_faces`] split into its two elements (each with
/// nodes of its own, `origin` their deck nodes) and its interface as a [`Crack`]: element 0's
/// top face (A) and element 1's bottom face (B), their nodes paired by deck node.
fn cracked_pair(fs: f64) -> (Model, Vec<u32>, Crack) {
    let (mut m, origin) = split_stack();
    m.contacts.push(def(true, fs, fs, 0.0));
    let a = face_nodes(&m.conn[0], 1);
    let b = a.map(|n| {
        (8..16)
            .find(|&j| origin[j as usize] == origin[n as usize])
            .unwrap()
    });
    let crack = Crack {
        faces: [(0, 1), (1, 0)],
        nodes: [a, b],
    };
    (m, origin, crack)
}

/// Element 1 of [`cracked_pair`] moved by `d`.
fn moved_top(m: &Model, d: Vec3) -> Vec<Vec3> {
    (0..16)
        .map(|i| if i >= 8 { add(m.x0[i], d) } else { m.x0[i] })
        .collect()
}

/// A closed crack pushes back through its node pairs alone. Element 1 pressed 0.01 into
/// element 0 across their failed interface (untied): each of the 4 pairs carries
/// `(k_A + k_B) 0.01` with k = SLSFAC K A^2 / V = 0.1 K, equal and opposite on its two
/// nodes (as the two node-to-face passes would push at a node with one crack face), and no
/// node-to-face pair is even listed: every face near a crack node holds a copy chained to it.
/// Sliding by 0.1 (half the release slip) changes nothing; with friction (FS = FD = 0.5) a
/// sideways slip over a step gives each pair `mu f_n` against the slip. Tolerances:
/// round-off.
#[test]
fn a_closed_crack_pushes_back_through_its_node_pairs() {
    let delta = 0.01;
    let (m, origin, crack) = cracked_pair(0.5);
    let mut cs = ContactSet::new(&m, Some(&origin)).unwrap();
    assert_eq!(cs.activate_cracks(&[crack]), 2);
    let v = zeros(16);
    let kp = 0.1 * K + 0.1 * K;
    for slide in [0.0, 0.1] {
        let x = moved_top(&m, [slide, 0.0, -delta]);
        let mut f = zeros(16);
        let st = cs.compute(&x, &v, 0.0, &[], &mut f);
        assert_eq!(st.pairs, 4, "slide {slide}");
        assert!(rel(cs.forces()[0].normal, 4.0 * kp * delta) < 1e-12);
        for k in 0..4 {
            let (a, b) = (crack.nodes[0][k] as usize, crack.nodes[1][k] as usize);
            assert!(rel(f[b][2], kp * delta) < 1e-12, "{:?}", f[b]);
            assert!(rel(f[a][2], -kp * delta) < 1e-12, "{:?}", f[a]);
            assert!(f[a][0].abs() + f[b][0].abs() < 1e-9 * kp * delta);
        }
        let total = f.iter().fold([0.0; 3], |s, fi| add(s, *fi));
        assert!(norm(total) < 1e-12 * kp * delta);
        let s = cs.stats();
        assert_eq!((s.candidates, s.closed, s.released), (0, 1, 0));
    }
    // friction: the top element slides along x at 10 m/s over a step of 1 ms (the elastic
    // trial k 0.01 is twice mu f_n: it slides)
    let x = moved_top(&m, [0.0, 0.0, -delta]);
    let v: Vec<Vec3> = (0..16)
        .map(|i| if i >= 8 { [10.0, 0.0, 0.0] } else { [0.0; 3] })
        .collect();
    let mut f = zeros(16);
    cs.compute(&x, &v, 1e-3, &[], &mut f);
    for &b in &crack.nodes[1] {
        assert!(
            rel(f[b as usize][0], -0.5 * kp * delta) < 1e-12,
            "{:?}",
            f[b as usize]
        );
    }
}

/// Without the closure (the faces only activated) the same press is node-to-face contact:
/// 8 pairs, each node a spring k = 0.1 K ([`ties_and_crack_faces`]), in all 8 k delta; with
/// it, 4 pairs of 2 k delta: the same force. And
/// once the faces have slid by 0.3 (over the release slip 0.2 of the unit edge) the crack is
/// released in the step that sees it and the node-to-face search takes the faces back at
/// once: the 2 + 2 nodes over the face opposite, each pushed by k delta (the first step
/// engages in full).
#[test]
fn a_crack_that_slid_goes_back_to_the_search() {
    let delta = 0.01;
    let k = 0.1 * K;
    let (m, origin, crack) = cracked_pair(0.0);
    let v = zeros(16);
    let x = moved_top(&m, [0.0, 0.0, -delta]);
    let mut plain = ContactSet::new(&m, Some(&origin)).unwrap();
    plain.activate(&crack.faces);
    assert_eq!(plain.compute(&x, &v, 0.0, &[], &mut zeros(16)).pairs, 8);
    assert!(plain.stats().candidates > 0);
    let pressed = plain.forces()[0].normal;
    assert!(rel(pressed, 8.0 * k * delta) < 1e-12);

    let mut cs = ContactSet::new(&m, Some(&origin)).unwrap();
    cs.activate_cracks(&[crack]);
    assert_eq!(cs.compute(&x, &v, 0.0, &[], &mut zeros(16)).pairs, 4);
    assert!(rel(cs.forces()[0].normal, pressed) < 1e-12);
    let x = moved_top(&m, [0.3, 0.0, -delta]);
    let mut f = zeros(16);
    let st = cs.compute(&x, &v, 0.0, &[], &mut f);
    let s = cs.stats();
    assert_eq!((s.closed, s.released), (0, 1));
    assert_eq!(st.pairs, 4);
    assert!(rel(cs.forces()[0].normal, 4.0 * k * delta) < 1e-12);
    let up: f64 = (8..16).map(|i| f[i][2]).sum();
    assert!(rel(up, 4.0 * k * delta) < 1e-12, "{up}");
}

/// A 2 x 2 x 1 block, split, all four interfaces failed and closed: each deck node on the
/// block's axis has four copies, in four sets, of which the diagonal ones share no face; all
/// are chained through the closed cracks, so no node is a candidate of a face holding a copy
/// of its deck node (with the faces merely activated such pairs are listed: the node sits on
/// the corner of the face opposite). An element slid past the release slip has its two
/// cracks released, and its copies, chained to the others through those cracks only, are
/// listed against their faces again.
#[test]
fn chained_copies_are_left_out_of_the_search() {
    let deck = single_part_model(BoxMesh::new([2, 2, 1], [2.0, 2.0, 1.0]), mat(), 1.0);
    let sm = split_with_contact(deck, 1e30);
    let m = &sm.model;
    let nn = m.num_nodes();
    assert_eq!(sm.interfaces, 4);
    let tie = ties(&sm, &vec![false; sm.faces.len()]);
    let cracks: Vec<Crack> = sm.faces[..sm.interfaces].iter().map(crack_of).collect();
    let same_deck_pairs = |cs: &ContactSet| {
        let c = &cs.contacts()[0];
        let (side, pass) = (&c.sides[0], &c.passes[0]);
        let mut n = 0;
        for i in 0..side.nodes.len() {
            let s = side.nodes[i];
            let (sched, room) = pass.cand.get(i);
            for f in sched.faces(room) {
                let face = &side.faces[f as usize];
                if face
                    .nodes
                    .iter()
                    .any(|&a| sm.origin[a as usize] == sm.origin[s as usize])
                {
                    n += 1;
                }
            }
        }
        n
    };
    let mut plain = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let faces: Vec<FaceId> = cracks.iter().flat_map(|c| c.faces).collect();
    plain.activate(&faces);
    plain.compute(&m.x0.to_vec(), &zeros(nn), 0.0, &tie, &mut zeros(nn));
    assert!(same_deck_pairs(&plain) > 0);

    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    cs.activate_cracks(&cracks);
    cs.compute(&m.x0.to_vec(), &zeros(nn), 0.0, &tie, &mut zeros(nn));
    assert_eq!(cs.stats().closed, 4);
    assert_eq!(same_deck_pairs(&cs), 0);

    // element 3 (x, y > 1) slides by 0.5 along z: its two cracks are released, and its
    // copies are no longer chained to the others: their pairs are listed again
    let x: Vec<Vec3> = (0..nn)
        .map(|i| {
            if m.conn[3].contains(&(i as u32)) {
                add(m.x0[i], [0.0, 0.0, 0.5])
            } else {
                m.x0[i]
            }
        })
        .collect();
    cs.compute(&x, &zeros(nn), 0.0, &tie, &mut zeros(nn));
    let s = cs.stats();
    assert_eq!((s.closed, s.released), (2, 2));
    assert!(same_deck_pairs(&cs) > 0);
}

/// Random warped faces and nodes: how many of the node's motions relative to the corners, of
/// at most `scale` times the pair's first due ([`first_due`], from the search sphere at these
/// positions), bring it into contact; and how many pairs had a positive first due.
fn first_due_crossings(scale_: f64, seed: u64) -> (usize, usize) {
    let mut rng = Rng(seed);
    let (mut positive, mut touched) = (0, 0);
    for _ in 0..3000 {
        let x = penalty::tests::warped_face(&mut rng).to_vec();
        let face = Face {
            elem: 0,
            face: 0,
            nodes: [0, 1, 2, 3],
            k: 1.0,
            depth: rng.range(0.05, 0.5),
        };
        let margin = rng.range(0.0, 0.2);
        let (c, reach) = search_sphere(&face, (&x).into(), margin);
        let sphere = Sphere::new(c, reach).get();
        let p: [Vec3; 4] = std::array::from_fn(|a| x[a]);
        let b = FaceBounds::new(&p);
        for _ in 0..20 {
            let s = [
                rng.range(-1.5, 2.5),
                rng.range(-1.5, 2.5),
                rng.range(-1.5, 1.5),
            ];
            let due = first_due(sphere, s, margin);
            if due <= 0.0 {
                continue;
            }
            positive += 1;
            let d = scale_ * due as f64;
            for k in 0..4 {
                // first all corners straight at the node, then at random, mostly towards it
                let at = sub(s, b.c);
                let at = scale(at, d / norm(at));
                let q = p.map(|c| {
                    if k == 0 {
                        return add(c, at);
                    }
                    let mut m = [0.0; 3];
                    for v in m.iter_mut() {
                        *v = rng.range(-1.0, 1.0);
                    }
                    m = add(m, scale(at, 2.0 / d));
                    add(c, scale(m, d * rng.range(0.5, 1.0) / norm(m)))
                });
                let touch = penalty::project(&q, s).is_some_and(|pr| {
                    pr.gap < -GAP_TOL * FaceBounds::new(&q).r && pr.gap > -face.depth
                });
                touched += touch as usize;
            }
        }
    }
    (positive, touched)
}

/// A pair that a full build lists first waits for its clearance from the face's search sphere
/// ([`first_due`]): no motion of the corners relative to the node within it brings them into
/// contact (random warped faces, depths and margins; 4 motions a pair). The check has teeth:
/// motions of 3 times the clearance do.
#[test]
fn first_due_from_the_sphere_is_never_crossed() {
    let (positive, touched) = first_due_crossings(1.0, 31);
    assert!(
        positive > 20_000,
        "{positive} pairs with a positive first due"
    );
    assert_eq!(touched, 0, "{touched} crossings");
    let (_, touched) = first_due_crossings(3.0, 31);
    assert!(touched > 0, "motions of 3 clearances never touched");
}

/// The motion bound watches a slot born of a split: it starts at its set's last position and
/// reference position and is watched as its set was (its nodes are on the surface), so a move
/// of that slot alone over the next step is in the bound and, beyond the margin, brings a full
/// build; a step without motion adds nothing.
#[test]
fn a_slot_born_of_a_split_is_watched() {
    let deck = single_part_model(BoxMesh::new([1, 1, 2], [1.0, 1.0, 2.0]), mat(), 1.0);
    let sm = split_with_contact(deck, 1.0);
    let m = &sm.model;
    let nn = m.num_nodes();
    let mut intact = vec![true; sm.faces.len()];
    let mut sets = CoincidentSets::build(nn, &sm.faces, &intact);
    let mut x: Vec<Vec3> = (0..nn)
        .filter(|&i| sets.rep(i as u32) == i as u32)
        .map(|i| m.x0[i])
        .collect();
    let mut cs = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let step = |cs: &mut ContactSet, x: &[Vec3], sets: &CoincidentSets, intact: &[bool]| {
        let tie = ties(&sm, intact);
        let v = zeros(x.len());
        let slots = Some(sets.slots());
        let mut f = zeros(x.len());
        let (xv, vv) = (Points::new(x, slots), Points::new(&v, slots));
        let r = cs.compute_with_slots(xv, vv, 1e-3, &tie, sets.slots(), &mut f);
        (cs.contacts[0].step_motion, r.rebuilt)
    };
    assert_eq!(step(&mut cs, &x, &sets, &intact), (0.0, true));
    // the one interface fails: its upper copies get slots of their own
    intact[0] = false;
    sets.split_after_failure(&sm.faces, &intact, &[0]);
    assert_eq!(sets.born().len(), 4, "{:?}", sets.born());
    for &(new, from) in sets.born() {
        assert_eq!(new as usize, x.len());
        x.push(x[from as usize]);
    }
    cs.sets_split(sets.born());
    let f = &sm.faces[0];
    cs.activate(&[(f.elems[0], f.faces[0]), (f.elems[1], f.faces[1])]);
    // only the new slots move, by more than the margin (0.1 of the faces' size) since the
    // build: a new full build, from the reference positions the new slots took over
    let d = [0.0, 0.0, 0.3];
    let born: Vec<u32> = sets.born().iter().map(|b| b.0).collect();
    for &s in &born {
        x[s as usize] = add(x[s as usize], d);
    }
    let (motion, rebuilt) = step(&mut cs, &x, &sets, &intact);
    assert!(motion >= norm(d) && rebuilt, "{motion} {rebuilt}");
    assert_eq!(step(&mut cs, &x, &sets, &intact), (0.0, false));
}

/// The chains of a split model read the deck node of each copy from the model's own origin
/// (shared, not copied: 4 bytes a copy); given another origin, they copy it.
#[test]
fn chains_share_the_models_origin() {
    let deck = single_part_model(BoxMesh::new([2, 1, 1], [2.0, 1.0, 1.0]), mat(), 1.0);
    let sm = split_with_contact(deck, 1.0);
    let m = &sm.model;
    let origin =
        m.x0.origin()
            .expect("a split model shares its deck's positions");
    let shared = ContactSet::new(m, Some(origin)).unwrap();
    assert!(shared.contacts[0].chains.reads(origin));
    let other = origin.to_vec();
    let copied = ContactSet::new(m, Some(&other)).unwrap();
    let ch = &copied.contacts[0].chains;
    assert!(!ch.reads(&other) && !ch.reads(origin));
    for n in 0..m.num_nodes() as u32 {
        assert_eq!(ch.copies(n), shared.contacts[0].chains.copies(n));
    }
}

/// A search sphere kept in single precision holds the sphere it was made from: every point
/// within the reach of the centre (on its boundary too) is within the stored one, whose radius
/// is not much larger.
#[test]
fn single_precision_spheres_hold_their_spheres() {
    let mut r = Rng(23);
    for _ in 0..2000 {
        let c: Vec3 = std::array::from_fn(|_| r.range(-3.0, 3.0) * 10f64.powf(r.range(-3.0, 1.0)));
        let reach = 10f64.powf(r.range(-4.0, 0.0));
        let s = Sphere::new(c, reach);
        let (c32, r2) = s.get();
        assert!(
            r2.sqrt() <= reach * (1.0 + 1e-6) + 1e-6 * norm(c),
            "{c:?} {reach}"
        );
        for _ in 0..20 {
            let d: Vec3 = std::array::from_fn(|_| r.range(-1.0, 1.0));
            let p = add(c, scale(d, reach / norm(d)));
            assert!(dist2(p, c32) <= r2, "{c:?} {reach} {p:?}");
        }
    }
}

/// The space order of a side's nodes as the serial code made it: the box of their finite
/// positions, each node's cell of 2^21 per axis, its Morton key ([`morton`], shared), and the
/// (key, place) pairs sorted. The reference of `space_order_does_not_depend_on_the_threads`.
fn serial_space_order(nodes: &[u32], x: &[Vec3]) -> Vec<(u64, u32)> {
    let mut b = Aabb::empty();
    for &n in nodes {
        let p = x[n as usize];
        if p.iter().all(|v| v.is_finite()) {
            b.include(p);
        }
    }
    let h = b.extent() / ((1u64 << 21) - 1) as f64;
    let cell = |v: f64, lo: f64| -> u64 {
        let q = ((v - lo) / h).floor();
        if q > 0.0 {
            (q as u64).min((1 << 21) - 1)
        } else {
            0
        }
    };
    let mut order: Vec<(u64, u32)> = nodes
        .iter()
        .enumerate()
        .map(|(k, &n)| {
            let p = x[n as usize];
            (
                morton(std::array::from_fn(|d| cell(p[d], b.min[d]))),
                k as u32,
            )
        })
        .collect();
    order.sort_unstable();
    order
}

/// A side's space order (Morton keys of its nodes, sorted) is made on every thread: the serial
/// code's order on 1, 2 and 3 threads, for a side of over 1,000 nodes (several tasks), with
/// tied keys (coincident nodes, non-finite positions), signed zeros, and the extreme positions
/// at the end of the side's list (the last task's part of the box).
#[test]
fn space_order_does_not_depend_on_the_threads() {
    let mut m = two_blocks(
        [24, 24, 2],
        [1.0; 3],
        [2, 2, 2],
        [1.0; 3],
        [0.25, 0.25, 0.99],
    );
    m.contacts.push(def(true, 0.0, 0.0, 0.0));
    let cs = ContactSet::new(&m, None).unwrap();
    let side = &cs.contacts[0].sides[0];
    let nodes = &side.nodes;
    assert!(nodes.len() > 4 * NODE_CHUNK, "{}", nodes.len());
    // positions jittered so that the keys are not those of a regular grid
    let mut x: Vec<Vec3> =
        m.x0.iter()
            .enumerate()
            .map(|(i, p)| {
                let j = (i as f64 * 0.618_033_988_75).fract() - 0.5;
                [p[0] + 0.01 * j, p[1] - 0.02 * j, p[2] + 0.005 * j]
            })
            .collect();
    let at = |k: usize| nodes[k] as usize;
    let last = nodes.len() - 1;
    // the box's extremes last, coincident pairs, non-finite and signed-zero coordinates
    x[at(last)] = [3.0, 2.5, 4.0];
    x[at(last - 1)] = [-2.0, -1.5, -3.0];
    x[at(5)] = x[at(6)];
    x[at(100)] = x[at(700)];
    x[at(7)] = [f64::NAN, 0.5, 0.5];
    x[at(8)] = [f64::INFINITY, f64::NEG_INFINITY, 0.5];
    x[at(9)] = [-0.0, 0.0, -0.0];
    x[at(10)] = [f64::NAN; 3];
    let reference = serial_space_order(nodes, &x);
    assert!(reference.windows(2).any(|w| w[0].0 == w[1].0), "tied keys");
    let order = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| side.space_order(Points::new(&x, None)))
    };
    for threads in [1, 2, 3] {
        assert_eq!(order(threads), reference, "{threads} threads");
    }
}
