//! Concentrated and pressure loads (`*LOAD_NODE_...`, `*LOAD_SEGMENT...`) at each step: the
//! nodal forces at t^n, and their work.
//!
//! A pressure segment's force is `-p A` with `A = (x3 - x1) x (x4 - x2) / 2` its area vector
//! at t^n (the diagonals' cross product: exact for flat quadrilaterals and for triangles,
//! `N1 N2 N3 N3`), shared equally by its distinct nodes.
//!
//! Work: the step's forces act as the impulse `J = F^n dt_mid` on v^(n+1/2), and the kinetic
//! energy at t^n is `1/2 m v^(n-1/2) . v^(n+1/2)`; so, as for the solver's other impulses, `J`'s
//! work is booked as `1/2 J . v^(n-1/2)` at t^n and `1/2 J . v^(n+1/2)` at the next step
//! ([`Loads::work`], once with each velocity). (The trapezoid `1/2 (F^(n-1) + F^n) . v dt` of
//! the interval is the same for a constant time step, but not where the step changes: a free
//! block pushed for 20 us ended 1.2% off when the last step was cut short to meet the end
//! time.)

use crate::curve::Curve;
use crate::math::{cross, dot, scale, sub, Vec3};
use crate::model::{Model, NodeLoad, PressureLoad};

/// The loads' forces of the step, in a fixed order (node loads, then each segment's nodes).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub struct Loads {
    now: Vec<(u32, Vec3)>,
}

impl Loads {
    /// Whether the model has any.
    pub fn any(model: &Model) -> bool {
        !model.node_loads.is_empty() || !model.pressure_loads.is_empty()
    }

    /// The forces at time `t` on positions `x` (by node), each passed to `add(node, force)` in
    /// a fixed order, and kept for [`Self::work`].
    pub fn apply(
        &mut self,
        model: &Model,
        t: f64,
        x: impl Fn(u32) -> Vec3,
        mut add_force: impl FnMut(u32, Vec3),
    ) {
        self.now.clear();
        for l in &model.node_loads {
            self.now.push((l.node, node_force(l, &model.curves, t)));
        }
        for l in &model.pressure_loads {
            let p = pressure(l, &model.curves, t);
            let pts = if l.nodes[3] == l.nodes[2] { 3 } else { 4 };
            let f = if p == 0.0 {
                [0.0; 3]
            } else {
                let xs = l.nodes.map(&x);
                let area = scale(cross(sub(xs[2], xs[0]), sub(xs[3], xs[1])), 0.5);
                scale(area, -p / pts as f64)
            };
            for &n in &l.nodes[..pts] {
                self.now.push((n, f));
            }
        }
        for &(n, f) in &self.now {
            add_force(n, f);
        }
    }

    /// Half the work of the last forces as the impulse `F dt_mid` on velocities `v` (by
    /// node): `1/2 sum F . v dt_mid`.
    pub fn work(&self, v: impl Fn(u32) -> Vec3, dt_mid: f64) -> f64 {
        let mut w = 0.0;
        for &(n, f) in &self.now {
            w += dot(f, v(n));
        }
        0.5 * w * dt_mid
    }
}

fn node_force(l: &NodeLoad, curves: &[Curve], t: f64) -> Vec3 {
    let mut f = [0.0; 3];
    f[l.axis] = l.sf * curves[l.curve].eval(t);
    f
}

fn pressure(l: &PressureLoad, curves: &[Curve], t: f64) -> f64 {
    if t < l.at {
        0.0
    } else {
        l.sf * curves[l.curve].eval(t)
    }
}
