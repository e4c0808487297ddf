//! Mesh topology helpers: connected components of elements through shared nodes.

use crate::model::Model;

/// Union-find with path halving; the root of a set is its smallest member, so results do not
/// depend on the order of unions.
pub struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    pub fn new(n: usize) -> Self {
        Self {
            parent: (0..n as u32).collect(),
        }
    }
    pub fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let p = self.parent[i as usize];
            self.parent[i as usize] = self.parent[p as usize];
            i = p;
        }
        i
    }
    pub fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra < rb {
            self.parent[rb as usize] = ra;
        } else if rb < ra {
            self.parent[ra as usize] = rb;
        }
    }
}

/// Component label of each element (0-based, numbered by smallest element) and the count.
pub fn element_components(model: &Model) -> (Vec<u32>, usize) {
    let f = crate::separation::fragments::components(
        &model.conn,
        model.num_nodes(),
        std::iter::empty(),
    );
    (f.label, f.count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_model;
    use crate::model::{Material, MaterialKind};

    #[test]
    fn two_separate_boxes_are_two_components() {
        let mat = Material {
            id: 1,
            density: 1.0,
            young: 1.0,
            poisson: 0.0,
            kind: MaterialKind::Elastic,
        };
        let mut m = box_model([2, 1, 1], [2.0, 1.0, 1.0], mat, 1.0);
        // detach element 1 by giving it its own copies of the shared nodes
        let nn = m.x0.len() as u32;
        let shared: Vec<u32> = m.conn[1]
            .iter()
            .copied()
            .filter(|n| m.conn[0].contains(n))
            .collect();
        for (k, &n) in shared.iter().enumerate() {
            m.x0.push(m.x0[n as usize]);
            for c in m.conn[1].iter_mut() {
                if *c == n {
                    *c = nn + k as u32;
                }
            }
        }
        assert_eq!(element_components(&m), (vec![0, 1], 2));
    }
}
