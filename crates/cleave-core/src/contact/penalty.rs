//! Node-to-face penalty: the closest point of a bilinear quadrilateral face to a node, the
//! penetration, and the normal penalty force with its reaction on the face's nodes.
//!
//! The face is the bilinear surface of its 4 nodes x_a (outward order),
//! `x(xi, eta) = sum_a N_a(xi, eta) x_a`, `N_a = (1 + xi_a xi)(1 + eta_a eta) / 4` with corners
//! (xi_a, eta_a) = (-1,-1), (1,-1), (1,1), (-1,1); its outward normal is
//! `n = x_xi x x_eta / |x_xi x x_eta|`.
//!
//! Projection: Newton's method on the closest-point conditions `(x(xi,eta) - s) . x_xi = 0`,
//! `(x(xi,eta) - s) . x_eta = 0` from the face centre (exact in one iteration on a flat
//! parallelogram; the bilinear map has `x_xi xi = x_eta eta = 0`, so the full Hessian is cheap).
//! When Newton does not converge (a badly warped face), the face is split into 4 triangles
//! about its centroid and the node is projected onto the plane of the triangle that contains
//! the projection; the triangle's barycentric weights are turned into corner weights (the
//! centroid's weight shared equally by the 4 corners). Either way the contact point is
//! `x_c = sum_a w_a x_a` with `sum_a w_a = 1`.
//!
//! Penalty (LS-DYNA theory manual, penalty method): the gap is `g = (s - x_c) . n`; a node
//! penetrates when `g < 0`. The node gets `f_s = -k g n` and the face nodes `f_a = -w_a f_s`,
//! so the forces sum to zero, and since `s - x_c` is along `n` at the closest point, so do
//! their moments.

use crate::math::{add, cross, dot, norm, scale, sub, Vec3};

/// How far outside the face, in natural coordinates (or barycentric weight for the triangle
/// fallback), a projection still counts as on the face: 2% of the half-width, so a node right
/// above an edge of a flat surface is caught by both faces rather than by neither.
pub const INSIDE_TOL: f64 = 0.02;

/// Newton iterations before falling back to the triangles.
const MAX_ITER: usize = 12;

/// Newton stops when the step in natural coordinates falls below this; the iteration converges
/// quadratically, so the point it stops at is exact to round-off.
const NEWTON_TOL: f64 = 1e-11;

/// Bound on the sum of |weights| of a point of the face extended by [`INSIDE_TOL`]:
/// (1 + INSIDE_TOL)^2 for the bilinear map, 1 + 4 INSIDE_TOL for the triangles.
pub const WEIGHT_SUM: f64 = 1.0 + 4.0 * INSIDE_TOL;

/// Where a node projects on a face.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Weights of the face's 4 nodes at the contact point (bilinear shape functions, or the
    /// triangle fallback's), summing to 1.
    pub w: [f64; 4],
    /// The contact point x_c = sum w_a x_a.
    pub point: Vec3,
    /// Unit outward normal of the face at the contact point.
    pub normal: Vec3,
    /// Signed gap g = (s - x_c) . n; negative when the node penetrates.
    pub gap: f64,
}

/// Bilinear shape functions of a face at (xi, eta).
#[inline]
pub fn shape_functions(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

/// Project node `s` onto the face with corners `p`; `None` when the projection falls outside
/// the face (beyond [`INSIDE_TOL`]) or the face is degenerate.
pub fn project(p: &[Vec3; 4], s: Vec3) -> Option<Projection> {
    match newton(p, s) {
        Newton::Converged(xi, eta) => {
            let lim = 1.0 + INSIDE_TOL;
            if xi.abs() > lim || eta.abs() > lim {
                return None;
            }
            let [a0, a1, a2, a3] = coefficients(p);
            let x_xi = add(a1, scale(a3, eta));
            let x_eta = add(a2, scale(a3, xi));
            let c = cross(x_xi, x_eta);
            let len = norm(c);
            if len.is_nan() || len <= 0.0 {
                return None;
            }
            let n = scale(c, 1.0 / len);
            let w = shape_functions(xi, eta);
            let point = add(
                add(a0, scale(a1, xi)),
                add(scale(a2, eta), scale(a3, xi * eta)),
            );
            Some(Projection {
                w,
                point,
                normal: n,
                gap: dot(sub(s, point), n),
            })
        }
        Newton::Outside => None,
        Newton::Failed => project_triangles(p, s),
    }
}

#[derive(serde::Serialize, serde::Deserialize)]
enum Newton {
    Converged(f64, f64),
    /// The iterate left the face far behind: no contact.
    Outside,
    Failed,
}

/// x(xi, eta) = a0 + a1 xi + a2 eta + a3 xi eta.
#[inline]
fn coefficients(p: &[Vec3; 4]) -> [Vec3; 4] {
    let [x1, x2, x3, x4] = *p;
    let q = |s: [f64; 4]| -> Vec3 {
        std::array::from_fn(|d| 0.25 * (s[0] * x1[d] + s[1] * x2[d] + s[2] * x3[d] + s[3] * x4[d]))
    };
    [
        q([1.0, 1.0, 1.0, 1.0]),
        q([-1.0, 1.0, 1.0, -1.0]),
        q([-1.0, -1.0, 1.0, 1.0]),
        q([1.0, -1.0, 1.0, -1.0]),
    ]
}

/// Newton on grad (1/2 |x(xi,eta) - s|^2) = 0 from the centre. The Hessian is
/// [[x_xi.x_xi, x_xi.x_eta + r.a3], [.., x_eta.x_eta]]; where it is not positive definite the
/// Gauss-Newton matrix (without r.a3) is used.
fn newton(p: &[Vec3; 4], s: Vec3) -> Newton {
    let [a0, a1, a2, a3] = coefficients(p);
    let (mut xi, mut eta) = (0.0f64, 0.0f64);
    for _ in 0..MAX_ITER {
        let x_xi = add(a1, scale(a3, eta));
        let x_eta = add(a2, scale(a3, xi));
        let r = sub(
            add(
                add(a0, scale(a1, xi)),
                add(scale(a2, eta), scale(a3, xi * eta)),
            ),
            s,
        );
        let (f1, f2) = (dot(r, x_xi), dot(r, x_eta));
        let (j11, j22) = (dot(x_xi, x_xi), dot(x_eta, x_eta));
        let mut j12 = dot(x_xi, x_eta) + dot(r, a3);
        let mut det = j11 * j22 - j12 * j12;
        let singular = |det: f64| det.is_nan() || det <= 1e-12 * j11 * j22;
        if singular(det) {
            j12 = dot(x_xi, x_eta);
            det = j11 * j22 - j12 * j12;
            if singular(det) {
                return Newton::Failed;
            }
        }
        let dxi = (j22 * f1 - j12 * f2) / det;
        let deta = (j11 * f2 - j12 * f1) / det;
        xi -= dxi;
        eta -= deta;
        if dxi.abs() + deta.abs() < NEWTON_TOL {
            return Newton::Converged(xi, eta);
        }
        if xi.abs() > 4.0 || eta.abs() > 4.0 {
            return Newton::Outside;
        }
    }
    Newton::Failed
}

/// Fallback: the face as 4 triangles (x_a, x_a+1, centroid). The node is projected onto each
/// triangle's plane; among the triangles that contain the projection (barycentric weights
/// >= -[`INSIDE_TOL`]) the one nearest to the node is taken.
pub fn project_triangles(p: &[Vec3; 4], s: Vec3) -> Option<Projection> {
    let c = scale(add(add(p[0], p[1]), add(p[2], p[3])), 0.25);
    let mut best: Option<Projection> = None;
    for a in 0..4 {
        let b = (a + 1) % 4;
        let (x0, x1) = (p[a], p[b]);
        let nn = cross(sub(x1, x0), sub(c, x0));
        let area2 = norm(nn);
        if area2.is_nan() || area2 <= 0.0 {
            continue;
        }
        let n = scale(nn, 1.0 / area2);
        let g = dot(sub(s, x0), n);
        let q = sub(s, scale(n, g));
        let l0 = dot(cross(sub(x1, q), sub(c, q)), n) / area2;
        let l1 = dot(cross(sub(c, q), sub(x0, q)), n) / area2;
        let lc = 1.0 - l0 - l1;
        if l0 < -INSIDE_TOL || l1 < -INSIDE_TOL || lc < -INSIDE_TOL {
            continue;
        }
        if best.is_some_and(|bp| bp.gap.abs() <= g.abs()) {
            continue;
        }
        let mut w = [0.25 * lc; 4];
        w[a] += l0;
        w[b] += l1;
        let point = (0..4).fold([0.0; 3], |acc, k| add(acc, scale(p[k], w[k])));
        best = Some(Projection {
            w,
            point,
            normal: n,
            gap: dot(sub(s, point), n),
        });
    }
    best
}

/// Bounds of a face at the current positions, to reject a node before projecting it.
///
/// With c the centroid, n0 the unit normal at the centre (along the cross product of the
/// diagonals), r the largest centroid-corner distance, w the largest corner distance from the
/// mean plane, and the normal of the bilinear map `x_xi x x_eta = b0 + xi b1 + eta b2` (linear
/// in xi, eta, so over the extended face it is a convex combination of its values at the 4
/// extended corners): `cos_min` <= n.n0 and `sin_max` >= |n - (n.n0) n0| everywhere on the face.
/// A contact point is `x_c = sum w_a x_a` with `sum w_a = 1`, `sum |w_a| <= WEIGHT_SUM = E`, and
/// the node is `s = x_c + g n` with `-depth < g < -gap_min` and n the normal of the bilinear map
/// at some point of the extended face (for the triangle fallback of [`project`] too: the normal
/// of the triangle on edge (x_a, x_a+1) and the centroid is the bilinear normal at the edge's
/// midpoint, e.g. `(x_2 - x_1) x (c - x_1) = 2 (b0 - b2)`, the normal at (0, -1)); hence, for
/// d0 = (s - c).n0 and l the distance of s from the axis through c along n0:
/// - `d0 < E w - gap_min cos_min` (when cos_min > 0) and `d0 > -E w - depth`;
/// - `l <= E r + depth sin_max`;
/// - `|s - c| <= E r + depth`;
/// - s is not within gap_min of a corner (|g| is at most the distance to any point of the face).
///
/// [`FaceBounds::may_touch`] checks the first three (from the bounds alone),
/// [`off_corners`] the last; a node that fails one is not in contact.
///
/// `turn`, `kn1`, `kn2`: the coefficients `a_k` of `x = a0 + a1 xi + a2 eta + a3 xi eta` are
/// combinations of the corners with weights +-1/4 summing to zero, so a motion of the corners
/// by at most delta relative to any one point changes each by at most delta; `b = a x a'` by at
/// most `delta (|a| + |a'|) + delta^2`; so the normal `N(xi, eta)` by at most
/// `K1 delta + K2 delta^2`, `K1 = |a1| + |a2| + e (|a1| + 2 |a3| + |a2|)`, `K2 = 1 + 2 e`
/// (e = 1 + INSIDE_TOL). `N.n0` stays positive everywhere while that is below `min N.n0` (at the
/// extended corners): `turn` is the positive root of `K2 d^2 + K1 d = min N.n0` (zero when the
/// face is folded). And as `|N| >= min N.n0`, the direction of N turns by an angle whose sine is
/// at most `kn1 delta + kn2 delta^2`, `kn = K / min N.n0` (infinite when folded).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct FaceBounds {
    pub c: Vec3,
    pub n0: Vec3,
    pub r: f64,
    pub w: f64,
    pub cos_min: f64,
    pub sin_max: f64,
    pub turn: f64,
    pub kn1: f64,
    pub kn2: f64,
}

impl FaceBounds {
    pub fn new(p: &[Vec3; 4]) -> Self {
        let [c, a1, a2, a3] = coefficients(p);
        let b0 = cross(a1, a2);
        let b1 = cross(a1, a3);
        let b2 = cross(a3, a2);
        let len = norm(b0);
        let n0 = if len > 0.0 {
            scale(b0, 1.0 / len)
        } else {
            [0.0; 3]
        };
        let mut r2: f64 = 0.0;
        let mut w: f64 = 0.0;
        for q in p {
            let d = sub(*q, c);
            r2 = r2.max(dot(d, d));
            w = w.max(dot(d, n0).abs());
        }
        let e = 1.0 + INSIDE_TOL;
        let (mut dmin, mut n2max, mut lat2max) = (f64::INFINITY, 0.0f64, 0.0f64);
        for (xi, eta) in [(-e, -e), (e, -e), (e, e), (-e, e)] {
            let nk = add(b0, add(scale(b1, xi), scale(b2, eta)));
            let dn = dot(nk, n0);
            let n2 = dot(nk, nk);
            dmin = dmin.min(dn);
            n2max = n2max.max(n2);
            lat2max = lat2max.max((n2 - dn * dn).max(0.0));
        }
        let (cos_min, sin_max) = if dmin > 0.0 && len > 0.0 {
            // |lat|^2 = |N|^2 - (N.n0)^2 loses ~1e-16 |N|^2 to rounding: add 1e-15 |N|^2 so
            // the bound stays safe (it only widens the lateral test, by ~3e-8 depth)
            let lat = (lat2max + 1e-15 * n2max).sqrt();
            (dmin / n2max.sqrt(), (lat / dmin).min(1.0))
        } else {
            (0.0, 1.0) // folded or degenerate: no plane bound
        };
        // min N.n0 less its rounding (~1e-16 |N|), then the root of K2 d^2 + K1 d = dmin
        let dmin = dmin - 1e-12 * n2max.sqrt();
        let (turn, kn1, kn2) = if dmin > 0.0 && len > 0.0 {
            let (l1, l2, l3) = (norm(a1), norm(a2), norm(a3));
            let k1 = l1 + l2 + e * (l1 + 2.0 * l3 + l2);
            let k2 = 1.0 + 2.0 * e;
            let turn = 2.0 * dmin / (k1 + (k1 * k1 + 4.0 * k2 * dmin).sqrt());
            (turn, k1 / dmin, k2 / dmin)
        } else {
            (0.0, f64::INFINITY, f64::INFINITY)
        };
        Self {
            c,
            n0,
            r: r2.sqrt(),
            w,
            cos_min,
            sin_max,
            turn,
            kn1,
            kn2,
        }
    }

    /// False when node `s` cannot have a gap in (-depth, -gap_min) with the face (see the type's
    /// docs); cheap, called before [`project`].
    #[inline]
    pub fn may_touch(&self, s: Vec3, depth: f64, gap_min: f64) -> bool {
        let d = sub(s, self.c);
        let dd = dot(d, d);
        let reach = WEIGHT_SUM * self.r + depth;
        if dd > reach * reach {
            return false;
        }
        let d0 = dot(d, self.n0);
        let ew = WEIGHT_SUM * self.w;
        if d0 <= -ew - depth || (self.cos_min > 0.0 && d0 >= ew - gap_min * self.cos_min) {
            return false;
        }
        let lat = WEIGHT_SUM * self.r + depth * self.sin_max;
        dd - d0 * d0 <= lat * lat
    }
}

/// A face's [`FaceBounds`] folded with its depth limit as the per-node check reads them: one
/// cache line, the thresholds in f32 widened outwards; and the *clearance* of a node that
/// fails them.
///
/// Rounding: n0 in f32 is within 1.1e-7 of n0, so d0 = (s - c).n0 moves by at most
/// `1.1e-7 |s - c|`, which the slab and lateral thresholds absorb (a node they reject is
/// outside the reach sphere or beyond `1.2e-7 reach` of the exact f64 thresholds, which
/// [`FaceBounds::may_touch`] applies): the bounds reject a subset of what the f64 tests
/// reject, so never a contact.
///
/// Clearance: a length D >= 0 such that the node cannot touch the face (have a gap in
/// (-depth, -gap_min), anywhere on the extended face, through [`project`] or its fallback)
/// while no corner moves by more than D relative to the node. Each bound below is a function of
/// the node and the corners that a relative motion delta changes by at most `E delta`
/// (E = [`WEIGHT_SUM`]): with the weights w of a contact point held fixed,
/// `s - sum w_a x_a` changes by `sum w_a (ds - dx_a)`, at most `E delta`. With ν = n0 now:
/// - distance: contact needs `min_w |s - sum w_a x_a| <= |g| < depth`, and now
///   `min_w |s - sum w_a x_a| >= |s - c| - E r`: `D1 = (|s - c| - E r - depth) / E`;
/// - below: contact needs `max_w (s - sum w_a x_a).ν >= g n.ν > -depth`, now at most
///   `d0 + E w`: `D2 = (-E w - depth - d0) / E`;
/// - above: while the normals keep `n.ν > 0` (motion below [`FaceBounds`]' `turn`), contact
///   (`g < 0`) needs `min_w (s - sum w_a x_a).ν < 0`, now at least `d0 - E w`:
///   `D3 = min((d0 - E w) / E, turn)`.
///
/// D is the largest of those that are positive, less `2e-7 (|s - c| + E r + depth)` for the
/// f32 rounding; 0 when none is.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
#[repr(align(64))]
pub struct Cull {
    pub c: Vec3,
    /// n0 in f32.
    pub n0: [f32; 3],
    /// Contact needs `|s - c|^2 <= reach2`, `lo < d0 < hi` (`lo = -E w - depth`,
    /// `hi = E w - gap_min cos_min`, +inf when cos_min <= 0) and `|s - c|^2 - d0^2 <= lat2`
    /// (`lat = E r + depth sin_max`), each widened as above.
    reach2: f32,
    lo: f32,
    hi: f32,
    lat2: f32,
    /// `E r + depth` (up), `E w` (up), `turn` (down).
    reach: f32,
    ew: f32,
    turn: f32,
}

/// What the rest of the check reads of a face's bounds: `gap_min` (exact) and, widened
/// outwards, the cone and the turning rate of its normals ([`FaceBounds`]).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct CullMore {
    /// Gaps above `-gap_min` are not contact (`GAP_TOL r`).
    pub gap_min: f64,
    pub cos_min: f32,
    pub sin_max: f32,
    pub kn1: f32,
    pub kn2: f32,
}

/// An f32 not below `v` (NaN stays NaN): `v` widened by 2^-22 of itself (and 1e-44 for the
/// subnormals) before the conversion, which rounds by at most 2^-24 of it (beyond the f32
/// range, the largest f32 on the right side).
#[inline]
pub fn up32(v: f64) -> f32 {
    let t = (v + v.abs() * WIDEN + 1e-44) as f32;
    if v.is_infinite() {
        v as f32
    } else if t == f32::NEG_INFINITY {
        f32::MIN
    } else {
        t
    }
}

/// An f32 not above `v` (NaN stays NaN), as [`up32`].
#[inline]
pub fn down32(v: f64) -> f32 {
    let t = (v - v.abs() * WIDEN - 1e-44) as f32;
    if v.is_infinite() {
        v as f32
    } else if t == f32::INFINITY {
        f32::MAX
    } else {
        t
    }
}

/// Relative widening of the f32 bounds: 2^-22.
const WIDEN: f64 = 2.384185791015625e-7;

impl Cull {
    pub fn new(b: &FaceBounds, depth: f64, gap_min: f64) -> (Self, CullMore) {
        let reach = WEIGHT_SUM * b.r + depth;
        let ew = WEIGHT_SUM * b.w;
        let lat = WEIGHT_SUM * b.r + depth * b.sin_max;
        let slack = 1.2e-7 * reach;
        let hi = if b.cos_min > 0.0 {
            ew - gap_min * b.cos_min
        } else {
            f64::INFINITY
        };
        if !(reach.is_finite() && ew.is_finite() && lat.is_finite())
            || b.c.iter().chain(&b.n0).any(|v| !v.is_finite())
        {
            // no bounds: every node goes on to the projection (which rejects NaN)
            let all = Self {
                c: [0.0; 3],
                n0: [0.0; 3],
                reach2: f32::INFINITY,
                lo: f32::NEG_INFINITY,
                hi: f32::INFINITY,
                lat2: f32::INFINITY,
                reach: f32::INFINITY,
                ew: f32::INFINITY,
                turn: 0.0,
            };
            let more = CullMore {
                gap_min,
                ..CullMore::default()
            };
            return (all, more);
        }
        let cull = Self {
            c: b.c,
            n0: b.n0.map(|v| v as f32),
            reach2: up32(reach * reach),
            lo: down32(-ew - depth - slack),
            hi: up32(hi + slack),
            lat2: up32(lat * lat + 2.5e-7 * reach * reach),
            reach: up32(reach),
            ew: up32(ew),
            turn: down32(b.turn),
        };
        let more = CullMore {
            gap_min,
            cos_min: down32(b.cos_min),
            sin_max: up32(b.sin_max),
            kn1: up32(b.kn1),
            kn2: up32(b.kn2),
        };
        (cull, more)
    }

    /// n0 (in f64, from its f32).
    #[inline]
    pub fn n0(&self) -> Vec3 {
        self.n0.map(|v| v as f64)
    }

    /// `None` when node `s` passes the bounds (a superset of what [`FaceBounds::may_touch`]
    /// passes), else its clearance.
    #[inline]
    pub fn clearance(&self, s: Vec3) -> Option<f64> {
        let d = sub(s, self.c);
        let dd = dot(d, d);
        let d0 = dot(d, self.n0());
        if dd <= self.reach2 as f64
            && d0 > self.lo as f64
            && d0 < self.hi as f64
            && dd - d0 * d0 <= self.lat2 as f64
        {
            return None;
        }
        let e = WEIGHT_SUM;
        let dist = dd.sqrt();
        let reach = self.reach as f64;
        let mut c = ((dist - reach) / e).max((self.lo as f64 - d0) / e);
        if self.turn > 0.0 {
            c = c.max(((d0 - self.ew as f64) / e).min(self.turn as f64));
        }
        Some((c - 2e-7 * (dist + reach)).max(0.0))
    }
}

/// False when node `s` is within `gap_min` of a corner of the face (a coincident copy): then
/// |g| <= gap_min, no contact.
#[inline]
pub fn off_corners(p: &[Vec3; 4], s: Vec3, gap_min: f64) -> bool {
    let g2 = gap_min * gap_min;
    p.iter().all(|q| {
        let e = sub(s, *q);
        dot(e, e) > g2
    })
}

/// Penalty normal force on a penetrating node: `f_s = -k g n` (along the outward normal, as
/// g < 0); zero when the node does not penetrate.
#[inline]
pub fn normal_force(k: f64, gap: f64, n: Vec3) -> Vec3 {
    if gap < 0.0 {
        scale(n, -k * gap)
    } else {
        [0.0; 3]
    }
}

/// The reaction of a force `f` on the node, on the face's nodes: `-w_a f`.
#[inline]
pub fn reactions(w: &[f64; 4], f: Vec3) -> [Vec3; 4] {
    w.map(|wa| scale(f, -wa))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A random warped unit face: corners of the unit square moved by up to 0.2 in its plane
    /// and up to a random warp (below 0.3) out of it.
    pub(crate) fn warped_face(rng: &mut crate::contact::search::tests::Rng) -> [Vec3; 4] {
        let warp = rng.range(0.0, 0.3);
        let mut p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        for q in p.iter_mut() {
            *q = [
                q[0] + rng.range(-0.2, 0.2),
                q[1] + rng.range(-0.2, 0.2),
                rng.range(-warp, warp),
            ];
        }
        p
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// A node pushed 0.01 into a flat, tilted, non-square face: the gap is -0.01, the node gets
    /// k |g| along the outward normal, each face node -N_a(xi, eta) times that, and force and
    /// moment sum to zero (1e-12 relative to |f| and |f| times the face size).
    #[test]
    fn flat_face_force_and_reaction() {
        // a parallelogram in the plane z = 0.3 x + 0.1 y + 2, rotated order = outward normal
        // with positive z component
        let plane = |x: f64, y: f64| [x, y, 0.3 * x + 0.1 * y + 2.0];
        let p = [
            plane(0.0, 0.0),
            plane(2.0, 0.2),
            plane(2.5, 1.2),
            plane(0.5, 1.0),
        ];
        let n_true = {
            let c = cross(sub(p[1], p[0]), sub(p[3], p[0]));
            scale(c, 1.0 / norm(c))
        };
        // a point on the face at natural (0.3, -0.4), pushed 0.01 inward
        let (xi, eta) = (0.3, -0.4);
        let n_ = shape_functions(xi, eta);
        let on = (0..4).fold([0.0; 3], |a, k| add(a, scale(p[k], n_[k])));
        let s = sub(on, scale(n_true, 0.01));
        let pr = project(&p, s).expect("inside");
        assert!(rel(pr.gap, -0.01) < 1e-12, "gap {}", pr.gap);
        for k in 0..4 {
            assert!((pr.w[k] - n_[k]).abs() < 1e-13, "w {:?} vs {:?}", pr.w, n_);
        }
        assert!(norm(sub(pr.normal, n_true)) < 1e-14);

        let k = 3.0e7;
        let fs = normal_force(k, pr.gap, pr.normal);
        assert!(rel(norm(fs), k * 0.01) < 1e-12);
        assert!(norm(sub(scale(fs, 1.0 / norm(fs)), n_true)) < 1e-13);
        let fa = reactions(&pr.w, fs);
        for a in 0..4 {
            assert!(rel(norm(fa[a]), n_[a] * k * 0.01) < 1e-12);
        }
        let fsum = fa.iter().fold(fs, |acc, f| add(acc, *f));
        let msum = (0..4).fold(cross(s, fs), |acc, a| add(acc, cross(p[a], fa[a])));
        let fmag = norm(fs);
        assert!(norm(fsum) <= 1e-12 * fmag, "force sum {fsum:?}");
        assert!(norm(msum) <= 1e-12 * fmag * 3.0, "moment sum {msum:?}");
    }

    /// The cheap bounds never reject a node that the projection finds in contact: random
    /// warped faces and random nodes around them (10^5 pairs); and they do reject most of them.
    #[test]
    fn bounds_never_reject_a_contact() {
        let mut rng = crate::contact::search::tests::Rng(11);
        let (mut contacts, mut rejected) = (0, 0);
        for _ in 0..2000 {
            let p = warped_face(&mut rng);
            let b = FaceBounds::new(&p);
            let depth = rng.range(0.05, 0.5);
            let gap_min = 1e-9 * b.r;
            for _ in 0..50 {
                let s = [
                    rng.range(-0.5, 1.5),
                    rng.range(-0.5, 1.5),
                    rng.range(-0.6, 0.3),
                ];
                let touch = project(&p, s).is_some_and(|pr| pr.gap < -gap_min && pr.gap > -depth);
                let may = b.may_touch(s, depth, gap_min) && off_corners(&p, s, gap_min);
                assert!(may || !touch, "rejected a contact: {p:?} {s:?}");
                contacts += touch as usize;
                rejected += !may as usize;
            }
        }
        assert!(
            contacts > 5000 && rejected > 50_000,
            "{contacts} {rejected}"
        );
    }

    /// The compact bounds pass every node the f64 bounds pass, and a node they reject stays
    /// out of contact under any motion of the corners relative to it by at most its clearance:
    /// random warped faces and nodes (2 x 10^5), each followed by 4 random motions of the node
    /// and the corners, each corner moving relative to the node by at most the clearance, in
    /// directions that make it likely (the corners pushed at the node along the normal); the
    /// clearances are not all tiny either.
    #[test]
    fn clearance_is_never_crossed() {
        let mut rng = crate::contact::search::tests::Rng(23);
        let (mut rejected, mut big, mut touched) = (0, 0, 0);
        for _ in 0..4000 {
            let p = warped_face(&mut rng);
            let b = FaceBounds::new(&p);
            let depth = rng.range(0.05, 0.5);
            let gap_min = 1e-9 * b.r;
            let (cull, _) = Cull::new(&b, depth, gap_min);
            for _ in 0..50 {
                let s = [
                    rng.range(-1.0, 2.0),
                    rng.range(-1.0, 2.0),
                    rng.range(-1.0, 1.0),
                ];
                let pass = b.may_touch(s, depth, gap_min);
                let Some(d) = cull.clearance(s) else {
                    continue;
                };
                assert!(!pass, "f64 bounds pass, compact reject: {p:?} {s:?}");
                rejected += 1;
                big += (d > 0.05) as usize;
                for k in 0..4 {
                    // the corners move relative to the node by at most d: first all straight
                    // at it, then at random, mostly towards the node's side of the face
                    let n = b.n0;
                    let towards = if dot(sub(s, b.c), n) > 0.0 { 1.0 } else { -1.0 };
                    let at = sub(s, b.c);
                    let at = scale(at, SCALE_TEST * d / norm(at).max(1e-300));
                    let q = p.map(|x| {
                        if k == 0 {
                            return add(x, at);
                        }
                        let mut m = [0.0; 3];
                        for v in m.iter_mut() {
                            *v = rng.range(-1.0, 1.0);
                        }
                        m = add(m, scale(n, towards * rng.range(0.0, 2.0)));
                        let l = norm(m);
                        add(x, scale(m, SCALE_TEST * d * rng.range(0.0, 1.0) / l))
                    });
                    let touch = project(&q, s).is_some_and(|pr| {
                        pr.gap < -GAP_TOL_TEST * FaceBounds::new(&q).r && pr.gap > -depth
                    });
                    assert!(!touch, "crossed a clearance {d}: {p:?} -> {q:?}, {s:?}");
                    touched += touch as usize;
                }
            }
        }
        assert!(
            rejected > 100_000 && big > 20_000,
            "{rejected} {big} {touched}"
        );
    }

    const GAP_TOL_TEST: f64 = 1e-9;
    /// The motions as a multiple of the clearance (at 3 the test fails: it has teeth).
    const SCALE_TEST: f64 = 1.0;

    /// The f32 bounds are on the right side of their f64 values, also for tiny, huge and
    /// negative ones.
    #[test]
    fn f32_bounds_are_outwards() {
        let mut rng = crate::contact::search::tests::Rng(3);
        for k in 0..100_000 {
            let v = rng.range(-1.0, 1.0) * 10f64.powf(rng.range(-50.0, 50.0));
            let v = if k % 1000 == 0 { 0.0 } else { v };
            assert!(up32(v) as f64 >= v && down32(v) as f64 <= v, "{v}");
        }
        assert!(up32(f64::NAN).is_nan() && down32(f64::NAN).is_nan());
        for v in [f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!((up32(v), down32(v)), (v as f32, v as f32));
        }
    }

    /// A node on a face's corner (a coincident copy) is rejected without projecting.
    #[test]
    fn node_on_a_corner_is_rejected() {
        let p = [
            [0.0, 0.0, 0.1],
            [1.0, 0.0, -0.1],
            [1.0, 1.0, 0.1],
            [0.0, 1.0, -0.1],
        ];
        let b = FaceBounds::new(&p);
        assert!(b.may_touch(p[1], 0.4, 1e-9) && !off_corners(&p, p[1], 1e-9));
        let s = [0.5, 0.5, -0.05];
        assert!(b.may_touch(s, 0.4, 1e-9) && off_corners(&p, s, 1e-9));
    }

    /// Outside the face (beyond 2% of the half-width) there is no projection; just inside the
    /// tolerance there is.
    #[test]
    fn outside_is_rejected() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert!(project(&p, [1.02, 0.5, -0.01]).is_none()); // xi = 1.04
        let pr = project(&p, [1.005, 0.5, -0.01]).expect("within tolerance"); // xi = 1.01
        assert!((pr.gap + 0.01).abs() < 1e-15);
        assert!(project(&p, [5.0, 0.5, -0.01]).is_none());
    }

    /// A warped face: Newton converges to a point where s - x_c is along the normal (the
    /// closest-point condition), so the moment of the pair vanishes; the triangle fallback
    /// lands within the warp of it.
    #[test]
    fn warped_face_closest_point() {
        let p = [
            [0.0, 0.0, 0.1],
            [1.0, 0.0, -0.1],
            [1.0, 1.0, 0.1],
            [0.0, 1.0, -0.1],
        ];
        let s = [0.63, 0.41, -0.05];
        let pr = project(&p, s).expect("inside");
        let d = sub(s, pr.point);
        let t = sub(d, scale(pr.normal, dot(d, pr.normal)));
        assert!(norm(t) < 1e-13, "tangential residual {t:?}");
        assert!(pr.gap < 0.0);
        let fs = normal_force(1.0, pr.gap, pr.normal);
        let fa = reactions(&pr.w, fs);
        let msum = (0..4).fold(cross(s, fs), |acc, a| add(acc, cross(p[a], fa[a])));
        assert!(norm(msum) <= 1e-12 * norm(fs));
        let tri = project_triangles(&p, s).expect("inside");
        assert!((tri.gap - pr.gap).abs() < 0.05, "{} vs {}", tri.gap, pr.gap);
        assert!((tri.w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }
}
