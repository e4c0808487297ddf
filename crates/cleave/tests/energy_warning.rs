//! A run whose energy balance fails warns (stderr and summary.json `warnings`), one that keeps
//! it does not.
//!
//! The case is a public one-hexahedron rig (Samos9877/lsdyna-agent-test, uniaxial unconfined
//! compression, see `corpus/README.md`), here with E = 210 so that it runs in a second: the top
//! face is pushed down 70% of the side. At 53% the compressive stress reaches 2G, where the
//! hypoelastic (Jaumann-rate) update loses stability: the top face shears back and forth, the
//! stress stops growing while the prescribed motion keeps working, and the energy ratio falls
//! to 0.50. To 40% compression (t = 0.57) the balance holds (to 8e-7).

mod common;

use common::{cleave, tmp};

const RIG: &str = "*KEYWORD
*CONTROL_TERMINATION
ENDTIM
*CONTROL_TIMESTEP
0.0, 0.9
*DATABASE_GLSTAT
0.01
*PART
unit_cube
1, 1, 99
*SECTION_SOLID
1, 1
*MAT_ELASTIC
99, 7.850E-9, 210.0, 0.3
*NODE
1, 0.0, 0.0, 0.0
2, 1.0, 0.0, 0.0
3, 1.0, 1.0, 0.0
4, 0.0, 1.0, 0.0
5, 0.0, 0.0, 1.0
6, 1.0, 0.0, 1.0
7, 1.0, 1.0, 1.0
8, 0.0, 1.0, 1.0
*ELEMENT_SOLID
1, 1, 1, 2, 3, 4, 5, 6, 7, 8
*BOUNDARY_SPC_NODE
1, 0, 1, 1, 1
2, 0, 0, 1, 1
3, 0, 0, 0, 1
4, 0, 1, 0, 1
*BOUNDARY_PRESCRIBED_MOTION_SET
1, 3, 2, 1, 1.0
*SET_NODE_LIST
1
5, 6, 7, 8
*DEFINE_CURVE
1
0.0, 0.0
1.0, -0.7
*END
";

fn summary(dir: &std::path::Path, end: &str) -> serde_json::Value {
    let deck = dir.join(format!("rig-{end}.k"));
    std::fs::write(&deck, RIG.replace("ENDTIM", end)).unwrap();
    let out = dir.join(format!("out-{end}"));
    let o = cleave(&[
        "run",
        deck.to_str().unwrap(),
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_run_that_loses_its_energy_balance_says_so() {
    let d = tmp("energy-warning");
    let bad = summary(&d, "1.0");
    let ratio = bad["energy_ratio"].as_f64().unwrap();
    assert!(ratio < 0.6, "energy ratio {ratio}");
    let w = bad["warnings"].as_array().unwrap();
    assert!(
        w.iter()
            .any(|w| w.as_str().unwrap().contains("the energy ratio reached 0.4")),
        "{w:?}"
    );
    let good = summary(&d, "0.57");
    let ratio = good["energy_ratio"].as_f64().unwrap();
    assert!((ratio - 1.0).abs() < 1e-5, "energy ratio {ratio}");
    let w = good["warnings"].as_array().unwrap();
    assert!(
        !w.iter()
            .any(|w| w.as_str().unwrap().contains("energy ratio")),
        "{w:?}"
    );
}
