//! The tetrahedron with nodal pressure averaging (LS-DYNA ELFORM 13), which relieves the
//! volumetric locking of the constant-strain tetrahedron in nearly incompressible flow
//! (plasticity, rubber-like materials).
//!
//! Bonet and Burton (1998, "A simple average nodal pressure tetrahedral element for
//! incompressible and nearly incompressible dynamic explicit applications", Commun. Numer.
//! Meth. Engng 14, 437-449) average the volume change over the elements around each node. In
//! the rate form cleave's materials are written in, with `theta_e = tr(D_e) dt` the volumetric
//! strain increment of tetrahedron e and `V_e` its mid-step volume:
//!
//! 1. before the element pass, each node's increment is the volume-weighted mean of its
//!    elements', `theta_a = sum_e V_e theta_e / sum_e V_e`, and each element takes the mean of
//!    its 4 nodes', `theta_bar_e = 1/4 sum_a theta_a`, in place of its own: the material
//!    update sees `d_eps = dev(D dt) + theta_bar_e / 3 I` ([`super::kernel`]'s stress update);
//! 2. after the pass, the pressure is averaged the same way, `p_a = sum_e V_e p_e / sum_e V_e`,
//!    `p_tilde_e = 1/4 sum_a p_a`, and the element's corner forces carry `p_tilde_e` instead of
//!    its own `p_e = -tr(sigma_e)/3`: `f_a += V_e (p_tilde_e - p_e) b_a`.
//!
//! With the same weights in both, the work of the averaged pressures on the elements' own
//! volume changes equals the work of the elements' pressures on the averaged ones,
//! `sum_e V_e p_tilde_e theta_e = sum_e V_e p_e theta_bar_e`, so the internal energy the material
//! books is the work the forces do. The averages run over the ELFORM 13 elements only (a node
//! they share with other elements averages over its ELFORM 13 elements). Bulk viscosity and the
//! time step stay per element. Every sum is a gather in a fixed order, so the result is the same
//! on any number of threads.

use rayon::prelude::*;

use super::tet4;
use crate::math::{Sym3, Vec3};

/// Position of element `e` in the list is `pos[e]`; `NONE` for elements that do not average.
const NONE: u32 = u32::MAX;

/// The averaging of the ELFORM 13 tetrahedra of a model, with its scratch.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub struct NodalPressure {
    /// The averaging elements, ascending, and the 4 nodes of each.
    elems: Vec<u32>,
    nodes_of: Vec<[u32; 4]>,
    pos: Vec<u32>,
    /// The nodes they touch, ascending, with their elements' (position, corner) pairs (CSR).
    nodes: Vec<u32>,
    start: Vec<u32>,
    around: Vec<(u32, u8)>,
    /// Per listed element: the index in `nodes` of each of its nodes, the weight V_e
    /// (mid-step volume), its own increment theta_e, the averaged theta_bar_e and p_tilde_e,
    /// and the corner corrections of the pressure.
    node_idx: Vec<[u32; 4]>,
    vol: Vec<f64>,
    theta: Vec<f64>,
    theta_bar: Vec<f64>,
    p_tilde: Vec<f64>,
    /// The elements' own pressures of the step (scratch).
    p: Vec<f64>,
    corr: Vec<[Vec3; 4]>,
    /// Per touched node: the averaged value.
    node_val: Vec<f64>,
}

impl NodalPressure {
    /// For the elements `e` of `conn` with `averages(e)` (tetrahedra in the stored layout,
    /// corners 0, 1, 2, 4); `None` if there are none. `num_nodes` bounds the node indices.
    pub fn new(
        conn: &[[u32; 8]],
        averages: impl Fn(usize) -> bool,
        num_nodes: usize,
    ) -> Option<Self> {
        let elems: Vec<u32> = (0..conn.len())
            .filter(|&e| averages(e))
            .map(|e| e as u32)
            .collect();
        if elems.is_empty() {
            return None;
        }
        let nodes_of: Vec<[u32; 4]> = elems
            .iter()
            .map(|&e| {
                let c = &conn[e as usize];
                [c[0], c[1], c[2], c[4]]
            })
            .collect();
        let mut pos = vec![NONE; conn.len()];
        for (k, &e) in elems.iter().enumerate() {
            pos[e as usize] = k as u32;
        }
        let mut count = vec![0u32; num_nodes];
        for ns in &nodes_of {
            for &n in ns {
                count[n as usize] += 1;
            }
        }
        let nodes: Vec<u32> = (0..num_nodes as u32)
            .filter(|&n| count[n as usize] > 0)
            .collect();
        let mut start = Vec::with_capacity(nodes.len() + 1);
        start.push(0u32);
        for &n in &nodes {
            start.push(start.last().copied().unwrap_or(0) + count[n as usize]);
        }
        let mut slot = vec![0u32; num_nodes];
        for (i, &n) in nodes.iter().enumerate() {
            slot[n as usize] = start[i];
        }
        let mut around = vec![(0u32, 0u8); start.last().copied().unwrap_or(0) as usize];
        for (k, ns) in nodes_of.iter().enumerate() {
            for (a, &n) in ns.iter().enumerate() {
                around[slot[n as usize] as usize] = (k as u32, a as u8);
                slot[n as usize] += 1;
            }
        }
        let m = elems.len();
        let node_idx = nodes_of
            .iter()
            .map(|ns| ns.map(|n| nodes.binary_search(&n).unwrap_or(0) as u32))
            .collect();
        Some(Self {
            node_idx,
            elems,
            nodes_of,
            pos,
            node_val: vec![0.0; nodes.len()],
            nodes,
            start,
            around,
            vol: vec![0.0; m],
            theta: vec![0.0; m],
            theta_bar: vec![0.0; m],
            p_tilde: vec![0.0; m],
            p: vec![0.0; m],
            corr: vec![[[0.0; 3]; 4]; m],
        })
    }

    /// Number of averaging elements.
    pub fn len(&self) -> usize {
        self.elems.len()
    }

    /// Whether there are none (never, for a value [`Self::new`] returned).
    pub fn is_empty(&self) -> bool {
        self.elems.is_empty()
    }

    /// The averaged volumetric strain increment of element `e` from the last
    /// [`Self::average_volume_change`], `None` for an element that does not average.
    #[inline]
    pub fn theta_bar(&self, e: usize) -> Option<f64> {
        let k = self.pos[e];
        (k != NONE).then(|| self.theta_bar[k as usize])
    }

    /// Part 1: each element's own increment `theta_e = tr(J_v J_mid^-1) dt` and weight V_mid
    /// at positions `x` (t^n) and velocities `v` (t^(n-1/2)), then the node and element means.
    /// An element inverted at mid-step gets weight 0 (the element pass reports it).
    ///
    /// `eroded[e]` marks elements eroded ([`crate::erosion`]; an empty slice: none): they take
    /// no part in the averages (weight 0) and get no pressure correction.
    pub fn average_volume_change(
        &mut self,
        x: impl Fn(u32) -> Vec3 + Sync,
        v: impl Fn(u32) -> Vec3 + Sync,
        dt: f64,
        eroded: &[bool],
    ) {
        let Self {
            elems,
            nodes_of,
            vol,
            theta,
            ..
        } = self;
        nodes_of
            .par_iter()
            .zip(elems.par_iter())
            .zip(vol.par_iter_mut().zip(theta.par_iter_mut()))
            .for_each(|((ns, &e), (w, th))| {
                if eroded.get(e as usize).is_some_and(|&d| d) {
                    (*w, *th) = (0.0, 0.0);
                    return;
                }
                let xe = ns.map(&x);
                let ve = ns.map(&v);
                (*w, *th) = tet4::volume_increment(&xe, &ve, dt).unwrap_or((0.0, 0.0));
            });
        let own = std::mem::take(&mut self.theta);
        self.node_means(&own);
        self.theta = own;
        let mut tb = std::mem::take(&mut self.theta_bar);
        self.element_means(&mut tb);
        self.theta_bar = tb;
    }

    /// Part 2: with the stresses after the element pass, the pressure corrections of the
    /// corner forces, `V^n (p_tilde_e - p_e) b_a` at positions `x`, added by `add(node, force)`
    /// node by node in ascending order, each node's in a fixed order.
    pub fn correct_forces(
        &mut self,
        x: impl Fn(u32) -> Vec3 + Sync,
        stress: &[Sym3],
        mut add: impl FnMut(u32, Vec3),
    ) {
        // the elements' own pressures, into a buffer kept between steps (no allocation)
        let mut p = std::mem::take(&mut self.p);
        p.par_iter_mut()
            .zip(self.elems.par_iter())
            .for_each(|(pe, &e)| {
                let s = &stress[e as usize];
                *pe = -(s[0] + s[1] + s[2]) / 3.0;
            });
        self.node_means(&p);
        let mut pt = std::mem::take(&mut self.p_tilde);
        self.element_means(&mut pt);
        self.p_tilde = pt;
        let Self {
            nodes_of,
            p_tilde,
            corr,
            vol: weight,
            ..
        } = self;
        nodes_of
            .par_iter()
            .zip(p_tilde.par_iter())
            .zip(p.par_iter())
            .zip(corr.par_iter_mut().zip(weight.par_iter()))
            .for_each(|(((ns, &pt), &pe), (c, &w))| {
                if w == 0.0 {
                    // out of the averages (eroded, or flat at the mid-step)
                    *c = [[0.0; 3]; 4];
                    return;
                }
                let xe = ns.map(&x);
                *c = match tet4::gradients(&xe) {
                    Some((vol, b)) => b.map(|ba| {
                        [
                            vol * (pt - pe) * ba[0],
                            vol * (pt - pe) * ba[1],
                            vol * (pt - pe) * ba[2],
                        ]
                    }),
                    None => [[0.0; 3]; 4],
                };
            });
        self.p = p;
        for (i, &n) in self.nodes.iter().enumerate() {
            let mut f = [0.0; 3];
            for &(k, a) in &self.around[self.start[i] as usize..self.start[i + 1] as usize] {
                let c = self.corr[k as usize][a as usize];
                f = [f[0] + c[0], f[1] + c[1], f[2] + c[2]];
            }
            add(n, f);
        }
    }

    /// `node_val[a] = sum_e V_e val_e / sum_e V_e` over the listed elements around each node.
    fn node_means(&mut self, val: &[f64]) {
        let Self {
            start,
            around,
            vol,
            node_val,
            ..
        } = self;
        node_val.par_iter_mut().enumerate().for_each(|(i, out)| {
            let (mut num, mut den) = (0.0, 0.0);
            for &(k, _) in &around[start[i] as usize..start[i + 1] as usize] {
                num += vol[k as usize] * val[k as usize];
                den += vol[k as usize];
            }
            *out = if den > 0.0 { num / den } else { 0.0 };
        });
    }

    /// `out[e] = 1/4 sum_a node_val[a]` over each listed element's nodes.
    fn element_means(&self, out: &mut [f64]) {
        out.par_iter_mut()
            .zip(self.node_idx.par_iter())
            .for_each(|(o, idx)| {
                *o = 0.25 * idx.iter().map(|&i| self.node_val[i as usize]).sum::<f64>();
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::mat_vec;
    use crate::mesh::BoxMesh;

    /// The averages against a direct computation: on a distorted tetrahedral box, a nonlinear
    /// velocity field gives each element its own theta_e; theta_bar_e must be the mean over the
    /// element's 4 nodes of the volume-weighted node means, computed here with plain loops. A
    /// linear field (uniform theta) must come back unchanged, and a uniform pressure must need
    /// no correction (p_tilde = p), to round-off.
    #[test]
    fn averages_are_the_weighted_node_means() {
        let mut b = BoxMesh::new([2, 2, 2], [1.0, 1.0, 1.0]);
        for p in &mut b.x {
            p[0] += 0.03 * (5.0 * p[1]).sin() * p[2];
        }
        let m = b.split_tets();
        let nn = m.x.len();
        let mut np = NodalPressure::new(&m.conn, |_| true, nn).unwrap();
        assert_eq!(np.len(), 48);
        let dt = 1e-3;
        let v = |n: u32| {
            let p = m.x[n as usize];
            [p[0] * p[0], p[1] * p[2], -p[2] + p[0] * p[1]]
        };
        np.average_volume_change(|n| m.x[n as usize], v, dt, &[]);
        // direct
        let mut num = vec![0.0; nn];
        let mut den = vec![0.0; nn];
        let mut own = Vec::new();
        for c in &m.conn {
            let ns = [c[0], c[1], c[2], c[4]];
            let (w, th) =
                tet4::volume_increment(&ns.map(|n| m.x[n as usize]), &ns.map(v), dt).unwrap();
            for n in ns {
                num[n as usize] += w * th;
                den[n as usize] += w;
            }
            own.push(th);
        }
        let mut differ = 0;
        for (e, c) in m.conn.iter().enumerate() {
            let ns = [c[0], c[1], c[2], c[4]];
            let want = 0.25
                * ns.iter()
                    .map(|&n| num[n as usize] / den[n as usize])
                    .sum::<f64>();
            let got = np.theta_bar(e).unwrap();
            assert!((got - want).abs() < 1e-14, "{e}: {got} vs {want}");
            differ += usize::from((got - own[e]).abs() > 1e-6 * own[e].abs());
        }
        assert!(
            differ > 0,
            "the field varies: the average differs from the own"
        );
        // a linear field: the average is each element's own
        let a = [[0.3, 0.1, 0.0], [0.2, -0.4, 0.1], [0.0, 0.3, 0.2]];
        let lin = |n: u32| mat_vec(&a, m.x[n as usize]);
        np.average_volume_change(|n| m.x[n as usize], lin, dt, &[]);
        for e in 0..m.conn.len() {
            let c = &m.conn[e];
            let ns = [c[0], c[1], c[2], c[4]];
            let (_, th) =
                tet4::volume_increment(&ns.map(|n| m.x[n as usize]), &ns.map(lin), dt).unwrap();
            assert!((np.theta_bar(e).unwrap() - th).abs() < 1e-15);
        }
        // a uniform pressure needs no correction
        let stress = vec![[-2e8, -2e8, -2e8, 1e7, 0.0, 3e6]; m.conn.len()];
        let mut worst = 0.0f64;
        np.correct_forces(
            |n| m.x[n as usize],
            &stress,
            |_, f| {
                worst = worst.max(f.iter().fold(0.0, |w, x| w.max(x.abs())));
            },
        );
        assert!(
            worst < 1e-6,
            "correction {worst} N under a uniform pressure"
        );
    }
}
