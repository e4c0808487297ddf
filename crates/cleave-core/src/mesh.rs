//! Structured mesh generators for tests, benchmarks and examples.

use crate::math::Vec3;

/// A structured block of nx x ny x nz hexahedra spanning [0,lx] x [0,ly] x [0,lz].
/// Nodes are numbered x fastest, then y, then z; elements likewise.
pub struct BoxMesh {
    pub x: Vec<Vec3>,
    pub conn: Vec<[u32; 8]>,
}

impl BoxMesh {
    pub fn new(n: [usize; 3], l: [f64; 3]) -> Self {
        let [nx, ny, nz] = n;
        let mut x = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    x.push([
                        l[0] * i as f64 / nx as f64,
                        l[1] * j as f64 / ny as f64,
                        l[2] * k as f64 / nz as f64,
                    ]);
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
}

use crate::model::{Control, Material, Model, Part, Section};

/// A one-part model of a structured box (deck ids = index + 1), with the given material and
/// end time and every other setting at its default. Tests, benches and examples start here.
pub fn box_model(n: [usize; 3], l: [f64; 3], material: Material, end_time: f64) -> Model {
    let m = BoxMesh::new(n, l);
    let nn = m.x.len();
    let ne = m.conn.len();
    Model {
        title: format!("box {}x{}x{}", n[0], n[1], n[2]),
        node_ids: (1..=nn as i64).collect(),
        v0: vec![[0.0; 3]; nn],
        x0: m.x,
        elem_ids: (1..=ne as i64).collect(),
        elem_part: vec![0; ne],
        conn: m.conn,
        parts: vec![Part {
            id: 1,
            title: "box".into(),
            section: 0,
            material: 0,
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
