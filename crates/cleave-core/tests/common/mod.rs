//! Helpers shared by the core's integration tests.

#![allow(dead_code)] // each test file uses its own subset of the helpers

use cleave_core::contact::ContactSet;
use cleave_core::model::Model;
use cleave_core::solver::{Observer, Solver};

/// An observer from a closure.
pub struct Obs<F: FnMut(&Solver)>(pub F);

impl<F: FnMut(&Solver)> Observer for Obs<F> {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        (self.0)(s);
        Ok(())
    }
}

/// Run `m` (with its contact definitions, if any) to its end time, calling `f` with the state
/// at every step t^n.
pub fn run(m: &Model, f: impl FnMut(&Solver)) -> Solver<'_> {
    let mut s = Solver::new(m).expect("setup");
    if !m.contacts.is_empty() {
        s.attach_contact(ContactSet::new(m, None).expect("contact"));
    }
    s.run(&mut Obs(f)).expect("run");
    s
}

/// The bits of the state a step leaves: positions, velocities, stresses, the energies and
/// the time (tests that compare two runs bit for bit).
pub fn state_bits(s: &Solver) -> Vec<u64> {
    let mut b: Vec<u64> = s
        .positions()
        .iter()
        .flatten()
        .map(|x| x.to_bits())
        .collect();
    b.extend(s.velocities().iter().flatten().map(|x| x.to_bits()));
    b.extend(s.state.stress.iter().flatten().map(|x| x.to_bits()));
    let e = &s.state.energy;
    b.extend([e.kinetic, e.internal, e.hourglass, e.external_work].map(f64::to_bits));
    b.push(s.state.t.to_bits());
    b
}

/// Take `n` steps of `s` (each ends with the positions of the next).
pub fn steps(s: &mut Solver, n: usize) {
    for _ in 0..n {
        s.advance_to_half_step().expect("step");
        s.update_positions().expect("positions");
    }
}

/// A separation group on material `material` that nothing breaks (MODEL 1, SIGMAX 1e30): the
/// mesh is split and every interface is checked, but none fails.
pub fn unbreakable(material: usize) -> cleave_core::model::SeparationDef {
    cleave_core::model::SeparationDef {
        material,
        model: 1,
        sigmax: 1e30,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    }
}

/// The largest displacement component of `last` from `x0` (the scale of a run's motion).
pub fn motion_scale(last: &[[f64; 3]], x0: &[[f64; 3]]) -> f64 {
    last.iter()
        .zip(x0)
        .map(|(x, x0)| (0..3).map(|d| (x[d] - x0[d]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
}

/// The largest |x_copy - x_deck| over the steps, components and copies of a split run's
/// positions `split` against the unsplit run's `deck` (`origin`: the deck node of each copy).
pub fn copy_deviation<'a>(
    deck: impl IntoIterator<Item = &'a Vec<[f64; 3]>>,
    split: impl IntoIterator<Item = &'a Vec<[f64; 3]>>,
    origin: &[u32],
) -> f64 {
    let mut worst = 0.0f64;
    for (xa, xb) in deck.into_iter().zip(split) {
        for (i, &o) in origin.iter().enumerate() {
            for d in 0..3 {
                worst = worst.max((xb[i][d] - xa[o as usize][d]).abs());
            }
        }
    }
    worst
}

/// A cube of side `l0` of `mat` in uniaxial stress along x: symmetry constraints on its three
/// faces through the origin, and its x = l0 face driven by the displacement curve (`ts`,
/// `ys`) until `end`. Returns the model and a node of the driven face.
#[allow(dead_code)]
pub fn uniaxial_cube(
    mat: cleave_core::model::Material,
    l0: f64,
    (ts, ys): (Vec<f64>, Vec<f64>),
    end: f64,
) -> (Model, usize) {
    use cleave_core::model::{MotionTarget, PrescribedMotion, Spc, Vad};
    let mut m = cleave_core::mesh::box_model([1, 1, 1], [l0; 3], mat, end);
    m.curves.push(cleave_core::curve::Curve {
        id: 1,
        t: ts,
        y: ys,
    });
    for (i, x) in m.x0.iter().enumerate() {
        let dof = [x[0] == 0.0, x[1] == 0.0, x[2] == 0.0, false, false, false];
        if dof.iter().any(|&d| d) {
            m.spcs.push(Spc {
                node: i as u32,
                dof,
            });
        }
    }
    for node in m.nodes_where(0, l0, 1e-9 * l0) {
        m.prescribed.push(PrescribedMotion {
            window: cleave_core::model::Window::ALWAYS,
            target: MotionTarget::Node(node),
            dof: cleave_core::model::MotionDof::Axis(0),
            vad: Vad::Displacement,
            curve: 0,
            sf: 1.0,
        });
    }
    let face = m.nodes_where(0, l0, 1e-9 * l0)[0] as usize;
    (m, face)
}

/// Linear elastic steel (rho 7800 kg/m^3, E 200 GPa) with Poisson's ratio `poisson`.
pub fn elastic_steel(poisson: f64) -> cleave_core::model::Material {
    cleave_core::model::Material {
        id: 1,
        density: 7800.0,
        young: 200e9,
        poisson,
        kind: cleave_core::model::MaterialKind::Elastic,
    }
}

/// Append a structured box (n elements, sides l, lowest corner at `origin`) as a new part with
/// its own section and material; returns the part index and the new nodes' index range.
pub fn append_box(
    m: &mut cleave_core::model::Model,
    n: [usize; 3],
    l: [f64; 3],
    origin: cleave_core::math::Vec3,
    mat: cleave_core::model::Material,
) -> (usize, std::ops::Range<usize>) {
    let b = cleave_core::mesh::BoxMesh::new(n, l);
    let base = m.x0.len();
    let part = m.parts.len();
    m.materials.push(cleave_core::model::Material {
        id: m.materials.len() as i64 + 1,
        ..mat
    });
    m.sections.push(cleave_core::model::Section {
        id: m.sections.len() as i64 + 1,
        elform: 1,
    });
    m.parts.push(cleave_core::model::Part {
        id: part as i64 + 1,
        title: format!("part {}", part + 1),
        section: m.sections.len() - 1,
        material: m.materials.len() - 1,
        hourglass: None,
    });
    for x in b.x {
        m.x0.push(cleave_core::math::add(x, origin));
        m.v0.push([0.0; 3]);
        m.node_ids.push(m.x0.len() as i64);
    }
    for c in b.conn {
        m.conn.push(c.map(|i| i + base as u32));
        m.elem_part.push(part as u32);
        m.elem_ids.push(m.conn.len() as i64);
    }
    (part, base..m.x0.len())
}

/// A soft elastic material (rho 1000, E 10 MPa, nu 0.3), id 1.
pub fn soft_elastic() -> cleave_core::model::Material {
    cleave_core::model::Material {
        id: 1,
        density: 1000.0,
        young: 1e7,
        poisson: 0.3,
        kind: cleave_core::model::MaterialKind::Elastic,
    }
}

/// A rigid steel (rho 7800) without constraints, id 2.
pub fn free_rigid() -> cleave_core::model::Material {
    cleave_core::model::Material {
        id: 2,
        density: 7800.0,
        young: 2e11,
        poisson: 0.3,
        kind: cleave_core::model::MaterialKind::Rigid {
            cmo: 0,
            con1: 0,
            con2: 0,
        },
    }
}
