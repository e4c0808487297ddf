//! Structured mesh generators for tests, benchmarks and examples: boxes ([`BoxMesh`]),
//! O-grid discs extruded into cylinders ([`ogrid_disc`], [`extrude`]), O-grid spheres
//! ([`ogrid_sphere`]), tetrahedra and wedges cut from any of them ([`BoxMesh::split_tets`],
//! [`BoxMesh::split_wedges`]), models built from them ([`single_part_model`], [`box_model`],
//! [`Assembly`] for several parts), and shape measures ([`quality`](fn@quality)).

mod assembly;
mod quality;
mod simplex;
mod sphere;

pub use assembly::Assembly;
pub use quality::{quality, MeshQuality};
pub use sphere::ogrid_sphere;

use crate::math::Vec3;

/// A structured block of nx x ny x nz hexahedra spanning `[0,lx] x [0,ly] x [0,lz]`.
/// Nodes are numbered x fastest, then y, then z; elements likewise. The other generators
/// return the same type: points and LS-DYNA-ordered hexahedra.
#[derive(Clone, Debug, Default)]
pub struct BoxMesh {
    pub x: Vec<Vec3>,
    pub conn: Vec<[u32; 8]>,
}

impl BoxMesh {
    pub fn new(n: [usize; 3], l: [f64; 3]) -> Self {
        let along =
            |k: usize| -> Vec<f64> { (0..=n[k]).map(|i| l[k] * i as f64 / n[k] as f64).collect() };
        Self::from_coords(&along(0), &along(1), &along(2))
    }

    /// The structured block whose node planes are at the given coordinates (each list
    /// strictly increasing, at least two values), numbered as [`BoxMesh::new`].
    pub fn from_coords(xs: &[f64], ys: &[f64], zs: &[f64]) -> Self {
        let (nx, ny, nz) = (xs.len() - 1, ys.len() - 1, zs.len() - 1);
        let mut x = Vec::with_capacity(xs.len() * ys.len() * zs.len());
        for &z in zs {
            for &y in ys {
                for &xv in xs {
                    x.push([xv, y, z]);
                }
            }
        }
        let id = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
        let mut conn = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    conn.push([
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ]);
                }
            }
        }
        Self { x, conn }
    }

    /// Moves every node by `d`.
    pub fn translate(&mut self, d: Vec3) {
        for p in &mut self.x {
            *p = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
        }
    }
}

use crate::model::{Control, Material, Model, Part, Section};

/// A one-part model of a structured box (deck ids = index + 1), with the given material and
/// end time and every other setting at its default. Tests, benches and examples start here.
pub fn box_model(n: [usize; 3], l: [f64; 3], material: Material, end_time: f64) -> Model {
    let mut m = single_part_model(BoxMesh::new(n, l), material, end_time);
    m.title = format!("box {}x{}x{}", n[0], n[1], n[2]);
    m
}

/// A one-part model of any mesh (deck ids = index + 1), at rest, every other
/// setting at its default.
pub fn single_part_model(mesh: BoxMesh, material: Material, end_time: f64) -> Model {
    let nn = mesh.x.len();
    let ne = mesh.conn.len();
    Model {
        node_ids: (1..=nn as i64).collect(),
        v0: vec![[0.0; 3]; nn].into(),
        x0: mesh.x.into(),
        elem_ids: (1..=ne as i64).collect(),
        elem_part: vec![0; ne],
        conn: mesh.conn,
        parts: vec![Part {
            id: 1,
            title: "part 1".into(),
            section: 0,
            material: 0,
            hourglass: None,
        }],
        sections: vec![Section { id: 1, elform: 1 }],
        materials: vec![material],
        control: Control {
            end_time,
            ..Control::default()
        },
        ..Model::default()
    }
}

impl Model {
    /// Indices of the nodes whose coordinate `axis` is within `tol` of `value`.
    pub fn nodes_where(&self, axis: usize, value: f64, tol: f64) -> Vec<u32> {
        (0..self.x0.len() as u32)
            .filter(|&i| (self.x0[i as usize][axis] - value).abs() <= tol)
            .collect()
    }
}

/// An O-grid disc of radius `r` in the xy-plane: a core square of n x n quads (half-side
/// a = r n / (n + 2m), so that core and ring elements have about the same size) and m rings of
/// 4n quads each, blending from the square's boundary to the circle. Quads are counterclockwise
/// seen from +z. Returns (points, quads); (n+1)^2 + 4 n m points, n^2 + 4 n m quads.
pub fn ogrid_disc(r: f64, n: usize, m: usize) -> (Vec<[f64; 2]>, Vec<[u32; 4]>) {
    let a = r * n as f64 / (n + 2 * m) as f64;
    let mut pts = Vec::new();
    let core = |i: usize, j: usize| (i + (n + 1) * j) as u32;
    for j in 0..=n {
        for i in 0..=n {
            pts.push([
                -a + 2.0 * a * i as f64 / n as f64,
                -a + 2.0 * a * j as f64 / n as f64,
            ]);
        }
    }
    let mut quads = Vec::new();
    for j in 0..n {
        for i in 0..n {
            quads.push([
                core(i, j),
                core(i + 1, j),
                core(i + 1, j + 1),
                core(i, j + 1),
            ]);
        }
    }
    // the core's boundary, counterclockwise from (-a, -a)
    let mut ring: Vec<u32> = Vec::with_capacity(4 * n);
    ring.extend((0..n).map(|i| core(i, 0)));
    ring.extend((0..n).map(|j| core(n, j)));
    ring.extend((0..n).map(|i| core(n - i, n)));
    ring.extend((0..n).map(|j| core(0, n - j)));
    let mut inner = ring.clone();
    for l in 1..=m {
        let s = l as f64 / m as f64;
        let outer: Vec<u32> = ring
            .iter()
            .map(|&k| {
                let p = pts[k as usize];
                let d = (p[0] * p[0] + p[1] * p[1]).sqrt();
                let q = [r * p[0] / d, r * p[1] / d];
                pts.push([(1.0 - s) * p[0] + s * q[0], (1.0 - s) * p[1] + s * q[1]]);
                (pts.len() - 1) as u32
            })
            .collect();
        let len = ring.len();
        for k in 0..len {
            let k1 = (k + 1) % len;
            quads.push([inner[k], outer[k], outer[k1], inner[k1]]);
        }
        inner = outer;
    }
    (pts, quads)
}

/// Extrude a planar quad mesh along z from 0 to `length` in `nz` layers into hexahedra
/// (LS-DYNA order: the quad at the lower z, then the same quad above).
pub fn extrude(pts: &[[f64; 2]], quads: &[[u32; 4]], length: f64, nz: usize) -> BoxMesh {
    let np = pts.len() as u32;
    let mut x = Vec::with_capacity(pts.len() * (nz + 1));
    for k in 0..=nz {
        let z = length * k as f64 / nz as f64;
        x.extend(pts.iter().map(|p| [p[0], p[1], z]));
    }
    let mut conn = Vec::with_capacity(quads.len() * nz);
    for k in 0..nz as u32 {
        for q in quads {
            let lo = q.map(|n| n + k * np);
            let hi = q.map(|n| n + (k + 1) * np);
            conn.push([lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]]);
        }
    }
    BoxMesh { x, conn }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::hex8::{corner_jacobians, volume};

    #[test]
    fn ogrid_cylinder_counts_volume_and_jacobians() {
        let (pts, quads) = ogrid_disc(1.0, 6, 3);
        assert_eq!(pts.len(), 49 + 72);
        assert_eq!(quads.len(), 36 + 72);
        let m = extrude(&pts, &quads, 2.0, 4);
        let mut v = 0.0;
        for c in &m.conn {
            let xe: [Vec3; 8] = std::array::from_fn(|a| m.x[c[a] as usize]);
            assert!(corner_jacobians(&xe).iter().all(|&j| j > 0.0));
            v += volume(&xe);
        }
        // polygonal approximation of pi r^2 L with 4 n = 24 sides: within 2%
        let exact = std::f64::consts::PI * 2.0;
        assert!((v - exact).abs() / exact < 0.02, "{v} vs {exact}");
    }
}
