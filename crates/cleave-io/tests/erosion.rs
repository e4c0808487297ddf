//! Element erosion (`cleave_core::erosion`) from the deck to the solver: the plastic strain
//! at failure against the analytic uniaxial-strain history, eroded elements carrying nothing
//! (their nodes fly on at constant velocity, their energy booked), the faces they expose
//! stopping an impactor, and the cards cleave refuses.

use cleave_core::contact::ContactSet;
use cleave_core::model::Model;
use cleave_core::solver::Solver;
use cleave_io::deck::{parse_deck, DeckError};

mod blocks;
use blocks::hex_block as block;

fn model(text: &str) -> Model {
    parse_deck(text, "t.k")
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

fn err(text: &str) -> DeckError {
    parse_deck(text, "t.k").expect_err("the deck should be refused")
}

/// Side, pull velocity, E, PR and yield stress of the uniaxial-strain element.
const L: f64 = 0.01;
const V: f64 = 1.0;
const E: f64 = 2.0e11;
const NU: f64 = 0.3;
const SIGY: f64 = 2.0e8;

/// One element in uniaxial strain: every node held in y and z, the x = 0 face in x, the
/// x = L face pulled at V, material card `mat` (MID 1). Returns the time of the step at whose
/// end the element eroded and the largest step. The element takes away the whole internal and
/// hourglass energy, which stops changing afterwards, and its stress is zero.
fn uniaxial_strain_erosion(mat: &str) -> (f64, f64) {
    let (nodes, elems) = block(1, 1, 1, [1, 1, 1], L, [0.0; 3]);
    let deck = format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n3.0e-4\n*PART\nbar\n1, 1, 1\n*SECTION_SOLID\n1, 1\n{mat}\
         *NODE\n{nodes}*ELEMENT_SOLID\n{elems}\
         *SET_NODE_LIST\n1\n1, 3, 5, 7\n*SET_NODE_LIST\n2\n2, 4, 6, 8\n\
         *BOUNDARY_SPC_SET\n1, 0, 1, 1, 1\n*BOUNDARY_SPC_SET\n2, 0, 0, 1, 1\n\
         *BOUNDARY_PRESCRIBED_MOTION_SET\n2, 1, 0, 9, {V}\n*DEFINE_CURVE\n9\n0., 1.\n1., 1.\n*END\n"
    );
    let m = model(&deck);
    assert_eq!(m.erosion.len(), 1);
    let mut s = Solver::new(&m).expect("setup");
    let (mut eroded_at, mut dt_max, mut energy_then) = (None, 0.0f64, None);
    while !s.is_finished() {
        s.advance_to_half_step().expect("step");
        dt_max = dt_max.max(s.state.dt);
        let en = s.state.energy;
        if eroded_at.is_none() && s.eroded_count() == 1 {
            eroded_at = Some(s.state.t);
            energy_then = Some(en.internal + en.hourglass);
            assert!(
                (en.eroded - (en.internal + en.hourglass)).abs() <= 1e-12 * en.eroded,
                "{en:?}"
            );
        }
        s.update_positions().expect("positions");
    }
    let en = s.state.energy;
    assert_eq!(Some(en.internal + en.hourglass), energy_then, "{en:?}");
    assert_eq!(s.state.stress[0], [0.0; 6]);
    (eroded_at.expect("the element eroded"), dt_max)
}

/// In uniaxial strain eps = ln(1 + V t / L), elastic-perfectly-plastic J2 (G, SIGY) reaches
/// the von Mises stress 2 G eps = SIGY at eps_y = SIGY / 2G; from there the whole deviatoric
/// rate is plastic and the effective plastic strain is 2/3 (eps - eps_y) (radial return gives
/// it exactly at each step). With a failure strain FAIL the element erodes at the first step
/// at or after eps* = eps_y + 3/2 FAIL: t* = L (exp(eps*) - 1) / V. Checked for `*MAT_024`
/// FAIL, `*MAT_003` FS, `*MAT_098` PSFAIL and `*MAT_015` damage with D1 = FAIL alone.
#[test]
fn plastic_strain_at_failure_erodes_at_the_analytic_time() {
    let fail = 0.01;
    let g = E / (2.0 * (1.0 + NU));
    let eps: f64 = SIGY / (2.0 * g) + 1.5 * fail;
    let t_star = L * (eps.exp() - 1.0) / V;
    for mat in [
        format!("*MAT_PIECEWISE_LINEAR_PLASTICITY\n1, 7800., {E}, {NU}, {SIGY}, 0., {fail}\n"),
        format!("*MAT_PLASTIC_KINEMATIC\n1, 7800., {E}, {NU}, {SIGY}, 0., 1.\n0., 0., {fail}\n"),
        format!("*MAT_SIMPLIFIED_JOHNSON_COOK\n1, 7800., {E}, {NU}\n{SIGY}, 0., 0., 0., {fail}\n"),
        format!(
            "*MAT_JOHNSON_COOK\n1, 7800., {g}, , {NU}\n{SIGY}, 0., 0., 0., 1., 0., 0., 1.\n\
             0., 0., 0., 0., {fail}\n"
        ),
    ] {
        let (t, dt) = uniaxial_strain_erosion(&mat);
        eprintln!("eroded at {t:.6e} s, analytic {t_star:.6e} s, step {dt:.3e} s");
        assert!(
            t >= t_star * (1.0 - 1e-6) && t <= t_star + dt * 1.001,
            "{mat}: eroded at {t:e}, analytic {t_star:e} (dt {dt:e})"
        );
    }
}

/// The strain criteria of `*MAT_ADD_EROSION` on the same element (elastic): its strain is
/// eps = ln(1 + V t / L) along x and 0 across, so MXEPS erodes it at eps = MXEPS, VOLEPS at
/// eps = VOLEPS (ln V/V0 = eps) and EFFEPS at eps = 3/2 EFFEPS (the deviator's effective
/// strain is 2/3 eps): each at the first step at or after its analytic time.
#[test]
fn strain_criteria_erode_at_the_analytic_time() {
    for (card2, card1_tail, eps) in [
        (", , , 0.01", "", 0.01),
        ("", ", , , 0.012", 0.012),
        ("", ", , 0.008", 1.5 * 0.008),
    ] {
        let mat = format!(
            "*MAT_ELASTIC\n1, 7800., {E}, {NU}\n*MAT_ADD_EROSION\n1, , {card1_tail}\n{card2}\n"
        );
        let t_star = L * (f64::exp(eps) - 1.0) / V;
        let (t, dt) = uniaxial_strain_erosion(&mat);
        assert!(
            t >= t_star * (1.0 - 1e-9) && t <= t_star + dt * 1.001,
            "{mat}: eroded at {t:e}, analytic {t_star:e} (dt {dt:e})"
        );
    }
}

/// Johnson-Cook damage with a triaxiality term (`*MAT_015` D1 0.005, D2 0.02, D3 -0.1): in the
/// same uniaxial strain the mean stress is K eps (K the bulk modulus) and the von Mises stress
/// SIGY once yielding, so s* = K eps / SIGY and the damage is
/// `D(eps) = integral from eps_y to eps of (2/3) de / (D1 + D2 exp(D3 K e / SIGY))`.
/// D = 1 is found by quadrature (10^5 midpoint steps, independent of the solver); the element
/// erodes within two steps of that time (the solver sums each step's increment over the
/// failure strain at its end: the sum lags the integral by less than one increment).
#[test]
fn johnson_cook_damage_follows_the_triaxiality() {
    let (d1, d2, d3) = (0.005, 0.02, -0.1);
    let g = E / (2.0 * (1.0 + NU));
    let k = E / (3.0 * (1.0 - 2.0 * NU));
    let eps_y = SIGY / (2.0 * g);
    let (mut damage, mut e, de) = (0.0, eps_y, 1.0e-7);
    while damage < 1.0 {
        let mid = e + 0.5 * de;
        damage += (2.0 / 3.0) * de / (d1 + d2 * (d3 * k * mid / SIGY).exp());
        e += de;
    }
    let t_star = L * (e.exp() - 1.0) / V;
    let mat = format!(
        "*MAT_JOHNSON_COOK\n1, 7800., {g}, , {NU}\n{SIGY}, 0., 0., 0., 1., 0., 0., 1.\n\
         0., 0., 0., 0., {d1}, {d2}, {d3}, 0.\n0.\n"
    );
    let (t, dt) = uniaxial_strain_erosion(&mat);
    eprintln!("damage 1 at {t:.6e} s, quadrature {t_star:.6e} s (eps {e:.5}), step {dt:.3e} s");
    assert!(
        (t - t_star).abs() <= 2.0 * dt,
        "eroded at {t:e}, quadrature {t_star:e} (dt {dt:e})"
    );
}

/// A block of 3 x 2 x 2 elements squeezed by an initial velocity field (its halves moving
/// towards each other at 5 m/s) erodes completely at FAILTM = 20 us (`*MAT_ADD_EROSION`):
/// from the next step on no force acts, so every node keeps its velocity bit for bit, the
/// momentum stays zero (to round-off) and the kinetic energy constant, and the eroded energy
/// is the internal and hourglass energy at that moment.
#[test]
fn eroded_elements_carry_nothing() {
    let (nodes, elems) = block(1, 1, 1, [3, 2, 2], 0.01, [0.0; 3]);
    let deck = format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n4.0e-5\n*PART\nblock\n1, 1, 1\n*SECTION_SOLID\n1, 1\n\
         *MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*MAT_ADD_EROSION\n1\n0., 0., 0., 0., 0., 0., 0., 2.0e-5\n\
         *NODE\n{nodes}*ELEMENT_SOLID\n{elems}\
         *SET_NODE_LIST_GENERATE\n1\n1, 2\n5, 6\n9, 10\n13, 14\n17, 18\n21, 22\n25, 26\n29, 30\n33, 34\n\
         *SET_NODE_LIST_GENERATE\n2\n3, 4\n7, 8\n11, 12\n15, 16\n19, 20\n23, 24\n27, 28\n31, 32\n35, 36\n\
         *INITIAL_VELOCITY\n1\n5., 0., 0.\n*INITIAL_VELOCITY\n2\n-5., 0., 0.\n*END\n"
    );
    let m = model(&deck);
    let mut s = Solver::new(&m).expect("setup");
    let mut before: Option<(Vec<[f64; 3]>, f64, f64)> = None;
    let mut checked = 0;
    while !s.is_finished() {
        s.advance_to_half_step().expect("step");
        let v: Vec<[f64; 3]> = s.half_step_velocities().iter().copied().collect();
        let en = s.state.energy;
        if s.eroded_count() == 12 {
            match &before {
                None => {
                    assert!(s.state.t >= 2.0e-5);
                    assert!(
                        (en.eroded - (en.internal + en.hourglass)).abs() <= 1e-12 * en.eroded,
                        "{en:?}"
                    );
                    assert!(en.internal > 1e-6, "the block was squeezed: {en:?}");
                }
                Some((v0, ke0, ie0)) => {
                    assert_eq!(&v, v0, "a node's velocity changed after erosion");
                    // the kinetic energy at t^n is 1/2 m v^(n-1/2).v^(n+1/2): constant from
                    // the second step after erosion (the first still holds the last force)
                    if checked > 0 {
                        assert!((en.kinetic - ke0).abs() <= 1e-12 * ke0, "{en:?}");
                    }
                    assert_eq!(en.internal, *ie0);
                    checked += 1;
                }
            }
            before = Some((v, en.kinetic, en.internal));
        } else {
            assert_eq!(s.eroded_count(), 0, "all elements erode in one step");
        }
        s.update_positions().expect("positions");
    }
    assert!(checked > 5, "{checked} steps after erosion");
    let p = s.momentum();
    assert!(p.iter().all(|c| c.abs() < 1e-12), "momentum {p:?}");
}

/// A two-layer slab, its top layer eroding at once (FAILTM 1 ns), and a one-element impactor
/// falling on it at 10 m/s over a footprint that holds none of the top layer's nodes. The
/// faces between the layers are inside the mesh; only because erosion exposes them to the
/// `*CONTACT_ERODING_SINGLE_SURFACE` does the impactor stop on the bottom layer (within 20%
/// of its side) and bounce back.
#[test]
fn faces_erosion_exposes_stop_an_impactor() {
    let h = 0.01;
    let (n1, e1) = block(1, 1, 1, [2, 2, 1], h, [0.0; 3]);
    // the top layer shares the slab's nodes at z = h: its own nodes are 10..18 at z = 2h
    let top: String = (0..2)
        .flat_map(|j| (0..2).map(move |i| (i, j)))
        .enumerate()
        .map(|(k, (i, j))| {
            let b = |i: usize, j: usize| 10 + i + 3 * j;
            format!(
                "{}, 2, {}, {}, {}, {}, {}, {}, {}, {}\n",
                10 + k,
                b(i, j),
                b(i + 1, j),
                b(i + 1, j + 1),
                b(i, j + 1),
                b(i, j) + 9,
                b(i + 1, j) + 9,
                b(i + 1, j + 1) + 9,
                b(i, j + 1) + 9
            )
        })
        .collect();
    let top_nodes: String = (0..9)
        .map(|k| {
            format!(
                "{}, {}, {}, {}\n",
                19 + k,
                h * (k % 3) as f64,
                h * (k / 3) as f64,
                2.0 * h
            )
        })
        .collect();
    let (n3, e3) = block(
        101,
        101,
        3,
        [1, 1, 1],
        0.5 * h,
        [0.25 * h, 0.25 * h, 2.1 * h],
    );
    let deck = format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n2.2e-3\n\
         *PART\nslab\n1, 1, 1\n*PART\ntop\n2, 1, 2\n*PART\nimpactor\n3, 1, 1\n*SECTION_SOLID\n1, 1\n\
         *MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*MAT_ELASTIC\n2, 7800., 2.0e11, 0.3\n\
         *MAT_ADD_EROSION\n2\n0., 0., 0., 0., 0., 0., 0., 1.0e-9\n\
         *NODE\n{n1}{top_nodes}{n3}*ELEMENT_SOLID\n{e1}{top}{e3}\
         *SET_NODE_LIST_GENERATE\n1\n1, 9\n*BOUNDARY_SPC_SET\n1, 0, 1, 1, 1\n\
         *SET_NODE_LIST_GENERATE\n3\n101, 108\n*INITIAL_VELOCITY\n3\n0., 0., -10.\n\
         *CONTACT_ERODING_SINGLE_SURFACE\n0\n*END\n"
    );
    let m = model(&deck);
    let mut s = Solver::new(&m).expect("setup");
    s.attach_contact(ContactSet::new(&m, None).expect("contact"));
    let imp: Vec<usize> = (0..m.node_ids.len())
        .filter(|&k| m.node_ids[k] > 100)
        .collect();
    let mut z_min = f64::INFINITY;
    while !s.is_finished() {
        s.advance_to_half_step().expect("step");
        s.update_positions().expect("positions");
        let x = s.positions();
        for &k in &imp {
            z_min = z_min.min(x[k][2]);
        }
    }
    assert_eq!(s.eroded_count(), 4);
    eprintln!("lowest point of the impactor {:.4} h", z_min / h);
    assert!(z_min > 0.8 * h, "the impactor went down to z = {z_min:e}");
    assert!(
        z_min < 1.05 * h,
        "it never reached the bottom layer: {z_min:e}"
    );
    let vz: f64 = imp.iter().map(|&k| s.velocities()[k][2]).sum::<f64>() / imp.len() as f64;
    eprintln!("impactor's final vz {vz:.3} m/s");
    assert!(vz > 1.0, "the impactor bounced back: vz = {vz}");
}

/// The cards cleave cannot run are refused naming the field.
#[test]
fn refusals() {
    let (nodes, elems) = block(1, 1, 1, [1, 1, 1], 0.01, [0.0; 3]);
    let base = |mat: &str, sec: &str, extra: &str| {
        format!(
            "*KEYWORD\n*CONTROL_TERMINATION\n1.0e-4\n*PART\np\n1, 1, 1\n*SECTION_SOLID\n1, {sec}\n{mat}{extra}\
             *NODE\n{nodes}*ELEMENT_SOLID\n{elems}*END\n"
        )
    };
    let el = "*MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n";
    for (deck, field, want) in [
        (
            base(el, "1", "*MAT_ADD_EROSION\n1\n, , , , 0.1\n"),
            "EPSSH",
            "a shear strain is not supported as an erosion criterion",
        ),
        (
            base(el, "1", "*MAT_ADD_EROSION\n1, , 1.0e9, , , , , 2\n"),
            "NCS",
            "2: the number of criteria that must hold at once is 1 to the 1 given",
        ),
        (
            base(
                "*MAT_PIECEWISE_LINEAR_PLASTICITY\n1, 7800., 2.0e11, 0.3, 2.0e8, 0., -1.\n",
                "1",
                "",
            ),
            "FAIL",
            "a user failure subroutine is not supported",
        ),
        (
            base(
                el,
                "1",
                "*MAT_ADD_EROSION\n1\n,,,,,,,1.0e-3\n*MAT_ADD_SEPARATION\n1, 1, 1.0e8\n",
            ),
            "MID",
            "an element either erodes or separates",
        ),
        (
            base(
                "*MAT_RIGID\n1, 7800., 2.0e11, 0.3\n",
                "1",
                "*MAT_ADD_EROSION\n1\n,,,,,,,1.0e-3\n",
            ),
            "MID",
            "is rigid and cannot erode",
        ),
    ] {
        let e = err(&deck);
        assert_eq!(e.field.as_deref(), Some(field), "{e}");
        assert!(e.to_string().contains(want), "want '{want}' in: {e}");
    }
    // Johnson-Cook damage is read with EFMIN, and not at all with EROD 1
    let jc = "*MAT_JOHNSON_COOK\n1, 7800., 7.7e10, , 0.3\n2.0e8, 0., 0., 0., 1., 0., 0., 1.\n\
              0., 0., 0., 0., 0.1, 0.2, -1.5, 0.01\n0.5, , EROD, 0.02\n";
    let m = model(&base(&jc.replace("EROD", "0"), "1", ""));
    let d = m.erosion[0].rule.johnson_cook.expect("damage");
    assert_eq!((d.d, d.efmin), ([0.1, 0.2, -1.5, 0.01, 0.5], 0.02));
    assert!(model(&base(&jc.replace("EROD", "1"), "1", ""))
        .erosion
        .is_empty());
    // a criterion equal to EXCL is not used; 1234 excludes SIGVM here
    let m = model(&base(
        el,
        "1",
        "*MAT_ADD_EROSION\n1, 1234.\n0., 0., 1234., 0., 0., 0., 0., 1.0e-3\n",
    ));
    let r = &m.erosion[0].rule;
    assert_eq!(
        (r.max_von_mises, r.failure_time, r.ncs),
        (None, Some(1.0e-3), 1)
    );
}
