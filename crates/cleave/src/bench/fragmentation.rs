//! `cleave bench fragmentation [--rates R1,R2,..] [--seeds K] [--elements N] [--threads T]
//! [--spread W] [-o DIR]`: the fragmenting bar of `cleave example fragmenting-bar` over a range of strain
//! rates (default 0.1 to 30 eps_dot0, two and a half decades), K seeds each, in process; the
//! fragment count and mean size against Zhou, Molinari and Ramesh's fit and Grady's energy
//! estimate, and the fracture energy against GC times the area of the opened interfaces.
//!
//! Normalised units (Zhou, Molinari and Ramesh 2005, eq. 16-18): sizes by L0 = E GC / SIGMAX^2,
//! strain rates by eps_dot0 = c SIGMAX^3 / (E^2 GC). Then
//!
//! ```text
//! Zhou, Molinari and Ramesh's fit:            s = 4.5 / (1 + 4.5 eps^(2/3))
//! Grady (1982), energy balance:                s = (24 / eps^2)^(1/3)
//! Glenn and Chudnovsky (1986):                 s = (4 / eps) sinh(asinh(3 eps / 2) / 3)
//! ```
//!
//! (The fit as Zhou, Molinari and Ramesh's later papers and reproductions of their study
//! write it; Glenn and Chudnovsky's estimate adds the strain energy to Grady's kinetic
//! energy balance: it tends to 2 at low rates and to Grady's at high rates.)
//!
//! A fragment is a group of elements held together by interfaces not yet fully open (the
//! fragments of every run: intact and softening interfaces hold); the mean size is the bar's
//! length over their count.
//!
//! Writes DIR/fragmentation.csv (one row per run), DIR/fragmentation.md (a row per rate: mean,
//! range, the fit, Grady) and DIR/fragmentation.png (log-log: size against rate, cleave's mean
//! with the fit and Grady's line).

use std::fmt::Write as _;
use std::path::PathBuf;

use cleave_core::separation::interfaces::Status;
use cleave_core::solver::{Observer, Solver};
use cleave_io::output::plot::plot_lines;

use crate::cli::BenchArgs;
use crate::example::fragmenting_bar::{self, fragmenting_bar, BarSpec, CERAMIC, ELEMENTS_PER_L0};
use crate::failure::{io_failure, Failure};

/// The default strain rates, in units of eps_dot0.
pub const RATES: [f64; 6] = [0.1, 0.3, 1.0, 3.0, 10.0, 30.0];

/// Zhou, Molinari and Ramesh's fit of their mean fragment size (in L0) against the strain rate
/// (in eps_dot0).
pub fn zmr_fit(rate: f64) -> f64 {
    4.5 / (1.0 + 4.5 * rate.powf(2.0 / 3.0))
}

/// Grady's energy-balance fragment size (in L0) at the strain rate `rate` (in eps_dot0):
/// (24 GC / (rho eps_dot^2))^(1/3) = (24 / rate^2)^(1/3) L0.
pub fn grady(rate: f64) -> f64 {
    (24.0 / (rate * rate)).cbrt()
}

/// Glenn and Chudnovsky's fragment size (in L0) at the strain rate `rate` (in eps_dot0).
pub fn glenn_chudnovsky(rate: f64) -> f64 {
    4.0 / rate * ((1.5 * rate).asinh() / 3.0).sinh()
}

/// What one run of the bar gave.
#[derive(Clone, Copy, Debug)]
pub struct BarRun {
    pub rate: f64,
    pub seed: u64,
    pub fragments: usize,
    /// Mean fragment size over L0.
    pub size: f64,
    /// Fracture energy booked by the cohesive laws (J).
    pub fracture_energy: f64,
    /// GC times the area of the interfaces fully open, and of those open or softening (J).
    pub gc_free: f64,
    pub gc_failed: f64,
    pub steps: u64,
    pub seconds: f64,
    /// Fragments half-way through the settling time ([`fragmenting_bar::SETTLE_T0`]), to see
    /// whether the count has stopped changing ([`Self::late_growth`]).
    pub fragments_half: usize,
}

impl BarRun {
    /// How much the count grew over the second half of the settling time, as a fraction of the
    /// final count: 0 once the bar has stopped breaking.
    pub fn late_growth(&self) -> f64 {
        (self.fragments as f64 - self.fragments_half as f64) / self.fragments as f64
    }
}

/// Run the bar of `spec` (its elements given) on `threads` threads.
pub fn run_bar(spec: BarSpec, threads: usize) -> Result<BarRun, Failure> {
    let (rate, seed) = (spec.rate, spec.seed);
    let elements = spec.elements.expect("the bar's elements");
    let model = fragmenting_bar(spec).map_err(Failure::Input)?;
    let t_half = model.control.end_time - 0.5 * fragmenting_bar::SETTLE_T0 * CERAMIC.t0();
    let pool = crate::run::thread_pool(Some(threads))?;
    let prepared = crate::run::prepare(model);
    let (mut solver, _) = crate::run::start_solver(&prepared.model, prepared.interfaces)?;
    let mut half = HalfWay {
        t: t_half,
        fragments: None,
    };
    let start = std::time::Instant::now();
    pool.install(|| solver.run(&mut half))
        .map_err(super::run_failure)?;
    let seconds = start.elapsed().as_secs_f64();
    let fragments = fragment_count(&solver);
    let sep = solver.separation().expect("the bar has a separation group");
    let (mut free, mut failed) = (0.0, 0.0);
    for i in sep.failed_interfaces() {
        let a = sep.faces()[i].area0;
        failed += a;
        if sep.status(i) == Status::Free {
            free += a;
        }
    }
    let gc = CERAMIC.gc;
    Ok(BarRun {
        rate,
        seed,
        fragments,
        size: elements as f64 / ELEMENTS_PER_L0 / fragments as f64,
        fracture_energy: solver.state.energy.fracture,
        gc_free: gc * free,
        gc_failed: gc * failed,
        steps: solver.state.step + 1,
        seconds,
        fragments_half: half.fragments.unwrap_or(0),
    })
}

/// Fragments of the bar now.
fn fragment_count(s: &Solver) -> usize {
    let sep = s.separation().expect("the bar has a separation group");
    sep.fragments(&s.model.conn, s.model.num_nodes()).count
}

/// Counts the fragments once, at the first step at or after `t`.
struct HalfWay {
    t: f64,
    fragments: Option<usize>,
}

impl Observer for HalfWay {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        if self.fragments.is_none() && s.state.t >= self.t {
            self.fragments = Some(fragment_count(s));
        }
        Ok(())
    }
}

/// The strain rates asked for: a comma-separated list, or [`RATES`].
fn rates(list: Option<&str>) -> Result<Vec<f64>, Failure> {
    let Some(list) = list else {
        return Ok(RATES.to_vec());
    };
    list.split(',')
        .map(|r| match r.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
            _ => Err(Failure::Input(format!(
                "--rates: '{r}' is not a positive number (strain rates in units of eps_dot0, comma-separated)"
            ))),
        })
        .collect()
}

pub fn bench_fragmentation(a: &BenchArgs) -> Result<(), Failure> {
    let rates = rates(a.rates.as_deref())?;
    let elements = a
        .elements
        .unwrap_or((fragmenting_bar::LENGTH_L0 * ELEMENTS_PER_L0) as usize);
    if a.seeds == 0 {
        return Err(Failure::Input(
            "--seeds 0: at least one run per rate".into(),
        ));
    }
    let mut runs = Vec::new();
    for &rate in &rates {
        for seed in 1..=a.seeds {
            let spec = BarSpec {
                rate,
                elements: Some(elements),
                spread: a.spread,
                seed,
                tssfac: a.tssfac,
                end_time: None,
            };
            let r = run_bar(spec, a.threads)?;
            eprintln!(
                "fragmentation: rate {rate} eps_dot0, seed {seed}: {} fragments, mean size {:.4} L0 ({} steps, {:.2} s)",
                r.fragments, r.size, r.steps, r.seconds
            );
            runs.push(r);
        }
    }
    let dir = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("fragmentation"));
    std::fs::create_dir_all(&dir).map_err(|e| io_failure("cannot create", &dir, e))?;
    let md = markdown(
        &runs,
        elements,
        a.spread.unwrap_or(fragmenting_bar::SPREAD),
        a.tssfac.unwrap_or(fragmenting_bar::TSSFAC),
    );
    for (name, text) in [
        ("fragmentation.md", &md),
        ("fragmentation.csv", &csv(&runs)),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| io_failure("cannot write", &path, e))?;
    }
    let png = dir.join("fragmentation.png");
    plot(&runs, &png).map_err(|e| io_failure("cannot write", &png, std::io::Error::other(e)))?;
    print!("{md}");
    println!("wrote {}", dir.display());
    Ok(())
}

/// The runs of each rate, in order of rate.
fn by_rate(runs: &[BarRun]) -> Vec<(f64, Vec<&BarRun>)> {
    let mut out: Vec<(f64, Vec<&BarRun>)> = Vec::new();
    for r in runs {
        match out.iter_mut().find(|(rate, _)| *rate == r.rate) {
            Some((_, v)) => v.push(r),
            None => out.push((r.rate, vec![r])),
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// Mean, least and largest of `x`.
fn stats(x: impl Iterator<Item = f64> + Clone) -> (f64, f64, f64) {
    let n = x.clone().count().max(1) as f64;
    let mean = x.clone().sum::<f64>() / n;
    let lo = x.clone().fold(f64::INFINITY, f64::min);
    let hi = x.fold(f64::NEG_INFINITY, f64::max);
    (mean, lo, hi)
}

fn markdown(runs: &[BarRun], elements: usize, spread: f64, tssfac: f64) -> String {
    let m = CERAMIC;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "Fragmenting bar: {elements} elements ({} L0, L0 = {:.4e} m, t0 = {:.4e} s, eps_dot0 = {:.4e} /s), MODEL 3, strengths uniform in [{}, {}] x {:e} Pa, GC {} J/m^2, TSSFAC {tssfac}; sizes in L0, strain rates in eps_dot0.\n",
        elements as f64 / ELEMENTS_PER_L0,
        m.l0(),
        m.t0(),
        m.rate0(),
        1.0 - spread,
        1.0 + spread,
        m.sigma,
        m.gc
    );
    let _ = writeln!(
        o,
        "| strain rate | runs | fragments (mean) | mean size (range) | Zhou-Molinari-Ramesh fit | cleave / fit | Grady | Glenn-Chudnovsky | fracture energy / GC A_open | count's growth over its last half of settling (largest) |"
    );
    let _ = writeln!(o, "|---|---|---|---|---|---|---|---|---|---|");
    for (rate, rs) in by_rate(runs) {
        let (size, lo, hi) = stats(rs.iter().map(|r| r.size));
        let (frags, ..) = stats(rs.iter().map(|r| r.fragments as f64));
        let (ratio, ..) = stats(rs.iter().map(|r| r.fracture_energy / r.gc_free));
        let growth = rs.iter().map(|r| r.late_growth()).fold(0.0, f64::max);
        let _ = writeln!(
            o,
            "| {rate} | {} | {frags:.1} | {size:.3} ({lo:.3}-{hi:.3}) | {:.3} | {:.2} | {:.3} | {:.3} | {ratio:.3} | {:.1}% |",
            rs.len(),
            zmr_fit(rate),
            size / zmr_fit(rate),
            grady(rate),
            glenn_chudnovsky(rate),
            100.0 * growth,
        );
    }
    o
}

fn csv(runs: &[BarRun]) -> String {
    let mut o = String::from(
        "rate,seed,fragments,fragments_half_way,mean_size_l0,zmr_fit_l0,grady_l0,fracture_energy,gc_area_open,gc_area_failed,steps,seconds\n",
    );
    for r in runs {
        let _ = writeln!(
            o,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            r.rate,
            r.seed,
            r.fragments,
            r.fragments_half,
            r.size,
            zmr_fit(r.rate),
            grady(r.rate),
            r.fracture_energy,
            r.gc_free,
            r.gc_failed,
            r.steps,
            r.seconds
        );
    }
    o
}

/// log10 of the mean size against log10 of the rate: cleave, the fit and Grady, the curves on
/// a fine grid over the rates run.
fn plot(runs: &[BarRun], path: &std::path::Path) -> Result<(), String> {
    let groups = by_rate(runs);
    let ours: Vec<(f64, f64)> = groups
        .iter()
        .map(|(rate, rs)| (rate.log10(), stats(rs.iter().map(|r| r.size)).0.log10()))
        .collect();
    let (a, b) = (
        groups.first().map_or(-1.0, |g| g.0.log10()),
        groups.last().map_or(1.0, |g| g.0.log10()),
    );
    let grid = |f: fn(f64) -> f64| -> Vec<(f64, f64)> {
        (0..=50)
            .map(|k| {
                let x = a + (b - a) * k as f64 / 50.0;
                (x, f(10f64.powf(x)).log10())
            })
            .collect()
    };
    let (fit, gr, gcy) = (grid(zmr_fit), grid(grady), grid(glenn_chudnovsky));
    plot_lines(
        path,
        "Fragment size against strain rate",
        "log10(strain rate / eps_dot0)",
        "log10(mean fragment size / L0)",
        &[
            ("cleave (mean of the seeds)", &ours),
            ("Zhou, Molinari, Ramesh fit", &fit),
            ("Grady", &gr),
            ("Glenn, Chudnovsky", &gcy),
        ],
    )
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit and Grady's estimate at rate 1: 4.5 / 5.5 and 24^(1/3); Glenn and Chudnovsky's
    /// tends to 2 at low rates and to Grady's at high rates.
    #[test]
    fn the_curves() {
        assert!((glenn_chudnovsky(1e-6) - 2.0).abs() < 1e-9);
        assert!((glenn_chudnovsky(1e6) / grady(1e6) - 1.0).abs() < 1e-3);
        assert!((zmr_fit(1.0) - 4.5 / 5.5).abs() < 1e-15);
        assert!((grady(1.0) - 24f64.cbrt()).abs() < 1e-15);
        assert!((grady(8.0) - (24.0f64 / 64.0).cbrt()).abs() < 1e-15);
    }

    /// Zhou, Molinari and Ramesh's problem through the solver: the bar of 2000 elements
    /// (100 L0), seed 1, strengths +/- 10%, TSSFAC 0.2 ([`fragmenting_bar::TSSFAC`]), at 0.3, 3
    /// and 10 eps_dot0.
    /// - The mean fragment size lies within 25% of their fit (measured 1.05, 1.13 and 1.18 of it:
    ///   their scatter is not at hand, see the README) and below half of Grady's energy
    ///   estimate.
    /// - At 3 and 10 eps_dot0 the count is within 8% of Akantu's on the same bar (the mean of
    ///   its three seeds, 200.3 and 419.0, whose seeds spread by 3% and 4%:
    ///   `studies/akantu-fragmentation`; measured 1.018 and 0.981).
    /// - The fracture energy booked by the cohesive laws lies between GC times the area of the
    ///   fully open interfaces and GC times that of every interface that started to open (2%
    ///   for the trapezoid of the work over the steps; measured 1.46, 1.52 and 1.52 times the
    ///   former: interfaces that opened part way, as on Akantu, 1.6 at 3 eps_dot0). This bound
    ///   caught the law's earlier defect ([`cleave_core::separation::cohesive::CohesiveLaw::traction`]),
    ///   0.72 at 3 eps_dot0.
    /// - From 3 eps_dot0 on, the count has settled: it grows by less than 2% over the last
    ///   20 t0 (measured 0% and 0%).
    #[test]
    fn fragment_sizes_follow_the_fit_and_the_energy_is_booked() {
        for (rate, akantu) in [(0.3, None), (3.0, Some(200.3)), (10.0, Some(419.0))] {
            let spec = BarSpec {
                rate,
                elements: Some(2000),
                spread: None,
                seed: 1,
                tssfac: None,
                end_time: None,
            };
            let r = run_bar(spec, 1).unwrap();
            let fit = zmr_fit(rate);
            eprintln!(
                "rate {rate}: {} fragments ({} half-way through the settling), size {:.4} L0, fit {fit:.4}, Grady {:.4}; fracture energy {:.4e} J in [{:.4e}, {:.4e}]",
                r.fragments,
                r.fragments_half,
                r.size,
                grady(rate),
                r.fracture_energy,
                r.gc_free,
                r.gc_failed
            );
            assert!((r.size / fit - 1.0).abs() < 0.25, "rate {rate}: {}", r.size);
            assert!(r.size < grady(rate) / 2.0);
            assert!(r.fracture_energy > 0.98 * r.gc_free, "rate {rate}");
            assert!(r.fracture_energy < 1.02 * r.gc_failed, "rate {rate}");
            if rate >= 3.0 {
                assert!(r.late_growth() < 0.02, "rate {rate}: the count has settled");
            }
            if let Some(n) = akantu {
                let ratio = r.fragments as f64 / n;
                eprintln!("rate {rate}: {ratio:.3} of Akantu's count");
                assert!((ratio - 1.0).abs() < 0.08, "rate {rate}: {ratio}");
            }
        }
    }

    #[test]
    fn rates_are_parsed_and_checked() {
        assert_eq!(rates(Some("0.5, 2")).unwrap(), vec![0.5, 2.0]);
        assert_eq!(rates(None).unwrap(), RATES.to_vec());
        assert!(rates(Some("1,-2")).is_err());
        assert!(rates(Some("1,x")).is_err());
    }
}
