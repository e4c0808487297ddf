use super::common::scratch;
use cleave_io::output::{plot_histogram, plot_lines, plot_two_axes};
use std::path::Path;

/// Checks that `path` is a 1000 x 700 PNG (signature and IHDR chunk).
fn assert_png(path: &Path) {
    let bytes = std::fs::read(path).unwrap();
    assert!(
        bytes.len() > 1000,
        "{} is only {} bytes",
        path.display(),
        bytes.len()
    );
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((width, height), (1000, 700));
}

fn energy() -> Vec<(&'static str, Vec<(f64, f64)>)> {
    let t = |k: usize| k as f64 * 1e-5;
    let n = 101;
    let kinetic: Vec<_> = (0..n)
        .map(|k| (t(k), 2.5e3 * (-(k as f64) / 30.0).exp()))
        .collect();
    let internal: Vec<_> = kinetic
        .iter()
        .map(|&(t, e)| (t, 0.9 * (2.5e3 - e)))
        .collect();
    let total: Vec<_> = kinetic
        .iter()
        .zip(&internal)
        .map(|(a, b)| (a.0, a.1 + b.1))
        .collect();
    vec![
        ("kinetic", kinetic),
        ("internal", internal),
        ("total", total),
    ]
}

#[test]
fn line_plot_of_normal_data() {
    let dir = scratch("plot_lines");
    let data = energy();
    let series: Vec<(&str, &[(f64, f64)])> = data.iter().map(|(n, s)| (*n, s.as_slice())).collect();
    let path = dir.join("energy.png");
    plot_lines(&path, "Energy", "time (s)", "energy (J)", &series).unwrap();
    assert_png(&path);
}

/// A named list of series for [`plot_lines`].
type Case<'a> = (&'a str, Vec<(&'a str, &'a [(f64, f64)])>);

#[test]
fn line_plot_of_degenerate_data() {
    let dir = scratch("plot_lines_degenerate");
    let nan = f64::NAN;
    let single: &[(f64, f64)] = &[(1.0, 2.0)];
    let constant: &[(f64, f64)] = &[(0.0, 5.0), (1.0, 5.0), (2.0, 5.0)];
    let zeros: &[(f64, f64)] = &[(0.0, 0.0), (1.0, 0.0)];
    let with_nan: &[(f64, f64)] = &[
        (0.0, 1.0),
        (1.0, nan),
        (2.0, 3.0),
        (nan, 1.0),
        (3.0, 2.0),
        (4.0, 2.5),
    ];
    let all_nan: &[(f64, f64)] = &[(nan, nan), (f64::INFINITY, 1.0)];
    let huge: &[(f64, f64)] = &[(0.0, 1e300), (1e-12, -3e299), (2e-12, 2e300)];
    let tiny: &[(f64, f64)] = &[(1e9, 1e-300), (1.0000001e9, 3e-300)];
    let small: &[(f64, f64)] = &[(0.0, 1e-15), (1e-6, 3e-15), (2e-6, -2e-15)];
    let cases: [Case; 10] = [
        ("no_series", vec![]),
        ("empty_series", vec![("nothing", &[])]),
        ("single", vec![("one", single)]),
        ("constant", vec![("flat", constant)]),
        ("zeros", vec![("zero", zeros)]),
        ("nan", vec![("gaps", with_nan), ("all nan", all_nan)]),
        ("huge", vec![("huge", huge)]),
        ("tiny", vec![("tiny", tiny)]),
        ("small", vec![("small", small)]),
        (
            "mixed",
            vec![("one", single), ("nothing", &[]), ("gaps", with_nan)],
        ),
    ];
    for (name, series) in cases {
        let path = dir.join(format!("{name}.png"));
        plot_lines(&path, name, "x", "y", &series).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_png(&path);
    }
}

#[test]
fn two_axis_plot() {
    let dir = scratch("plot_two_axes");
    let area: Vec<(f64, f64)> = (0..50)
        .map(|k| (k as f64 * 2e-6, (k as f64 * 1e-3).powi(2)))
        .collect();
    let fragments: Vec<(f64, f64)> = (0..50).map(|k| (k as f64 * 2e-6, (k / 7) as f64)).collect();
    let path = dir.join("crack.png");
    plot_two_axes(
        &path,
        "Cracks",
        "time (s)",
        ("crack area (m^2)", &area),
        ("fragments", &fragments),
    )
    .unwrap();
    assert_png(&path);
    let path = dir.join("empty.png");
    plot_two_axes(&path, "", "t", ("a", &[]), ("b", &[(f64::NAN, 1.0)])).unwrap();
    assert_png(&path);
    let path = dir.join("single.png");
    plot_two_axes(
        &path,
        "single",
        "t",
        ("a", &[(0.0, 0.0)]),
        ("b", &[(0.0, 3.0), (0.0, 3.0)]),
    )
    .unwrap();
    assert_png(&path);
}

#[test]
fn histograms() {
    let dir = scratch("plot_histogram");
    let masses: Vec<f64> = (1..200)
        .map(|k| 1e-4 * (k as f64 * 0.37).exp().rem_euclid(50.0) + 1e-6)
        .collect();
    let path = dir.join("masses_log.png");
    plot_histogram(
        &path,
        "Fragment masses",
        "mass (kg)",
        "fragments",
        &masses,
        20,
        true,
    )
    .unwrap();
    assert_png(&path);
    let path = dir.join("masses.png");
    plot_histogram(
        &path,
        "Fragment masses",
        "mass (kg)",
        "fragments",
        &masses,
        0,
        false,
    )
    .unwrap();
    assert_png(&path);
    let cases: [(&str, &[f64], bool); 6] = [
        ("empty", &[], false),
        ("empty_log", &[], true),
        ("single", &[3.0], true),
        ("constant", &[2.0, 2.0, 2.0], false),
        ("nan", &[f64::NAN, 1.0, f64::INFINITY, 2.0], false),
        ("non_positive_log", &[-1.0, 0.0, 10.0, 100.0], true),
    ];
    for (name, values, log_x) in cases {
        let path = dir.join(format!("{name}.png"));
        plot_histogram(&path, name, "x", "count", values, 5, log_x)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_png(&path);
    }
}

#[test]
fn unwritable_path_is_an_error_not_a_panic() {
    let path = scratch("plot_error").join("missing-folder").join("x.png");
    let e = plot_lines(&path, "t", "x", "y", &[("a", &[(0.0, 1.0), (1.0, 2.0)])]).unwrap_err();
    assert!(e.to_string().contains("x.png"), "{e}");
    let _: &dyn std::error::Error = &e;
}
