//! Solid elements: the 8-node hexahedron's geometry ([`hex8`]) and one-point force kernel
//! with Flanagan-Belytschko hourglass control ([`kernel`]), the constant-strain tetrahedron
//! ([`tet4`]), the shapes an 8-node connectivity can hold ([`shape`]) with the step of each
//! ([`element_step`]), and the colours of element chunks that let the element pass add its
//! forces into the nodes on all cores ([`colouring`]).

pub mod colouring;
pub mod hex8;
pub mod kernel;
pub mod nodal_pressure;
pub mod shape;
pub mod sri;
pub mod tet4;

pub use shape::Shape;

use crate::material::{History, SolidParams};
use crate::math::{Sym3, Vec3};
use kernel::{ElementStep, InvertedElement, KernelControls};

/// The 4 corners of a tetrahedron's stored 8 ([`Shape::corners`]).
const TET: [usize; 4] = [0, 1, 2, 4];

/// The element phase of one element of shape `shape`, on its 8 stored corners: the
/// hexahedron kernel for hexahedra and wedges, the tetrahedron's on the 4 distinct corners of
/// a tetrahedron (the other corners get zero force). Arguments as [`kernel::hex8_step`], and
/// `theta_bar`: an ELFORM 13 tetrahedron's averaged volumetric strain increment
/// ([`nodal_pressure`]; `None` otherwise).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn element_step(
    shape: Shape,
    x: &[Vec3; 8],
    v: &[Vec3; 8],
    theta_bar: Option<f64>,
    dt_prev: f64,
    mat: &SolidParams,
    ctl: &KernelControls,
    sigma: &mut Sym3,
    hist: &mut History,
    q_prev: &mut f64,
    hg_force: Option<&mut [f64; 12]>,
    f: &mut [Vec3; 8],
) -> Result<ElementStep, InvertedElement> {
    match shape {
        Shape::Hex | Shape::Wedge => {
            kernel::hex8_step(x, v, dt_prev, mat, ctl, sigma, hist, q_prev, hg_force, f)
        }
        Shape::Tet => {
            let mut f4 = [[0.0; 3]; 4];
            let r = tet4::tet4_step(
                &TET.map(|a| x[a]),
                &TET.map(|a| v[a]),
                theta_bar,
                dt_prev,
                mat,
                ctl,
                sigma,
                hist,
                q_prev,
                &mut f4,
            )?;
            *f = [[0.0; 3]; 8];
            for (k, &a) in TET.iter().enumerate() {
                f[a] = f4[k];
            }
            Ok(r)
        }
    }
}

/// The corner forces from the state the last [`element_step`] left, bit for bit the same.
pub fn element_corner_forces(
    shape: Shape,
    x: &[Vec3; 8],
    sigma: &Sym3,
    q: f64,
    hg_force: &[f64; 12],
    f: &mut [Vec3; 8],
) -> Result<(), InvertedElement> {
    match shape {
        Shape::Hex | Shape::Wedge => kernel::hex8_corner_forces(x, sigma, q, hg_force, f),
        Shape::Tet => {
            let mut f4 = [[0.0; 3]; 4];
            tet4::tet4_corner_forces(&TET.map(|a| x[a]), sigma, q, &mut f4)?;
            *f = [[0.0; 3]; 8];
            for (k, &a) in TET.iter().enumerate() {
                f[a] = f4[k];
            }
            Ok(())
        }
    }
}

/// Exact volume of an element on its 8 stored corners.
pub fn volume(shape: Shape, x: &[Vec3; 8]) -> f64 {
    match shape {
        Shape::Hex | Shape::Wedge => hex8::volume(x),
        Shape::Tet => tet4::volume(&TET.map(|a| x[a])),
    }
}

/// Characteristic length of the stable time step at rest: `V / A_max` for the hexahedron and
/// the wedge (LS-DYNA's solids), the minimum altitude `3 V / A_max` for the tetrahedron.
pub fn characteristic_length(shape: Shape, x: &[Vec3; 8]) -> f64 {
    match shape {
        Shape::Hex | Shape::Wedge => hex8::volume(x) / hex8::max_face_area(x),
        Shape::Tet => {
            let t = TET.map(|a| x[a]);
            3.0 * tet4::volume(&t) / tet4::max_face_area(&t)
        }
    }
}

/// Where an element is not upright: the first corner (0-based, of the stored 8) whose
/// Jacobian determinant is not positive, with its value. A hexahedron is checked at its 8
/// corners, a wedge at the 4 corners of its quadrilateral base (its top corners are collapsed,
/// where the determinant vanishes) and by its volume, a tetrahedron by its volume (6 V is its
/// one determinant).
pub fn first_bad_corner(shape: Shape, x: &[Vec3; 8]) -> Option<(usize, f64)> {
    match shape {
        Shape::Hex => {
            let j = hex8::corner_jacobians(x);
            (0..8).find(|&a| !upright(j[a])).map(|a| (a, j[a]))
        }
        Shape::Wedge => {
            let j = hex8::corner_jacobians(x);
            let v = hex8::volume(x);
            (0..4)
                .find(|&a| !upright(j[a]))
                .map(|a| (a, j[a]))
                .or_else(|| (!upright(v)).then_some((4, v)))
        }
        Shape::Tet => {
            let v = tet4::volume(&TET.map(|a| x[a]));
            (!upright(v)).then_some((4, 6.0 * v))
        }
    }
}

/// A determinant or volume that is positive (NaN is not).
fn upright(j: f64) -> bool {
    j > 0.0
}
