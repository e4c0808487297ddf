//! Load curves (`*DEFINE_CURVE`): piecewise-linear functions of time.

/// A piecewise-linear curve with its scale factors and offsets already applied:
/// the deck's point (a, o) becomes (SFA * a + OFFA, SFO * o + OFFO), as in the LS-DYNA manual.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Deck id (LCID).
    pub id: i64,
    /// Abscissae, strictly increasing (the deck reader rejects unsorted ones).
    pub t: Vec<f64>,
    /// Ordinates.
    pub y: Vec<f64>,
}

impl Curve {
    /// Value at `t`: linear interpolation between points; before the first and after the last
    /// point the end value is held (LS-DYNA's behaviour for load curves). A one-point curve is
    /// a constant.
    pub fn eval(&self, t: f64) -> f64 {
        let n = self.t.len();
        if n == 0 {
            return 0.0;
        }
        if t <= self.t[0] {
            return self.y[0];
        }
        if t >= self.t[n - 1] {
            return self.y[n - 1];
        }
        // first index with self.t[i] > t; 1 <= i <= n-1
        let i = self.t.partition_point(|&ti| ti <= t);
        let (t0, t1) = (self.t[i - 1], self.t[i]);
        let (y0, y1) = (self.y[i - 1], self.y[i]);
        y0 + (y1 - y0) * (t - t0) / (t1 - t0)
    }

    /// The largest time step a `*CONTROL_TIMESTEP` LCTM curve allows at `t`: its value, except
    /// past its last abscissa or where it is 0, where the computed step is used (`None`), as
    /// the LS-DYNA keyword manual says.
    pub fn step_cap(&self, t: f64) -> Option<f64> {
        let last = *self.t.last()?;
        let y = self.eval(t);
        (t <= last && y != 0.0).then_some(y)
    }

    /// Integral of the curve from 0 to `t` (exact for the piecewise-linear function, with the
    /// held end values outside the abscissa range). Used to turn a prescribed velocity into the
    /// displacement it implies.
    pub fn integral(&self, t: f64) -> f64 {
        self.integral_between(0.0, t)
    }

    fn integral_between(&self, a: f64, b: f64) -> f64 {
        if b < a {
            return -self.integral_between(b, a);
        }
        // breakpoints inside (a, b)
        let mut s = 0.0;
        let mut prev = a;
        let mut fprev = self.eval(a);
        for &tk in self.t.iter().filter(|&&tk| tk > a && tk < b) {
            let fk = self.eval(tk);
            s += 0.5 * (fprev + fk) * (tk - prev);
            prev = tk;
            fprev = fk;
        }
        let fb = self.eval(b);
        s + 0.5 * (fprev + fb) * (b - prev)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> Curve {
        Curve {
            id: 1,
            t: vec![0.0, 1.0, 2.0],
            y: vec![0.0, 2.0, 2.0],
        }
    }

    #[test]
    fn interpolates_and_holds_ends() {
        let c = ramp();
        assert_eq!(c.eval(-1.0), 0.0);
        assert_eq!(c.eval(0.5), 1.0);
        assert_eq!(c.eval(1.5), 2.0);
        assert_eq!(c.eval(5.0), 2.0);
    }

    #[test]
    fn integral_is_exact_for_piecewise_linear() {
        let c = ramp();
        assert!((c.integral(1.0) - 1.0).abs() < 1e-15);
        assert!((c.integral(3.0) - 5.0).abs() < 1e-15);
        assert!((c.integral(0.5) - 0.25).abs() < 1e-15);
    }
}
