//! Interface strengths: one per interface, drawn once before the run from its group's
//! distribution ([`StrengthDist`]).
//!
//! # The draw
//!
//! A counter-based draw: the uniform variate of an interface is a hash of the group's seed and
//! the deck ids of its two elements (the smaller first), not the next number of a stream. So
//! an interface gets the same strength whatever order the interfaces are built in, on any
//! number of threads, on the GPU, and after a restart; renumbering the interfaces or adding
//! elements elsewhere does not change it. The hash is the SplitMix64 output function (Steele,
//! Lea and Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014; the mixing
//! constants of Stafford's variant 13), applied in a chain:
//!
//! ```text
//! h = mix(mix(mix(seed) ^ id_lo) ^ id_hi),   U = (floor(h / 2^11) + 1/2) / 2^53  in (0, 1)
//! ```
//!
//! # The distributions
//!
//! ```text
//! DIST 1, uniform:  s = SMIN + (SMAX - SMIN) U
//! DIST 2, Weibull:  s = SMIN + SIGMAX (-ln U  AREF / A)^(1/M)       (AREF = 0: A / AREF = 1)
//! ```
//!
//! The Weibull draw inverts P_f(s) = 1 - exp(-(A / AREF) ((s - SMIN) / SIGMAX)^M), the weakest
//! link law of a face of area A made of A / AREF independent pieces of area AREF (Weibull
//! 1951): a face four times larger is weaker by 4^(-1/M) in the median, so a mesh refined
//! across a crack plane keeps the plane's strength distribution. Its mean is
//! SMIN + SIGMAX (AREF / A)^(1/M) Gamma(1 + 1/M).
//!
//! # Where two groups meet
//!
//! An interface between elements of two different separation groups draws a strength from
//! each group (each with its own seed) and takes the weaker one; that group's criterion and
//! cohesive law govern the interface (the first element's group on a tie). A crack runs through
//! the weaker of two bonded materials. An interface between a group and an element of no
//! group is its group's.

use crate::model::StrengthDist;

/// The SplitMix64 output function: a bijection of u64 whose output bits each depend on every
/// input bit.
#[inline]
pub fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The uniform variate in (0, 1) of the interface between elements with deck ids `a` and `b`
/// (in either order) for `seed`.
pub fn uniform(seed: u64, a: i64, b: i64) -> f64 {
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    let h = mix(mix(mix(seed) ^ lo as u64) ^ hi as u64);
    ((h >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
}

/// The strength (Pa) of an interface of reference area `area` between the elements with deck
/// ids `a` and `b`, in a group of strength (or Weibull scale) `sigmax` and distribution `dist`.
pub fn draw(sigmax: f64, dist: &StrengthDist, area: f64, a: i64, b: i64) -> f64 {
    match *dist {
        StrengthDist::Constant => sigmax,
        StrengthDist::Uniform { smin, smax, seed } => smin + (smax - smin) * uniform(seed, a, b),
        StrengthDist::Weibull {
            m,
            aref,
            smin,
            seed,
        } => {
            let size = if aref > 0.0 { aref / area } else { 1.0 };
            smin + sigmax * (-uniform(seed, a, b).ln() * size).powf(1.0 / m)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gamma(x) for x > 1/2 (Lanczos, g = 7, 9 terms: 1e-15 relative), for the Weibull mean.
    fn gamma(x: f64) -> f64 {
        const C: [f64; 9] = [
            0.999_999_999_999_809_9,
            676.520_368_121_885_1,
            -1_259.139_216_722_402_8,
            771.323_428_777_653_1,
            -176.615_029_162_140_6,
            12.507_343_278_686_905,
            -0.138_571_095_265_720_12,
            9.984_369_578_019_572e-6,
            1.505_632_735_149_311_6e-7,
        ];
        let x = x - 1.0;
        let mut a = C[0];
        let t = x + 7.5;
        for (i, c) in C.iter().enumerate().skip(1) {
            a += c / (x + i as f64);
        }
        (2.0 * std::f64::consts::PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * a
    }

    #[test]
    fn gamma_is_right() {
        assert!((gamma(5.0) - 24.0).abs() < 1e-12);
        assert!((gamma(1.5) - 0.5 * std::f64::consts::PI.sqrt()).abs() < 1e-14);
    }

    /// The draw depends on the seed and the pair only, in either order.
    #[test]
    fn the_draw_is_a_function_of_seed_and_pair() {
        assert_eq!(uniform(7, 3, 9), uniform(7, 9, 3));
        assert_ne!(uniform(7, 3, 9), uniform(8, 3, 9));
        assert_ne!(uniform(7, 3, 9), uniform(7, 3, 10));
        assert_ne!(uniform(7, 3, 9), uniform(7, 4, 9));
    }

    /// 10^5 uniform variates over neighbouring element pairs (as a mesh numbers them): mean
    /// 1/2 and variance 1/12 within 4 standard errors (sd of the mean 0.289 / sqrt(n) =
    /// 9.1e-4; of the variance's estimate sqrt(1/180 / n) = 2.4e-4), and each of 20 bins
    /// within 4 sd of n / 20 (sd sqrt(n p (1 - p)) = 69). The lag-one correlation of
    /// consecutive pairs is within 4 / sqrt(n) of 0.
    #[test]
    fn uniform_variates_are_uniform_and_uncorrelated() {
        let n = 100_000;
        let u: Vec<f64> = (0..n as i64).map(|i| uniform(1, i, i + 1)).collect();
        let mean = u.iter().sum::<f64>() / n as f64;
        let var = u.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 4.0 * 9.1e-4, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 4.0 * 2.4e-4, "variance {var}");
        let mut bins = [0usize; 20];
        for &x in &u {
            assert!(x > 0.0 && x < 1.0);
            bins[(x * 20.0) as usize] += 1;
        }
        for b in bins {
            assert!((b as f64 - 5000.0).abs() < 4.0 * 69.0, "bin count {b}");
        }
        let r = u
            .windows(2)
            .map(|w| (w[0] - 0.5) * (w[1] - 0.5))
            .sum::<f64>()
            / (n as f64 * var);
        assert!(r.abs() < 4.0 / (n as f64).sqrt(), "lag-one correlation {r}");
    }

    /// Uniform strengths lie within the bounds with the mean of the bounds.
    #[test]
    fn uniform_strengths_lie_between_the_bounds() {
        let d = StrengthDist::Uniform {
            smin: 100.0,
            smax: 300.0,
            seed: 5,
        };
        let s: Vec<f64> = (0..20_000).map(|i| draw(0.0, &d, 1.0, i, i + 7)).collect();
        assert!(s.iter().all(|&x| (100.0..300.0).contains(&x)));
        let mean = s.iter().sum::<f64>() / s.len() as f64;
        // sd of the mean 200 / sqrt(12 n) = 0.41
        assert!((mean - 200.0).abs() < 4.0 * 0.41, "mean {mean}");
    }

    /// Weibull strengths follow their distribution: the Kolmogorov-Smirnov distance of 20,000
    /// draws to P_f(s) = 1 - exp(-((s - smin) / S)^m) is below 1.63 / sqrt(n) (the 1% level),
    /// and with size scaling the mean of faces of area A is S (AREF / A)^(1/m) Gamma(1 + 1/m)
    /// within 4 standard errors.
    #[test]
    fn weibull_strengths_follow_their_distribution() {
        let (scale, m, smin) = (200e6, 6.0, 50e6);
        let n = 20_000;
        let d = StrengthDist::Weibull {
            m,
            aref: 0.0,
            smin,
            seed: 11,
        };
        let mut s: Vec<f64> = (0..n as i64)
            .map(|i| draw(scale, &d, 1.0, 2 * i, 2 * i + 1))
            .collect();
        s.sort_by(f64::total_cmp);
        let mut ks: f64 = 0.0;
        for (k, &x) in s.iter().enumerate() {
            let p = 1.0 - (-((x - smin) / scale).powf(m)).exp();
            ks = ks
                .max((p - k as f64 / n as f64).abs())
                .max((p - (k + 1) as f64 / n as f64).abs());
        }
        assert!(ks < 1.63 / (n as f64).sqrt(), "KS distance {ks}");

        let (aref, area) = (1e-6, 4e-6);
        let d = StrengthDist::Weibull {
            m,
            aref,
            smin: 0.0,
            seed: 12,
        };
        let s: Vec<f64> = (0..n as i64)
            .map(|i| draw(scale, &d, area, i, -i - 1))
            .collect();
        let mean = s.iter().sum::<f64>() / n as f64;
        let sd = (s.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
        let expect = scale * (aref / area).powf(1.0 / m) * gamma(1.0 + 1.0 / m);
        assert!(
            (mean - expect).abs() < 4.0 * sd / (n as f64).sqrt(),
            "mean {mean} against {expect}"
        );
    }

    /// The weakest-link size effect: a bar of N equal interfaces in series (uniform tension)
    /// fails at its weakest one, and the mean of that minimum over many bars is
    /// S N^(-1/m) Gamma(1 + 1/m), i.e. it scales as (L_ref / L)^(1/m) with the bar's length.
    /// 400 bars of each length (N = 10, 40, 160): each mean within 4 standard errors of the
    /// law, and the fitted slope of ln(mean) against ln N within 4 standard errors of -1/m.
    #[test]
    fn weakest_link_size_effect() {
        let (scale, m) = (300e6, 8.0);
        let d = StrengthDist::Weibull {
            m,
            aref: 0.0,
            smin: 0.0,
            seed: 3,
        };
        let bars = 400;
        let mut pts = Vec::new();
        for (b0, n) in [(0i64, 10i64), (100_000, 40), (200_000, 160)] {
            let mins: Vec<f64> = (0..bars)
                .map(|b| {
                    let first = b0 + b * (n + 1);
                    (0..n)
                        .map(|k| draw(scale, &d, 1.0, first + k, first + k + 1))
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
            let mean = mins.iter().sum::<f64>() / bars as f64;
            let sd = (mins.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / bars as f64).sqrt();
            let se = sd / (bars as f64).sqrt();
            let expect = scale * (n as f64).powf(-1.0 / m) * gamma(1.0 + 1.0 / m);
            assert!(
                (mean - expect).abs() < 4.0 * se,
                "N {n}: mean {mean} against {expect} (se {se})"
            );
            pts.push(((n as f64).ln(), mean.ln(), se / mean));
        }
        // slope through the end points; its error from the two relative standard errors
        let slope = (pts[2].1 - pts[0].1) / (pts[2].0 - pts[0].0);
        let err = (pts[0].2.powi(2) + pts[2].2.powi(2)).sqrt() / (pts[2].0 - pts[0].0);
        assert!(
            (slope + 1.0 / m).abs() < 4.0 * err,
            "slope {slope} against {}",
            -1.0 / m
        );
    }
}
