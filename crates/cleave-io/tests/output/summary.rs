use super::common::scratch;
use cleave_io::output::Summary;

fn sample() -> Summary {
    Summary {
        elements: 2800,
        nodes: 3375,
        nodes_solved: 22400,
        interfaces: 7960,
        failed_interfaces: 412,
        fragments: 17,
        eroded_elements: 3,
        crack_initiation_time: Some(1.34e-4),
        crack_speed_mean: None,
        steps: 123_456_789_012,
        end_time: 1e-3,
        wall_seconds: 12.5,
        us_per_element_step: 0.0375,
        peak_rss_mb: 81.25,
        device: "cpu".into(),
        threads: 2,
        energy_ratio: 0.9987,
        status: "finished".into(),
        version: "0.1.0".into(),
        warnings: vec!["a warning".into()],
    }
}

/// The keys the interface page lists for `summary.json`, and the crack's and `warnings`.
const KEYS: [&str; 20] = [
    "elements",
    "nodes",
    "nodes_solved",
    "interfaces",
    "failed_interfaces",
    "fragments",
    "eroded_elements",
    "crack_initiation_time",
    "crack_speed_mean",
    "steps",
    "end_time",
    "wall_seconds",
    "us_per_element_step",
    "peak_rss_mb",
    "threads",
    "device",
    "energy_ratio",
    "status",
    "version",
    "warnings",
];

#[test]
fn json_has_every_key_and_parses_back() {
    let path = scratch("summary").join("summary.json");
    let s = sample();
    s.write(&path).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let object = v.as_object().unwrap();
    for key in KEYS {
        assert!(object.contains_key(key), "missing {key}");
    }
    assert_eq!(object.len(), KEYS.len());
    assert_eq!(v["steps"].as_u64(), Some(123_456_789_012));
    assert_eq!(v["elements"].as_u64(), Some(2800));
    assert_eq!(v["end_time"].as_f64(), Some(1e-3));
    assert_eq!(v["energy_ratio"].as_f64(), Some(0.9987));
    assert_eq!(v["version"].as_str(), Some("0.1.0"));
    assert_eq!(v["warnings"][0].as_str(), Some("a warning"));
}

#[test]
fn non_finite_floats_become_null() {
    let s = Summary {
        energy_ratio: f64::NAN,
        us_per_element_step: f64::INFINITY,
        ..sample()
    };
    let v: serde_json::Value = serde_json::from_str(&s.to_json()).unwrap();
    assert!(v["energy_ratio"].is_null());
    assert!(v["us_per_element_step"].is_null());
    assert_eq!(v["threads"].as_u64(), Some(2));
}

#[test]
fn peak_rss_is_plausible() {
    let mb = cleave_io::output::peak_rss_mb();
    if cfg!(target_os = "linux") {
        assert!(mb > 0.5 && mb < 1e6, "peak RSS {mb} MiB");
    } else {
        assert!(mb >= 0.0);
    }
}
