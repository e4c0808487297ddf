//! The model as the GPU reads it: flat arrays built once on the host.
//!
//! - `par` (f64): the materials (`MAT_STRIDE` values each: density, Lame lambda, shear modulus,
//!   wave speed, step speed, law 0 elastic / 1 bilinear plastic, SIGY, Hp, beta), then the
//!   curves (n, abscissae, ordinates), the body loads (axis, curve offset or -1, SF) and the
//! - `nptr`/`ninc`: for each node, its element corners `8 e + a` in element order (the order
//!   its forces are summed in, so the sum is the same bits every run);
//!   prescribed nodal motions (axis, VAD 0 velocity / 1 displacement, SF, curve offset, the
//!   node's initial coordinate on the axis) and the planar rigid walls (a point, the unit
//!   normal, FRIC);
//! - `nflag`: the SPC bits of each node (1 x, 2 y, 4 z), and 8 << w for each rigid wall w
//!   that stops it;
//! - `mptr`: for each node, its prescribed motions (in the deck's order).

use cleave_core::material::SolidLaw;
use cleave_core::math::{norm, scale, sub};
use cleave_core::model::{Model, MotionTarget, Vad};
use cleave_core::setup::Setup;

/// Values per material in `par`.
pub const MAT_STRIDE: usize = 10;
/// The most rigid walls (the bits of `nflag` above the SPC's, the ledger's partial sums).
pub const MAX_WALLS: usize = 8;

/// The flat arrays of a model ([module docs](self)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    pub par: Vec<f64>,
    pub body_off: u32,
    pub n_body: u32,
    pub mot_off: u32,
    pub wall_off: u32,
    pub conn: Vec<u32>,
    pub emat: Vec<u32>,
    pub nptr: Vec<u32>,
    pub ninc: Vec<u32>,
    pub nflag: Vec<u32>,
    pub mptr: Vec<u32>,
}

impl Layout {
    /// The arrays of a model that [`crate::support::unsupported`] accepts (hexahedra of
    /// deformable materials, nodal constraints).
    pub fn new(model: &Model, setup: &Setup) -> Self {
        let nn = model.num_nodes();
        let mut par = Vec::new();
        // the materials, then again with the free-element step for the lone elements
        for p in setup.params.iter().chain(&setup.loose_params) {
            let mut m = [0.0; MAT_STRIDE];
            if let Some(p) = p {
                m[..5].copy_from_slice(&[p.density, p.lambda, p.shear, p.wave_speed, p.step_speed]);
                if let SolidLaw::PlasticKinematic { sigy, hp, beta } = p.law {
                    m[5..9].copy_from_slice(&[1.0, sigy, hp, beta]);
                }
            }
            par.extend_from_slice(&m);
        }
        let mut curve_off = Vec::with_capacity(model.curves.len());
        for c in &model.curves {
            curve_off.push(par.len() as f64);
            par.push(c.t.len() as f64);
            par.extend_from_slice(&c.t);
            par.extend_from_slice(&c.y);
        }
        let body_off = par.len() as u32;
        for b in &model.body_loads {
            par.extend_from_slice(&[b.axis as f64, b.curve.map_or(-1.0, |c| curve_off[c]), b.sf]);
        }
        let mot_off = par.len() as u32;
        let mut motions: Vec<(u32, usize)> = (setup.node_motion.iter().enumerate())
            .filter_map(|(k, m)| match m.target {
                MotionTarget::Node(n) => Some((n, k)),
                _ => None,
            })
            .collect();
        motions.sort_by_key(|&(n, _)| n); // stable: a node's motions stay in the deck's order
        let mut mptr = vec![0u32; nn + 1];
        for &(n, k) in &motions {
            let m = &setup.node_motion[k];
            mptr[n as usize + 1] += 1;
            par.extend_from_slice(&[
                m.axis as f64,
                match m.vad {
                    Vad::Velocity => 0.0,
                    Vad::Displacement => 1.0,
                },
                m.sf,
                curve_off[m.curve],
                model.x0[n as usize][m.axis],
            ]);
        }
        for i in 0..nn {
            mptr[i + 1] += mptr[i];
        }
        let wall_off = par.len() as u32;
        for wall in &model.rigid_walls {
            let d = sub(wall.head, wall.tail);
            par.extend_from_slice(&wall.tail);
            par.extend_from_slice(&scale(d, 1.0 / norm(d)));
            par.push(wall.fric);
        }
        let mut nflag = vec![0u32; nn];
        for (w, nodes) in setup.wall_nodes.iter().enumerate() {
            for &n in nodes {
                nflag[n as usize] |= 8 << w;
            }
        }
        for &(n, d) in &setup.spc {
            for (a, &fixed) in d.iter().enumerate() {
                if fixed {
                    nflag[n as usize] |= 1 << a;
                }
            }
        }
        let mut nptr = vec![0u32; nn + 1];
        for c in &model.conn {
            for &n in c {
                nptr[n as usize + 1] += 1;
            }
        }
        for i in 0..nn {
            nptr[i + 1] += nptr[i];
        }
        let mut fill = nptr.clone();
        let mut ninc = vec![0u32; 8 * model.num_elements()];
        for (e, c) in model.conn.iter().enumerate() {
            for (a, &n) in c.iter().enumerate() {
                let k = &mut fill[n as usize];
                ninc[*k as usize] = 8 * e as u32 + a as u32;
                *k += 1;
            }
        }
        Self {
            par,
            body_off,
            n_body: model.body_loads.len() as u32,
            mot_off,
            wall_off,
            conn: model.conn.iter().flatten().copied().collect(),
            emat: (setup.elem_mat.iter().zip(&setup.lone))
                .map(|(&m, &lone)| m + if lone { setup.params.len() as u32 } else { 0 })
                .collect(),
            nptr,
            ninc,
            nflag,
            mptr,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::mesh::box_model;
    use cleave_core::model::{Material, MaterialKind};

    #[test]
    fn every_corner_is_gathered_once_in_element_order() {
        let steel = Material {
            id: 1,
            density: 7850.0,
            young: 210e9,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        };
        let model = box_model([3, 2, 2], [0.3, 0.2, 0.2], steel, 1.0);
        let setup = Setup::new(&model).unwrap();
        let l = Layout::new(&model, &setup);
        let nn = model.num_nodes();
        assert_eq!(l.nptr[nn] as usize, 8 * model.num_elements());
        let mut seen = vec![false; 8 * model.num_elements()];
        for n in 0..nn {
            let incs = &l.ninc[l.nptr[n] as usize..l.nptr[n + 1] as usize];
            assert!(incs.windows(2).all(|w| w[0] < w[1]), "element order");
            for &c in incs {
                assert_eq!(model.conn[c as usize / 8][c as usize % 8], n as u32);
                assert!(!std::mem::replace(&mut seen[c as usize], true));
            }
        }
        assert!(seen.iter().all(|&s| s));
        // the material: density, then elastic law 0
        assert_eq!(l.par[0], 7850.0);
        assert_eq!(l.par[5], 0.0);
    }
}
