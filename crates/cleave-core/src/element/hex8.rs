//! Geometry of the trilinear 8-node hexahedron, LS-DYNA node order.
//!
//! Natural coordinates of the corners (xi, eta, zeta):
//! 1 (-,-,-) 2 (+,-,-) 3 (+,+,-) 4 (-,+,-) 5 (-,-,+) 6 (+,-,+) 7 (+,+,+) 8 (-,+,+).
//! A well-formed element has a positive Jacobian determinant at every corner.

use crate::math::{cross, dot, inverse, sub, Mat3, Vec3};

/// Natural coordinates of the 8 corners.
pub const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The 4 hourglass base vectors (Flanagan and Belytschko 1981): the bilinear and trilinear
/// products eta*zeta, zeta*xi, xi*eta, xi*eta*zeta at the corners.
pub const GAMMA: [[f64; 8]; 4] = [
    [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0],
    [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0],
];

/// The 6 faces as corner indices (0-based), each ordered so that its normal by the right-hand
/// rule points out of the element (LS-DYNA face order: bottom, top, and the four sides).
pub const FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// Jacobian dx/dxi at natural point `p`: `J[i][j] = sum_a x_a[i] dN_a/dxi_j`.
pub fn jacobian_at(x: &[Vec3; 8], p: [f64; 3]) -> Mat3 {
    let mut j = [[0.0; 3]; 3];
    for (a, xa) in x.iter().enumerate() {
        let s = CORNERS[a];
        let dn = [
            0.125 * s[0] * (1.0 + s[1] * p[1]) * (1.0 + s[2] * p[2]),
            0.125 * s[1] * (1.0 + s[0] * p[0]) * (1.0 + s[2] * p[2]),
            0.125 * s[2] * (1.0 + s[0] * p[0]) * (1.0 + s[1] * p[1]),
        ];
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += xa[i] * dn[k];
            }
        }
    }
    j
}

/// Jacobian determinant at each corner, in corner order. All must be positive.
pub fn corner_jacobians(x: &[Vec3; 8]) -> [f64; 8] {
    let mut out = [0.0; 8];
    for (a, o) in out.iter_mut().enumerate() {
        *o = crate::math::det(&jacobian_at(x, CORNERS[a]));
    }
    out
}

/// Exact volume of the trilinear hexahedron (2x2x2 Gauss integration of det J, exact because
/// det J is a polynomial of degree 2 in each natural coordinate).
pub fn volume(x: &[Vec3; 8]) -> f64 {
    let g = 1.0 / 3f64.sqrt();
    let mut v = 0.0;
    for s in CORNERS {
        v += crate::math::det(&jacobian_at(x, [s[0] * g, s[1] * g, s[2] * g]));
    }
    v
}

/// Centre-point geometry: volume 8 det J(0) and the shape-function gradients b_a = dN_a/dx.
/// Returns `None` if det J(0) is not positive.
#[inline]
pub fn centre_gradients(x: &[Vec3; 8]) -> Option<(f64, [Vec3; 8])> {
    let j = centre_jacobian(x);
    let (det, jinv) = det_inverse(&j)?;
    Some((8.0 * det, gradients_from_inverse(&jinv)))
}

/// `J(0)[i][k] = 1/8 sum_a x_a[i] s_a[k]`, with s_a the corner's natural coordinates.
#[inline]
pub fn centre_jacobian(x: &[Vec3; 8]) -> Mat3 {
    let mut j = [[0.0; 3]; 3];
    for i in 0..3 {
        let x_ = |a: usize| x[a][i];
        // sums of corner values with the signs of xi, eta, zeta
        j[i][0] = 0.125 * (-x_(0) + x_(1) + x_(2) - x_(3) - x_(4) + x_(5) + x_(6) - x_(7));
        j[i][1] = 0.125 * (-x_(0) - x_(1) + x_(2) + x_(3) - x_(4) - x_(5) + x_(6) + x_(7));
        j[i][2] = 0.125 * (-x_(0) - x_(1) - x_(2) - x_(3) + x_(4) + x_(5) + x_(6) + x_(7));
    }
    j
}

/// Determinant and inverse of J; `None` if the determinant is not positive and finite.
#[inline]
pub fn det_inverse(j: &Mat3) -> Option<(f64, Mat3)> {
    let d = crate::math::det(j);
    if d.is_nan() || d <= 0.0 || !d.is_finite() {
        return None;
    }
    inverse(j).map(|inv| (d, inv))
}

/// `b_a[i] = dN_a/dx_i = sum_k s_a[k]/8 Jinv[k][i]`.
#[inline]
pub fn gradients_from_inverse(jinv: &Mat3) -> [Vec3; 8] {
    let mut b = [[0.0; 3]; 8];
    for (a, ba) in b.iter_mut().enumerate() {
        let s = CORNERS[a];
        for i in 0..3 {
            ba[i] = 0.125 * (s[0] * jinv[0][i] + s[1] * jinv[1][i] + s[2] * jinv[2][i]);
        }
    }
    b
}

/// Cross product of a quadrilateral's diagonals, `(p2 - p0) x (p3 - p1)`: twice its
/// area-weighted normal.
#[inline]
pub fn diagonal_cross(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3) -> Vec3 {
    cross(sub(p2, p0), sub(p3, p1))
}

/// Area of a quadrilateral face: half the norm of the cross product of its diagonals.
#[inline]
pub fn quad_area(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3) -> f64 {
    0.5 * crate::math::norm(diagonal_cross(p0, p1, p2, p3))
}

/// Area-weighted unit normal and area of a quadrilateral (diagonal cross product).
#[inline]
pub fn quad_normal_area(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3) -> (Vec3, f64) {
    let c = diagonal_cross(p0, p1, p2, p3);
    let n2 = dot(c, c).sqrt();
    if n2 == 0.0 {
        return ([0.0; 3], 0.0);
    }
    ([c[0] / n2, c[1] / n2, c[2] / n2], 0.5 * n2)
}

/// Largest face area of the element, `max_f |d1 x d2| / 2` over its faces (diagonals d1,
/// d2, as [`quad_area`]).
///
/// One square root, of the largest `|d1 x d2|^2`: the square root is correctly rounded and
/// monotone, so this is bit for bit the largest [`quad_area`].
#[inline]
pub fn max_face_area(x: &[Vec3; 8]) -> f64 {
    let mut c2max: f64 = 0.0;
    for f in FACES {
        let c = diagonal_cross(x[f[0]], x[f[1]], x[f[2]], x[f[3]]);
        c2max = c2max.max(dot(c, c));
    }
    0.5 * c2max.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn unit_cube(l: f64) -> [Vec3; 8] {
        let mut x = [[0.0; 3]; 8];
        for (a, xa) in x.iter_mut().enumerate() {
            for i in 0..3 {
                xa[i] = 0.5 * l * (1.0 + CORNERS[a][i]);
            }
        }
        x
    }

    #[test]
    fn cube_volume_and_gradients() {
        let x = unit_cube(2.0);
        assert!((volume(&x) - 8.0).abs() < 1e-14);
        let (v, b) = centre_gradients(&x).unwrap();
        assert!((v - 8.0).abs() < 1e-14);
        // b_a = s_a / (4 L)
        for a in 0..8 {
            for i in 0..3 {
                assert!((b[a][i] - CORNERS[a][i] / 8.0).abs() < 1e-15);
            }
        }
        assert!(corner_jacobians(&x)
            .iter()
            .all(|&j| (j - 1.0).abs() < 1e-14));
    }

    #[test]
    #[allow(clippy::needless_range_loop)] // i, k index a tensor, not one slice
    fn gradients_reproduce_linear_fields_on_a_distorted_element() {
        let mut x = unit_cube(1.0);
        x[6] = [1.3, 1.1, 1.2];
        x[1][2] -= 0.1;
        let (_, b) = centre_gradients(&x).unwrap();
        // sum_a x_a (x) b_a = I and sum_a b_a = 0
        for i in 0..3 {
            for k in 0..3 {
                let s: f64 = (0..8).map(|a| x[a][i] * b[a][k]).sum();
                assert!((s - if i == k { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
            assert!((0..8).map(|a| b[a][i]).sum::<f64>().abs() < 1e-14);
        }
    }

    #[test]
    fn inverted_element_has_negative_corner_jacobian() {
        let mut x = unit_cube(1.0);
        x.swap(0, 1);
        assert!(corner_jacobians(&x).iter().any(|&j| j <= 0.0));
    }

    #[test]
    fn faces_point_outwards() {
        let x = unit_cube(1.0);
        let c = [0.5, 0.5, 0.5];
        for f in FACES {
            let (n, a) = quad_normal_area(x[f[0]], x[f[1]], x[f[2]], x[f[3]]);
            assert!((a - 1.0).abs() < 1e-14);
            let fc = sub(x[f[0]], c);
            assert!(dot(n, fc) > 0.0);
        }
    }

    #[test]
    fn max_face_area_is_the_largest_quad_area_bit_for_bit() {
        // a brick with unequal sides (each face pair its own area) and distorted copies of it
        let mut x = unit_cube(1.0);
        for (a, xa) in x.iter_mut().enumerate() {
            xa[0] *= 3.0;
            xa[1] *= 2.0;
            xa[2] += 0.01 * a as f64;
        }
        assert!((max_face_area(&x) - 6.0).abs() < 0.1);
        let mut seed = 12345u64;
        let mut r = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..1000 {
            let y: [Vec3; 8] =
                std::array::from_fn(|a| std::array::from_fn(|i| x[a][i] + 0.3 * r()));
            let each = FACES.map(|f| quad_area(y[f[0]], y[f[1]], y[f[2]], y[f[3]]));
            let largest = each.iter().fold(0.0f64, |m, &a| m.max(a));
            assert_eq!(max_face_area(&y).to_bits(), largest.to_bits());
        }
    }
}
