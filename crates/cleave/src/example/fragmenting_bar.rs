//! `cleave example fragmenting-bar`: dynamic fragmentation of a bar stretched at a uniform
//! strain rate, the one-dimensional problem of Zhou, Molinari and Ramesh (2005) and of Grady's
//! energy estimate, with every interface cohesive and of random strength.
//!
//! - The bar: [`LENGTH_L0`] characteristic lengths long, one element across (square section of
//!   side h), [`ELEMENTS_PER_L0`] elements per characteristic length
//!   L0 = E GC / SIGMAX^2. Poisson's ratio 0, so the bar is a one-dimensional rod: uniaxial
//!   stress travels at c = sqrt(E / rho) and no lateral motion couples in.
//! - The material ([`CERAMIC`]): the ceramic of Zhou, Molinari and Ramesh: E 275 GPa, rho 2750
//!   kg/m^3, mean cohesive strength 300 MPa, GC 100 J/m^2 (L0 = 0.306 mm, c = 10 km/s,
//!   t0 = L0 / c = 30.6 ns).
//! - Every interface is cohesive: `*MAT_ADD_SEPARATION` MODEL 3 (linear softening, as theirs),
//!   strengths uniform between 1 - w and 1 + w times the mean (DIST 1), w = `--spread`
//!   (default [`SPREAD`]), seed `--seed`.
//! - Loading: v = eps_dot (x - L/2) at t = 0 and the end faces driven at -/+ eps_dot L / 2 for
//!   the whole run: until the first failure the bar stretches homogeneously (no waves), the
//!   stress rising as E eps_dot t.
//! - `*CONTACT_AUTOMATIC_SINGLE_SURFACE` over the bar, frictionless: a fragment that springs
//!   back after it breaks free meets its neighbour (a closing cohesive face carries no
//!   compression; contact takes it).
//! - End time: the strength's upper bound is reached at (1 + w) t0 / eps_bar (eps_bar = eps_dot /
//!   eps_dot0, eps_dot0 = c SIGMAX^3 / (E^2 GC) = 3.6e4 /s); the run goes on for
//!   [`SETTLE_T0`] t0 after it: the count of fragments has settled by then (it grows by less
//!   than 2% over the last 20 t0 from 0.3 eps_dot0 up, 5% at 0.1; `cleave bench
//!   fragmentation` reports the growth).
//! - Time step: TSSFAC [`TSSFAC`], where the count has converged with the step.
//!
//! Normalised as Zhou, Molinari and Ramesh do (their eq. 16-18): length by L0, time by t0,
//! strain rate by eps_dot0 = 1 / (E t0 / SIGMAX).

use cleave_core::mesh::box_model;
use cleave_core::model::{
    ContactDef, Material, MaterialKind, Model, MotionTarget, PrescribedMotion, SeparationDef,
    StrengthDist, Vad,
};

/// The ceramic: density (kg/m^3), Young's modulus (Pa), mean strength (Pa), GC (J/m^2).
pub const CERAMIC: Ceramic = Ceramic {
    density: 2750.0,
    young: 275e9,
    sigma: 300e6,
    gc: 100.0,
};

/// Elements per characteristic length L0.
pub const ELEMENTS_PER_L0: f64 = 20.0;
/// The bar's length in characteristic lengths L0.
pub const LENGTH_L0: f64 = 100.0;
/// Default half-width of the uniform strength distribution, as a fraction of the mean.
pub const SPREAD: f64 = 0.1;
/// The time step scale factor (`*CONTROL_TIMESTEP` TSSFAC) of the bar: the fragment count
/// converges with the time step (the cohesive faces' stiffness grows as the step shrinks,
/// [`cleave_core::separation::cohesive::stable_slope`]). Seed 1, 2000 elements (`cleave bench
/// fragmentation --tssfac F`): at 1 eps_dot0, 118, 115, 112, 110, 114 fragments at TSSFAC 0.9,
/// 0.5, 0.3, 0.2, 0.1; at 3 eps_dot0 207, 206, 203, 204 from 0.5 down; at 10 eps_dot0 416,
/// 412, 411, 409. At 0.9, seed 1, the bar inverted elements at 3 eps_dot0 (1, 10 and 30 ran;
/// the cohesive law's known limit). Akantu, on the same bar, is unstable at 0.9 and
/// converged from 0.5 down (`studies/akantu-fragmentation`).
pub const TSSFAC: f64 = 0.2;
/// Time run after the strongest interface's stress is reached, in units of t0.
pub const SETTLE_T0: f64 = 40.0;

/// A brittle material with a cohesive law.
#[derive(Clone, Copy, Debug)]
pub struct Ceramic {
    pub density: f64,
    pub young: f64,
    /// Mean cohesive strength SIGMAX (Pa).
    pub sigma: f64,
    pub gc: f64,
}

impl Ceramic {
    /// Wave speed c = sqrt(E / rho) of the rod (m/s).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }
    /// Characteristic length L0 = E GC / SIGMAX^2 (m).
    pub fn l0(&self) -> f64 {
        self.young * self.gc / (self.sigma * self.sigma)
    }
    /// Characteristic time t0 = L0 / c (s).
    pub fn t0(&self) -> f64 {
        self.l0() / self.wave_speed()
    }
    /// Characteristic strain rate eps_dot0 = SIGMAX / (E t0) = c SIGMAX^3 / (E^2 GC) (1/s).
    pub fn rate0(&self) -> f64 {
        self.sigma / (self.young * self.t0())
    }
}

/// How the bar is made: strain rate, size, strengths, end time.
#[derive(Clone, Copy, Debug)]
pub struct BarSpec {
    /// The strain rate in units of eps_dot0.
    pub rate: f64,
    /// Elements along the bar (`None`: [`LENGTH_L0`] x [`ELEMENTS_PER_L0`]).
    pub elements: Option<usize>,
    /// Half-width of the strength distribution, as a fraction of the mean (`None`: [`SPREAD`]).
    pub spread: Option<f64>,
    pub seed: u64,
    /// `*CONTROL_TIMESTEP` TSSFAC (`None`: [`TSSFAC`]).
    pub tssfac: Option<f64>,
    /// `None`: the default above.
    pub end_time: Option<f64>,
}

/// The bar of `spec`.
pub fn fragmenting_bar(spec: BarSpec) -> Result<Model, String> {
    let BarSpec {
        rate,
        elements,
        spread,
        seed,
        tssfac,
        end_time,
    } = spec;
    let tssfac = tssfac.unwrap_or(TSSFAC);
    if tssfac.is_nan() || tssfac <= 0.0 || tssfac > 1.0 {
        return Err(format!("--tssfac {tssfac}: must lie in (0, 1]"));
    }
    let spread = spread.unwrap_or(SPREAD);
    if !(0.0..1.0).contains(&spread) || spread == 0.0 {
        return Err(format!(
            "--spread {spread}: the half-width of the strengths must lie in (0, 1) (a fraction of the mean)"
        ));
    }
    if !(rate.is_finite() && rate > 0.0) {
        return Err(format!(
            "--strain-rate {rate}: must be a positive number (eps_dot / eps_dot0)"
        ));
    }
    let n = elements.unwrap_or((LENGTH_L0 * ELEMENTS_PER_L0) as usize);
    if !(2..=10_000_000).contains(&n) {
        return Err(format!(
            "--elements {n}: fragmenting-bar takes 2 to 10,000,000 elements"
        ));
    }
    let m = CERAMIC;
    let h = m.l0() / ELEMENTS_PER_L0;
    let len = n as f64 * h;
    let eps_dot = rate * m.rate0();
    let end = end_time.unwrap_or((1.0 + spread) * m.t0() / rate + SETTLE_T0 * m.t0());
    let mat = Material {
        id: 1,
        density: m.density,
        young: m.young,
        poisson: 0.0,
        kind: MaterialKind::Elastic,
    };
    let mut model = box_model([n, 1, 1], [len, h, h], mat, end);
    model.title = format!(
        "Fragmenting bar: {n} elements, strain rate {rate} eps_dot0 = {eps_dot:.6e} /s, strengths +/- {spread}, seed {seed}"
    );
    model.parts[0].title = "ceramic bar".into();
    for (x, v) in model.x0.iter().zip(model.v0.iter_mut()) {
        *v = [eps_dot * (x[0] - 0.5 * len), 0.0, 0.0];
    }
    model.curves.push(cleave_core::curve::Curve {
        id: 1,
        t: vec![0.0, end],
        y: vec![1.0, 1.0],
    });
    for (x, sf) in [(0.0, -0.5 * eps_dot * len), (len, 0.5 * eps_dot * len)] {
        for node in model.nodes_where(0, x, 1e-9 * h) {
            model.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(0),
                vad: Vad::Velocity,
                curve: 0,
                sf,
            });
        }
    }
    model.separations.push(SeparationDef {
        material: 0,
        model: 3,
        sigmax: m.sigma,
        beta: 1.0,
        gc: m.gc,
        bond: 1,
        strength: StrengthDist::Uniform {
            smin: (1.0 - spread) * m.sigma,
            smax: (1.0 + spread) * m.sigma,
            seed,
        },
    });
    // fragments that spring back meet their neighbours: without contact they would pass through
    model.contacts = vec![ContactDef::single_surface_all(0.0, 0.0)];
    model.control.tssfac = tssfac;
    model.output.glstat_dt = end / 200.0;
    model.output.d3plot_dt = end / 20.0;
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The characteristic scales of the ceramic: L0 = 275e9 x 100 / (300e6)^2 = 0.3056 mm,
    /// c = 10 km/s, t0 = 30.56 ns, eps_dot0 = 3.57e4 /s.
    #[test]
    fn characteristic_scales() {
        let m = CERAMIC;
        assert!((m.l0() - 3.0556e-4).abs() < 1e-8);
        assert!((m.wave_speed() - 1e4).abs() < 1e-9);
        assert!((m.t0() - 3.0556e-8).abs() < 1e-12);
        assert!((m.rate0() - 3.5702e4).abs() < 1.0);
    }

    fn spec(rate: f64, elements: Option<usize>) -> BarSpec {
        BarSpec {
            rate,
            elements,
            spread: None,
            seed: 1,
            tssfac: None,
            end_time: None,
        }
    }

    /// The bar starts stretching homogeneously: the initial velocity is the ends' speed at the
    /// ends, linear in between.
    #[test]
    fn the_initial_velocity_is_the_uniform_stretch() {
        let b = fragmenting_bar(spec(1.0, Some(10))).unwrap();
        let eps = CERAMIC.rate0();
        for (x, v) in b.x0.iter().zip(b.v0.iter()) {
            assert!(
                (v[0] - eps * (x[0] - 0.5 * 10.0 * CERAMIC.l0() / ELEMENTS_PER_L0)).abs() < 1e-9
            );
        }
        assert_eq!(b.prescribed.len(), 8);
        assert!(fragmenting_bar(spec(0.0, None)).is_err());
        assert!(fragmenting_bar(spec(1.0, Some(1))).is_err());
        let wide = BarSpec {
            spread: Some(1.0),
            ..spec(1.0, None)
        };
        assert!(fragmenting_bar(wide).is_err());
    }
}
