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

/// The hexahedra and wedges that share no face with another element of the deck's mesh (for a
/// split model, faces are compared on the deck nodes, `x0.origin()`): a lone one-point
/// hexahedron's uniform dilatation is unstable at the usual step h / c_L, so these take the
/// free-element step ([`crate::material::free_element_speed`]) from the start.
pub fn lone_elements(model: &Model) -> Vec<bool> {
    use crate::element::hex8::FACES;
    use crate::element::shape::{face_key, shape_of};
    use crate::element::Shape;
    let origin = model.x0.origin();
    let deck = |n: u32| origin.map_or(n, |o| o[n as usize]);
    let mut keys: Vec<([u32; 4], u32)> = Vec::with_capacity(6 * model.num_elements());
    for (e, c) in model.conn.iter().enumerate() {
        for f in FACES {
            if let Some(k) = face_key(f.map(|a| deck(c[a]))) {
                keys.push((k, e as u32));
            }
        }
    }
    keys.sort_unstable();
    let mut shares = vec![false; model.num_elements()];
    for w in keys.windows(2) {
        if w[0].0 == w[1].0 && w[0].1 != w[1].1 {
            shares[w[0].1 as usize] = true;
            shares[w[1].1 as usize] = true;
        }
    }
    (model.conn.iter().zip(&shares))
        .map(|(c, &s)| !s && matches!(shape_of(c), Some(Shape::Hex | Shape::Wedge)))
        .collect()
}

/// For each element face ([`crate::element::hex8::FACES`] order), the (element, local face)
/// on the other side, or `(u32::MAX, 0)` where the face is on the surface or collapsed.
/// Faces are compared on the model's own nodes (a split model's copies make every face a
/// surface).
pub fn face_neighbours(model: &Model) -> Vec<[(u32, u8); 6]> {
    use crate::element::hex8::FACES;
    use crate::element::shape::face_key;
    let mut keys: Vec<([u32; 4], u32, u8)> = Vec::with_capacity(6 * model.num_elements());
    for (e, c) in model.conn.iter().enumerate() {
        for (f, corners) in FACES.iter().enumerate() {
            if let Some(k) = face_key(corners.map(|a| c[a])) {
                keys.push((k, e as u32, f as u8));
            }
        }
    }
    keys.sort_unstable();
    let mut out = vec![[(u32::MAX, 0u8); 6]; model.num_elements()];
    for w in keys.windows(2) {
        let ((ka, ea, fa), (kb, eb, fb)) = (w[0], w[1]);
        if ka == kb && ea != eb {
            out[ea as usize][fa as usize] = (eb, fb);
            out[eb as usize][fb as usize] = (ea, fa);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_model;
    use crate::model::{Material, MaterialKind};

    fn unit_material() -> Material {
        Material {
            id: 1,
            density: 1.0,
            young: 1.0,
            poisson: 0.0,
            kind: MaterialKind::Elastic,
        }
    }

    #[test]
    fn face_neighbours_pair_the_shared_faces() {
        let m = box_model([3, 1, 1], [3.0, 1.0, 1.0], unit_material(), 1.0);
        let n = face_neighbours(&m);
        // each interior x-face pairs face 3 (+x) of one element with face 5 (-x) of the next
        let x_of = |e: usize, f: usize| {
            let c = m.conn[e];
            crate::element::hex8::FACES[f]
                .iter()
                .map(|&a| m.x0[c[a] as usize][0])
                .sum::<f64>()
                / 4.0
        };
        let mut pairs = 0;
        for (e, faces) in n.iter().enumerate() {
            for (f, &(e2, f2)) in faces.iter().enumerate() {
                if e2 == u32::MAX {
                    continue;
                }
                pairs += 1;
                assert_eq!(n[e2 as usize][f2 as usize], (e as u32, f as u8));
                assert_eq!(x_of(e, f), x_of(e2 as usize, f2 as usize));
            }
        }
        assert_eq!(pairs, 4, "{n:?}");
    }

    #[test]
    fn two_separate_boxes_are_two_components() {
        let mut m = box_model([2, 1, 1], [2.0, 1.0, 1.0], unit_material(), 1.0);
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
