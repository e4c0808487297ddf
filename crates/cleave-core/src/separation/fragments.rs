//! Fragments: connected components of elements through shared nodes and through the shared
//! faces that still hold (bonds, intact and softening interfaces); a model without separation
//! has the components of its mesh. Labels are numbered in order of first element, so they do
//! not depend on the order of unions.

use crate::math::{add, scale, Vec3};
use crate::node_values::NodeValues;
use crate::topology::UnionFind;

/// A fragment label per element and the number of fragments.
#[derive(Clone, Debug, PartialEq)]
pub struct Fragments {
    pub label: Vec<u32>,
    pub count: usize,
}

/// Mass, centroid and velocity (mass-weighted over its nodes) of one fragment.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FragmentSummary {
    pub elements: usize,
    pub mass: f64,
    pub centroid: Vec3,
    pub velocity: Vec3,
}

/// Components of the elements of `conn` joined through shared nodes and through the node pairs
/// `ties` (a node of one element and its coincident copy in another).
pub fn components(
    conn: &[[u32; 8]],
    num_nodes: usize,
    ties: impl Iterator<Item = (u32, u32)>,
) -> Fragments {
    let mut uf = UnionFind::new(num_nodes);
    for c in conn {
        for &n in &c[1..] {
            uf.union(c[0], n);
        }
    }
    for (a, b) in ties {
        uf.union(a, b);
    }
    let mut root_label = vec![u32::MAX; num_nodes];
    let mut count = 0u32;
    let label = conn
        .iter()
        .map(|c| {
            let r = uf.find(c[0]) as usize;
            if root_label[r] == u32::MAX {
                root_label[r] = count;
                count += 1;
            }
            root_label[r]
        })
        .collect();
    Fragments {
        label,
        count: count as usize,
    }
}

impl Fragments {
    /// Mass, centroid and velocity of each fragment from the nodal masses, positions and
    /// velocities, by decreasing mass. Every node belongs to the fragment of the elements that
    /// use it (they are all in one).
    pub fn summaries(
        &self,
        conn: &[[u32; 8]],
        mass: &[f64],
        x: NodeValues<Vec3>,
        v: NodeValues<Vec3>,
    ) -> Vec<FragmentSummary> {
        let mut rows = vec![FragmentSummary::default(); self.count];
        let mut node_frag = vec![u32::MAX; mass.len()];
        for (e, c) in conn.iter().enumerate() {
            rows[self.label[e] as usize].elements += 1;
            for &n in c {
                node_frag[n as usize] = self.label[e];
            }
        }
        for (i, &f) in node_frag.iter().enumerate() {
            if f == u32::MAX {
                continue;
            }
            let r = &mut rows[f as usize];
            r.mass += mass[i];
            r.centroid = add(r.centroid, scale(x[i], mass[i]));
            r.velocity = add(r.velocity, scale(v[i], mass[i]));
        }
        for r in &mut rows {
            if r.mass > 0.0 {
                r.centroid = scale(r.centroid, 1.0 / r.mass);
                r.velocity = scale(r.velocity, 1.0 / r.mass);
            }
        }
        rows.sort_by(|a, b| b.mass.total_cmp(&a.mass));
        rows
    }
}
