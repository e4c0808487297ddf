//! Interface failure criteria: when does an intact interface stop tying its nodes?
//!
//! Each step every intact interface is shown an [`InterfaceSample`]: the information the paper
//! lists as available to a criterion (section 3: nodal and element variables, time, interface
//! history), and returns its stress measure; the interface fails when the measure reaches the
//! interface's strength (its failure index, measure over strength, reaches 1). The strength is
//! the group's SIGMAX or, with a strength distribution, the interface's own draw
//! ([`super::strength`]).
//!
//! A new criterion is one file: implement [`Criterion`] and add its MODEL number to
//! [`criterion_for`]. The solver loop never changes.
//!
//! | MODEL | criterion | after onset |
//! |---|---|---|
//! | 1 | [`normal_stress::NormalStress`]: n.s.n | free |
//! | 2 | [`effective_stress::EffectiveStress`]: `sqrt(<sn>^2 + (tau/BETA)^2)` | free |
//! | 3 | as 2 | linear softening ([`super::cohesive::CohesiveLaw`]), then free |
//! | 4 | as 2 | exponential softening ([`super::cohesive::CohesiveLaw`]), then free |

pub mod effective_stress;
pub mod normal_stress;

use crate::material::History;
use crate::math::{dot, scale, sub, sym_mul_vec, Sym3, Vec3};
use crate::model::SeparationDef;
use crate::node_values::NodeValues;
use crate::separation::split::SharedFace;

/// What a criterion may look at for one interface at t^n.
pub struct InterfaceSample<'a> {
    /// Time t^n.
    pub time: f64,
    /// The interface (its two elements, 4 + 4 nodes, reference area).
    pub face: &'a SharedFace,
    /// Current unit normal of the face, pointing out of `face.elems[0]` into `face.elems[1]`.
    pub normal: Vec3,
    /// Cauchy stresses of the two elements at t^n.
    pub stress: [&'a Sym3; 2],
    /// Material history (plastic strain, back stress) of the two elements.
    pub history: [&'a History; 2],
    /// Nodal positions x^n and velocities v^(n-1/2) of the whole model.
    pub x: NodeValues<'a, Vec3>,
    pub v: NodeValues<'a, Vec3>,
}

impl InterfaceSample<'_> {
    /// Mean Cauchy stress of the two elements, s = (s_a + s_b) / 2 (the interface page's
    /// sampling).
    pub fn mean_stress(&self) -> Sym3 {
        std::array::from_fn(|k| 0.5 * (self.stress[0][k] + self.stress[1][k]))
    }

    /// Traction on the face, t = s n, split into its normal part sn = n.t (positive in tension)
    /// and the magnitude of its shear part tau = |t - sn n|.
    pub fn normal_and_shear(&self) -> (f64, f64) {
        let t = sym_mul_vec(&self.mean_stress(), self.normal);
        let sn = dot(t, self.normal);
        let ts = sub(t, scale(self.normal, sn));
        (sn, dot(ts, ts).sqrt())
    }
}

/// A failure criterion of one separation group.
pub trait Criterion: Send + Sync {
    /// The stress measure (Pa) of the interface: it fails when the measure reaches its
    /// strength.
    fn stress(&self, sample: &InterfaceSample) -> f64;

    /// An upper bound of the measure over every unit normal, for an interface between
    /// elements of stresses `a` and `b` (its mean stress `(a + b) / 2`): a cheap test that
    /// spares the full sample (the face normal, the traction) of interfaces far from failure.
    /// The default, infinity, always takes the full sample.
    fn bound(&self, _a: &Sym3, _b: &Sym3) -> f64 {
        f64::INFINITY
    }
}

/// An upper bound of |s n| over unit normals n for the mean of two stresses: the mean of their
/// largest absolute row sums (the spectral norm of a symmetric matrix is at most its largest
/// absolute row sum, Gershgorin).
pub fn traction_bound(a: &Sym3, b: &Sym3) -> f64 {
    fn rows(s: &Sym3) -> f64 {
        let (xy, yz, zx) = (s[3].abs(), s[4].abs(), s[5].abs());
        (s[0].abs() + xy + zx)
            .max(s[1].abs() + xy + yz)
            .max(s[2].abs() + yz + zx)
    }
    0.5 * (rows(a) + rows(b))
}

/// An upper bound of the normal stress n.s.n over unit normals n for the mean of two
/// stresses: the mean of their largest signed row bounds `s_ii + sum_(j != i) |s_ij|`
/// (n.s.n is at most the largest eigenvalue of s, which lies in one of the Gershgorin discs,
/// and n.s.n of the mean is the mean of the two). Unlike [`traction_bound`] it is negative
/// under a compression: no compressed interface needs its normal for a tension criterion.
pub fn tension_bound(a: &Sym3, b: &Sym3) -> f64 {
    fn rows(s: &Sym3) -> f64 {
        let (xy, yz, zx) = (s[3].abs(), s[4].abs(), s[5].abs());
        (s[0] + xy + zx).max(s[1] + xy + yz).max(s[2] + yz + zx)
    }
    0.5 * (rows(a) + rows(b))
}

/// The criterion of a `*MAT_ADD_SEPARATION` card, by its MODEL number.
///
/// MODELs 3 and 4 start softening at the onset given by MODEL 2's effective stress.
pub fn criterion_for(def: &SeparationDef) -> Result<Box<dyn Criterion>, String> {
    match def.model {
        1 => Ok(Box::new(normal_stress::NormalStress)),
        2..=4 => Ok(Box::new(effective_stress::EffectiveStress {
            beta: def.beta,
        })),
        m => Err(format!(
            "*MAT_ADD_SEPARATION MODEL {m} is not a criterion (1, 2, 3 or 4)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{norm, principal_values};
    use crate::separation::split::FaceKind;

    /// A deterministic stream of numbers in [-1, 1).
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// Each criterion's measure, at random stresses (tension, compression, shear; Pa) and
    /// random unit normals, never exceeds its bound, nor do the worst normals' (the mean
    /// stress's largest eigenvalue, and largest in magnitude, below the tension and the
    /// traction bound); and the tension bound of the paper's
    /// criterion is negative under a compression of every axis however large the shear is
    /// below it, so no compressed interface needs the full sample.
    #[test]
    fn the_cheap_bounds_hold_and_skip_compressed_interfaces() {
        let face = SharedFace {
            elems: [0, 1],
            faces: [0, 1],
            nodes: [0; 8],
            area0: 1.0,
            group: 0,
            kind: FaceKind::Interface,
            strength: 1.0,
        };
        let history = History::default();
        let x = NodeValues::new(&[], None);
        let criteria: [Box<dyn Criterion>; 3] = [
            Box::new(normal_stress::NormalStress),
            Box::new(effective_stress::EffectiveStress { beta: 0.5 }),
            Box::new(effective_stress::EffectiveStress { beta: 2.0 }),
        ];
        let mut r = stream(7);
        let mut tight = 0;
        for k in 0..2000 {
            // a mean pressure from -3e8 to 3e8 Pa under deviators up to 2e8
            let mut sym = |p: f64| -> Sym3 {
                std::array::from_fn(|i| if i < 3 { p + 2e8 * r() } else { 1e8 * r() })
            };
            let p = 3e8 * (k as f64 / 1000.0 - 1.0);
            let (a, b) = (sym(p), sym(p));
            let stress = [&a, &b];
            // the worst normal: the extreme eigenvalues of the mean stress
            let mean: Sym3 = std::array::from_fn(|i| 0.5 * (a[i] + b[i]));
            let l = principal_values(&mean);
            let (l_max, l_abs) = (l[0].max(l[1]).max(l[2]), l.map(f64::abs));
            assert!(l_max <= tension_bound(&a, &b) + 1e-6, "{l:?}");
            assert!(l_abs[0].max(l_abs[1]).max(l_abs[2]) <= traction_bound(&a, &b) + 1e-6);
            let mut top = [f64::NEG_INFINITY; 3];
            for _ in 0..50 {
                let v = [r(), r(), r()];
                let l = norm(v);
                if l < 1e-3 {
                    continue;
                }
                let normal = v.map(|c| c / l);
                let sample = InterfaceSample {
                    time: 0.0,
                    face: &face,
                    normal,
                    stress,
                    history: [&history, &history],
                    x,
                    v: x,
                };
                for (c, crit) in criteria.iter().enumerate() {
                    let m = crit.stress(&sample);
                    assert!(m <= crit.bound(&a, &b) + 1e-6, "criterion {c}: {m}");
                    top[c] = top[c].max(m);
                }
            }
            // the bound is not loose by more than the discs' width (2 of 3 shear terms)
            let slack = 2.0 * 1e8 + 2.0 * 2e8;
            if criteria[0].bound(&a, &b) - top[0] < slack {
                tight += 1;
            }
        }
        assert!(tight > 1900, "tension bound loose {} times", 2000 - tight);
        // every axis compressed by more than its shear row: negative
        let c: Sym3 = [-5e8, -4e8, -6e8, 1e8, -2e8, 1.5e8];
        assert!(tension_bound(&c, &c) < 0.0);
        assert!(traction_bound(&c, &c) > 0.0);
    }
}
