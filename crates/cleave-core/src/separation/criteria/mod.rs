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

    /// A factor k such that the measure is at most k |t| when the traction on the face, for
    /// any normal, is at most |t|: with the bound of [`traction_bound`] a cheap test that
    /// spares the full sample of interfaces far from failure. The default, infinity, always
    /// takes the full sample.
    fn bound_factor(&self) -> f64 {
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
