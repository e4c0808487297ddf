//! O-grid hexahedral sphere: a core cube of n^3 elements and six shell blocks of n x n x m
//! elements between the core's faces and the sphere, the kind of mesh of the paper's Figure 3
//! (2800 elements: n = 10, m = 3).
//!
//! Construction, for a sphere of radius R centred at the origin:
//! - the core is the structured n^3 grid of the cube [-a, a]^3 with half-size
//!   a = R n / (n + 2m), so that the core's element size 2a/n equals the shell layers' radial
//!   thickness (R - a)/m along the axes, 2R/(n + 2m): the elements are nearly uniform;
//! - the core is rounded towards a sphere: the grid point at normalised cube coordinates c
//!   (in [-1, 1]^3, t = |c|_inf) goes to a c (1 - g + g t/|c|_2), g = 0.7, a map homogeneous
//!   in c, so every cube shell t = const of the core becomes a scaled copy of the rounded
//!   boundary: the face centres stay where they are and the cube's corners come in (from
//!   a sqrt(3) to 1.22 a), which keeps the shell thick enough there (its thinnest elements
//!   would set the time step);
//! - the six shell blocks blend linearly, layer by layer, from the core's boundary to the
//!   sphere, whose nodes are placed by the equi-angular (gnomonic) map of the cube's faces,
//!   direction (tan(pi/4 c_x), tan(pi/4 c_y), tan(pi/4 c_z)), so that the surface elements
//!   have about the same size on the whole sphere.
//!
//! Nodes shared between blocks are merged exactly: every node is created once from its
//! integer lattice position (layer, i, j, k), so the sphere has exactly
//! (n+1)^3 + m (6 n^2 + 2) nodes and n^3 + 6 n^2 m elements.

use super::BoxMesh;
use crate::math::Vec3;

/// How far the core cube is rounded towards a sphere (0: a sharp cube, 1: a sphere of
/// radius a). A sharp core cannot be used: its corners, at a sqrt(3), lie outside the sphere
/// for n = 10, m = 3 and finer (a > R / sqrt(3)). Over the six meshes of the paper, 0.7 gives
/// the most uniform elements (edge lengths within a factor 2.35 over the whole mesh, element
/// aspect ratio below 2, scaled Jacobian above 0.66, V/A_max above 0.49 of the nominal size;
/// see the tests); 0.5 leaves the shell thin at the cube's corners (V/A_max down to 0.27 of
/// the nominal size), 0.8 flattens the core's corner elements (scaled Jacobian 0.5).
const ROUND: f64 = 0.7;

/// The six shell blocks: the cube axis normal to the face, the side (false: -, true: +), and
/// the two in-face axes (u, v) with u x v pointing out of the cube, so that elements built
/// as (u, v, outward) are right-handed like hex8's (xi, eta, zeta).
const FACES: [(usize, bool, usize, usize); 6] = [
    (0, true, 1, 2),
    (0, false, 2, 1),
    (1, true, 2, 0),
    (1, false, 0, 2),
    (2, true, 0, 1),
    (2, false, 1, 0),
];

/// The O-grid sphere of radius `radius` centred at the origin, `n` >= 1 core elements along an
/// edge and `m` >= 1 shell layers. Nodes: the core's (n+1)^3 first (x fastest, then y, then
/// z, as [`BoxMesh`]), then each shell layer's 6 n^2 + 2 nodes, from the inside out.
/// Elements: the core's n^3 (as [`BoxMesh`]), then the shell, layer by layer, face by face.
/// Corner order is LS-DYNA's (hex8), every element with positive corner Jacobians.
pub fn ogrid_sphere(radius: f64, n: usize, m: usize) -> BoxMesh {
    assert!(n >= 1 && m >= 1, "ogrid_sphere needs n >= 1 and m >= 1");
    let a = radius * n as f64 / (n + 2 * m) as f64;
    let n1 = n + 1;
    let lattice = |i: [usize; 3]| i[0] + n1 * (i[1] + n1 * i[2]);
    // normalised cube coordinate of a lattice index
    let unit = |i: usize| -1.0 + 2.0 * i as f64 / n as f64;
    let core_point = |i: [usize; 3]| -> Vec3 {
        let c = i.map(unit);
        let t = c.iter().fold(0.0f64, |t, v| t.max(v.abs()));
        let r2 = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        if r2 == 0.0 {
            return [0.0; 3];
        }
        let f = a * (1.0 - ROUND + ROUND * t / r2);
        c.map(|v| v * f)
    };
    let sphere_point = |i: [usize; 3]| -> Vec3 {
        let d = i.map(|k| (std::f64::consts::FRAC_PI_4 * unit(k)).tan());
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|v| radius * v / l)
    };

    let nodes_total = n1 * n1 * n1 + m * (6 * n * n + 2);
    let mut x = Vec::with_capacity(nodes_total);
    // node of each (layer, lattice point); layer 0 is the core
    let mut id = vec![u32::MAX; (m + 1) * n1 * n1 * n1];
    for k in 0..n1 {
        for j in 0..n1 {
            for i in 0..n1 {
                id[lattice([i, j, k])] = x.len() as u32;
                x.push(core_point([i, j, k]));
            }
        }
    }
    let on_boundary = |i: [usize; 3]| i.iter().any(|&v| v == 0 || v == n);
    for l in 1..=m {
        let s = l as f64 / m as f64;
        for k in 0..n1 {
            for j in 0..n1 {
                for i in 0..n1 {
                    let q = [i, j, k];
                    if !on_boundary(q) {
                        continue;
                    }
                    id[l * n1 * n1 * n1 + lattice(q)] = x.len() as u32;
                    let (p, r) = (core_point(q), sphere_point(q));
                    x.push(if l == m {
                        r
                    } else {
                        std::array::from_fn(|d| (1.0 - s) * p[d] + s * r[d])
                    });
                }
            }
        }
    }
    debug_assert_eq!(x.len(), nodes_total);

    let mut conn = Vec::with_capacity(n * n * n + 6 * n * n * m);
    conn.extend(BoxMesh::new([n, n, n], [1.0; 3]).conn);
    let node = |l: usize, q: [usize; 3]| id[l * n1 * n1 * n1 + lattice(q)];
    for l in 0..m {
        for &(axis, plus, u, v) in &FACES {
            let at = |p: usize, q: usize| {
                let mut c = [0; 3];
                c[axis] = if plus { n } else { 0 };
                c[u] = p;
                c[v] = q;
                c
            };
            for q in 0..n {
                for p in 0..n {
                    let quad = [at(p, q), at(p + 1, q), at(p + 1, q + 1), at(p, q + 1)];
                    let lo = quad.map(|c| node(l, c));
                    let hi = quad.map(|c| node(l + 1, c));
                    conn.push([lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]]);
                }
            }
        }
    }
    BoxMesh { x, conn }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::hex8::{corner_jacobians, volume};
    use crate::math::norm;
    use crate::mesh::quality;

    /// The paper's Table II meshes: (n, m) -> (elements, nodes).
    const SIZES: [((usize, usize), (usize, usize)); 6] = [
        ((4, 2), (256, 321)),
        ((5, 2), (425, 520)),
        ((6, 2), (648, 779)),
        ((10, 3), (2800, 3137)),
        ((15, 4), (8775, 9504)),
        ((20, 5), (20000, 21271)),
    ];

    #[test]
    fn counts_match_the_papers_table() {
        for ((n, m), (ne, nn)) in SIZES {
            let s = ogrid_sphere(0.005, n, m);
            assert_eq!(s.conn.len(), ne, "elements for n={n} m={m}");
            assert_eq!(s.x.len(), nn, "nodes for n={n} m={m}");
            // every node is used, none twice at the same place (merged exactly)
            let mut used = vec![false; nn];
            s.conn
                .iter()
                .flatten()
                .for_each(|&i| used[i as usize] = true);
            assert!(used.iter().all(|&u| u), "unused node for n={n} m={m}");
            let mut keys: Vec<[i64; 3]> =
                s.x.iter()
                    .map(|p| p.map(|v| (v * 1e12).round() as i64))
                    .collect();
            keys.sort_unstable();
            keys.dedup();
            assert_eq!(keys.len(), nn, "coincident nodes for n={n} m={m}");
        }
    }

    #[test]
    fn jacobians_positive_surface_on_sphere_and_volume() {
        let r = 0.005;
        for ((n, m), _) in SIZES {
            let s = ogrid_sphere(r, n, m);
            let mut v = 0.0;
            for c in &s.conn {
                let xe: [Vec3; 8] = c.map(|i| s.x[i as usize]);
                let j = corner_jacobians(&xe);
                assert!(j.iter().all(|&j| j > 0.0), "n={n} m={m}: {j:?}");
                v += volume(&xe);
            }
            // the outer layer's nodes lie on the sphere
            let first_outer = (n + 1).pow(3) + (m - 1) * (6 * n * n + 2);
            for p in &s.x[first_outer..] {
                assert!(
                    (norm(*p) - r).abs() < 1e-12,
                    "n={n} m={m}: |x| = {}",
                    norm(*p)
                );
            }
            for p in &s.x[..first_outer] {
                assert!(
                    norm(*p) < r * (1.0 - 1e-3),
                    "n={n} m={m}: inner node on the surface"
                );
            }
            // Volume: the surface is made of bilinear patches through points of the sphere,
            // so the mesh lies inside it. A patch whose corners span the angle theta dips
            // about R theta^2 / 8 below the sphere at its centre, and on average over the
            // patch 2/3 of that (the gap is close to a sum of two parabolas), so the deficit
            // is the sum over surface patches of (2/3) A_p g_p, g_p the gap at the centre (the
            // distance from the sphere of the mean of its corners). The mesh's volume must be
            // below the sphere's and agree with that estimate to 5% of the deficit (the
            // deficit is 6.5% of the sphere's volume for n = 4 and 0.27% for n = 20; the
            // estimate is off by 1.7% of it for n = 4, 0.1% for n = 20).
            let exact = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
            let mut deficit = 0.0;
            for c in &s.conn[s.conn.len() - 6 * n * n..] {
                let top: [Vec3; 4] = [c[4], c[5], c[6], c[7]].map(|i| s.x[i as usize]);
                let mid: Vec3 =
                    std::array::from_fn(|d| top.iter().map(|p| p[d]).sum::<f64>() / 4.0);
                let gap = r - norm(mid);
                let area = crate::element::hex8::quad_area(top[0], top[1], top[2], top[3]);
                deficit += 2.0 / 3.0 * area * gap;
            }
            assert!(
                v < exact,
                "n={n} m={m}: mesh volume {v} above the sphere's {exact}"
            );
            let rel = (exact - v - deficit).abs() / deficit;
            eprintln!(
                "sphere n={n} m={m}: volume deficit {:.4}% (estimate {:.4}%), off by {:.1}% of it",
                100.0 * (exact - v) / exact,
                100.0 * deficit / exact,
                100.0 * rel
            );
            assert!(
                rel < 0.05,
                "n={n} m={m}: deficit {} vs estimate {deficit}",
                exact - v
            );
        }
    }

    #[test]
    fn elements_are_near_uniform() {
        for ((n, m), _) in SIZES {
            let r = 1.0;
            let s = ogrid_sphere(r, n, m);
            let q = quality(&s);
            let h = 2.0 * r / (n + 2 * m) as f64;
            eprintln!(
                "sphere n={n} m={m}: edges {:.3}-{:.3} h (ratio {:.2}), worst element aspect {:.2}, \
                 min scaled Jacobian {:.3}, min V/A_max {:.3} h",
                q.min_edge / h,
                q.max_edge / h,
                q.max_edge / q.min_edge,
                q.max_aspect,
                q.min_scaled_jacobian,
                q.min_char_length / h
            );
            assert!(q.max_edge / q.min_edge < 2.5, "n={n} m={m}: {q:?}");
            assert!(q.max_aspect < 2.1, "n={n} m={m}: {q:?}");
            assert!(q.min_scaled_jacobian > 0.6, "n={n} m={m}: {q:?}");
            assert!(q.min_char_length > 0.45 * h, "n={n} m={m}: {q:?}");
        }
    }
}
