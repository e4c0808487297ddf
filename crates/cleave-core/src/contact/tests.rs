//! End-to-end checks of the contact engine without the solver: forces, energy, friction,
//! ties, activation of crack faces, lazy search, stable step and thread independence.

use super::*;
use crate::math::norm;
use crate::mesh::{single_part_model, BoxMesh};
use crate::model::{ContactSurface, Material, MaterialKind, Part, SegmentSet};
use crate::setup::Setup;
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
    });
    m
}

fn def(single: bool, fs: f64, fd: f64, dc: f64) -> ContactDef {
    ContactDef {
        id: 1,
        single_surface: single,
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
        let st = cs.compute(&m.x0, &v, 0.0, &[], &mut f);
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
        &m.x0,
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
    let mut m = two_blocks(
        [1, 1, 1],
        [1.0; 3],
        [1, 1, 1],
        [0.2; 3],
        [0.4, 0.4, 1.0 - delta],
    );
    m.contacts.push(ContactDef {
        slave: ContactSurface::Part(1),
        master: Some(ContactSurface::Part(0)),
        ..def(false, fs, fd, dc)
    });
    let k = 0.1 * K;
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
        assert_eq!(cs.compute(&m.x0, &v, 0.0, &[], &mut zeros(nn)).pairs, 4);
        for step in 1..=2 {
            let mut f = zeros(nn);
            let st = cs.compute(&m.x0, &v, dt, &[], &mut f);
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
/// k delta along +z.
#[test]
fn nearest_face_wins_near_an_edge() {
    let delta = 0.01;
    let mut m = two_blocks(
        [1, 1, 1],
        [1.0; 3],
        [1, 1, 1],
        [0.2; 3],
        [0.7, 0.4, 1.0 - delta],
    );
    m.contacts.push(def(true, 0.0, 0.0, 0.0));
    let mut cs = ContactSet::new(&m, None).unwrap();
    let nn = m.num_nodes();
    let mut f = zeros(nn);
    let st = cs.compute(&m.x0, &zeros(nn), 0.0, &[], &mut f);
    assert_eq!(st.pairs, 4);
    for i in (8..16).filter(|&i| m.x0[i][2] < 1.0) {
        assert!(
            rel(f[i][2], 0.1 * K * delta) < 1e-12 && f[i][0] == 0.0,
            "{:?}",
            f[i]
        );
    }
}

/// Two unit cubes stacked in z, each on its own 8 nodes (a split model; origin maps the copies
/// to the 12 deck nodes). The upper one is pushed 0.01 into the lower one.
/// - the shared faces are not surfaces at first: no contact even when untied;
/// - once activated, tied copies (one coincident set per deck node) never contact;
/// - untied (the failure named to `activate`), the 4 + 4 nodes of the crack faces penetrate each other: 8 pairs, 8 k delta with
///   k = 0.1 K.
#[test]
fn ties_and_crack_faces() {
    let delta = 0.01;
    let deck = single_part_model(BoxMesh::new([1, 1, 2], [1.0, 1.0, 2.0]), mat(), 1.0);
    let origin: Vec<u32> = deck.conn.iter().flatten().copied().collect();
    let mut m = deck.clone();
    m.x0 = origin.iter().map(|&o| deck.x0[o as usize]).collect();
    m.v0 = zeros(16);
    m.node_ids = origin.iter().map(|&o| o as i64 + 1).collect();
    m.conn = (0..2u32)
        .map(|e| std::array::from_fn(|a| 8 * e + a as u32))
        .collect();
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
    let mut x = m.x0.clone();
    assert_eq!(x[7], [1.0; 3]); // BoxMesh numbers x fastest
    x[7] = [0.9, 0.9, 0.9];
    let st = cs.compute(&x, &zeros(8), 0.0, &[], &mut zeros(8));
    assert_eq!(st.pairs, 0);
    let c = &cs.contacts()[0];
    let side = &c.sides[0];
    for (i, &n) in side.nodes.iter().enumerate() {
        for &f in &c.passes[0].cand[i] {
            assert!(!side.faces[f as usize].nodes.contains(&n));
        }
    }
}

/// Positions of two perturbed 6x6x2 blocks approaching each other, step `n` of a made-up
/// motion (B moves down 0.004 per step, every node jitters by up to 0.01 per step).
fn jitter_positions(m: &Model, na: usize, steps: usize, seed: u64) -> Vec<Vec<Vec3>> {
    let mut r = Rng(seed);
    let mut x = m.x0.clone();
    let mut out = vec![x.clone()];
    for _ in 0..steps {
        for (i, p) in x.iter_mut().enumerate() {
            let dz = if i >= na { -0.004 } else { 0.0 };
            *p = add(
                *p,
                [
                    r.range(-0.01, 0.01),
                    r.range(-0.01, 0.01),
                    dz + r.range(-0.01, 0.01),
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

/// Interfaces of a fully split 4x4x2 block fail at random steps while every node jitters: the
/// incremental search around the activated faces gives exactly the forces of a full rebuild
/// at every step (same ties, same faces), for 40 steps; and it is used (few full builds).
/// Single surface over the block, and surface to surface between its lower and upper layer
/// (two parts, one material), where faces join one side at a time.
#[test]
fn incremental_activation_equals_full_rebuild() {
    for single in [true, false] {
        incremental_vs_full(single);
    }
}

fn incremental_vs_full(single: bool) {
    use crate::separation::coincident::CoincidentSets;
    use crate::separation::split::split_model;
    let mut deck = single_part_model(BoxMesh::new([4, 4, 2], [1.0, 1.0, 0.5]), mat(), 1.0);
    deck.separations.push(crate::model::SeparationDef {
        material: 0,
        model: 1,
        sigmax: 1.0,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
    });
    deck.parts.push(Part {
        id: 2,
        title: "upper".into(),
        section: 0,
        material: 0,
    });
    deck.elem_part = (0..32).map(|e| (e >= 16) as u32).collect();
    deck.contacts.push(def(single, 0.3, 0.2, 0.5));
    let sm = split_model(&deck);
    let m = &sm.model;
    let nn = m.num_nodes();
    let mut intact = vec![true; sm.faces.len()];
    let mut lazy = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let mut eager = ContactSet::new(m, Some(&sm.origin)).unwrap();
    let mut r = Rng(21);
    let mut x = m.x0.clone();
    let dt = 1e-3;
    let mut pairs = 0;
    for step in 0..40 {
        let mut failed = Vec::new();
        if step % 3 == 1 {
            for (k, ok) in intact.iter_mut().enumerate().take(sm.interfaces) {
                if *ok && r.unit() < 0.08 {
                    *ok = false;
                    let f = &sm.faces[k];
                    failed.push((f.elems[0], f.faces[0]));
                    failed.push((f.elems[1], f.faces[1]));
                }
            }
        }
        let sets = CoincidentSets::build(nn, &sm.faces, &intact);
        let tie: Vec<u32> = (0..nn as u32)
            .map(|i| sets.set_of(i).map_or(u32::MAX, |s| s[0]))
            .collect();
        assert_eq!(lazy.activate(&failed), eager.activate(&failed));
        eager.ties_changed();
        let v: Vec<Vec3> = (0..nn)
            .map(|_| [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)])
            .collect();
        if step > 0 {
            for (xi, vi) in x.iter_mut().zip(&v) {
                *xi = add(*xi, scale(*vi, 0.004 * dt / dt));
            }
        }
        let (mut fa, mut fb) = (zeros(nn), zeros(nn));
        let sa = lazy.compute(&x, &v, dt, &tie, &mut fa);
        let sb = eager.compute(&x, &v, dt, &tie, &mut fb);
        assert_eq!(
            (fa, sa.energy, sa.pairs),
            (fb, sb.energy, sb.pairs),
            "step {step}"
        );
        pairs += sa.pairs;
    }
    let st = lazy.stats();
    assert!(pairs > 200, "single {single}: {pairs} pairs");
    assert!(st.updates >= 10, "single {single}: {st:?}");
    assert!(st.rebuilds < 20, "single {single}: {st:?}");
}
