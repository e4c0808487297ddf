//! Building a model of several parts from generated meshes.

use std::ops::Range;

use super::BoxMesh;
use crate::model::{Control, Material, Model, Part, Section};

/// A model under construction: materials, parts and meshes are appended in order, and every
/// deck id is its index + 1 (nodes, elements, parts, materials). One solid section (id 1,
/// ELFORM 1) serves every part; everything else is at its default, at rest.
pub struct Assembly {
    pub model: Model,
}

impl Assembly {
    pub fn new(title: &str, end_time: f64) -> Self {
        Self {
            model: Model {
                title: title.into(),
                sections: vec![Section { id: 1, elform: 1 }],
                control: Control {
                    end_time,
                    ..Control::default()
                },
                ..Model::default()
            },
        }
    }

    /// Adds a material (its id becomes its index + 1); returns its index.
    pub fn material(&mut self, mut material: Material) -> usize {
        let m = &mut self.model.materials;
        material.id = m.len() as i64 + 1;
        m.push(material);
        m.len() - 1
    }

    /// Adds a part of material index `material`; returns its index.
    pub fn part(&mut self, title: &str, material: usize) -> usize {
        let p = &mut self.model.parts;
        p.push(Part {
            id: p.len() as i64 + 1,
            title: title.into(),
            section: 0,
            material,
            hourglass: None,
        });
        p.len() - 1
    }

    /// Appends a mesh (its own nodes, shared with nothing added before), each element to the
    /// part `part_of(local element index)`. Returns the new nodes' and elements' index ranges.
    pub fn mesh(
        &mut self,
        mesh: BoxMesh,
        mut part_of: impl FnMut(usize) -> usize,
    ) -> (Range<u32>, Range<u32>) {
        let m = &mut self.model;
        let n0 = m.x0.len() as u32;
        let e0 = m.conn.len() as u32;
        let nn = mesh.x.len() as u32;
        m.x0.extend(mesh.x);
        m.v0.resize(m.x0.len(), [0.0; 3]);
        m.node_ids.extend((n0 as i64 + 1)..=(n0 + nn) as i64);
        for (k, c) in mesh.conn.into_iter().enumerate() {
            m.conn.push(c.map(|i| i + n0));
            m.elem_part.push(part_of(k) as u32);
        }
        let e1 = m.conn.len() as u32;
        m.elem_ids.extend((e0 as i64 + 1)..=e1 as i64);
        (n0..n0 + nn, e0..e1)
    }

    pub fn finish(self) -> Model {
        self.model
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::MaterialKind;

    #[test]
    fn parts_and_ids() {
        let steel = Material {
            id: 0,
            density: 7850.0,
            young: 200e9,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        };
        let mut a = Assembly::new("two blocks", 1e-3);
        let m = a.material(steel);
        let (p, q) = (a.part("a", m), a.part("b", m));
        let (n1, e1) = a.mesh(BoxMesh::new([1, 1, 1], [1.0; 3]), |_| p);
        let (n2, e2) = a.mesh(BoxMesh::new([2, 1, 1], [1.0; 3]), |k| {
            if k == 0 {
                p
            } else {
                q
            }
        });
        let model = a.finish();
        assert_eq!((n1, e1, n2.clone(), e2), (0..8, 0..1, 8..20, 1..3));
        assert_eq!(model.materials[0].id, 1);
        assert_eq!(model.node_ids, (1..=20).collect::<Vec<_>>());
        assert_eq!(model.elem_ids, vec![1, 2, 3]);
        assert_eq!(model.elem_part, vec![0, 0, 1]);
        assert_eq!(model.conn[1][0], 8);
        assert_eq!(model.v0.len(), 20);
    }
}
