//! `cleave example NAME`: write a ready deck for a bundled example.
//!
//! | name | what |
//! |---|---|
//! | `taylor-bar` | the classic copper Taylor impact test (LS-DYNA/NAFEMS benchmark): a cylinder of radius 3.2 mm and length 32.4 mm at 227 m/s onto a rigid wall, bilinear plasticity (E 117 GPa, nu 0.35, rho 8930 kg/m^3, SIGY 400 MPa, ETAN 100 MPa), 80 us. Published results: final length about 21.4-21.7 mm, foot radius about 7.0-7.1 mm. |
//! | `ball-impact` | the paper's section 4.1: an alumina ball of 10 mm diameter (O-grid mesh of 256 to 20000 elements as in the paper, or 160000 and 1097440 for scaling runs, `--elements`) at 75 m/s onto and 50 m/s along a rigid steel plate, fracturing by MODEL 1 at 310 MPa, 10 ms ([`ball_impact`](fn@ball_impact)). |
//! | `fragmenting-bar` | a ceramic bar stretched at a uniform strain rate (`--strain-rate`, in units of eps_dot0 = c SIGMAX^3 / (E^2 GC)), every interface cohesive with uniform random strength (`--seed`): Zhou, Molinari and Ramesh's fragmentation problem ([`fragmenting_bar`](fn@fragmenting_bar)). |
//! | `three-point-bend` | the paper's section 4.2: a notched steel beam (200 x 75 x 25 mm, notch 25 mm) hit at mid-span by a rigid tup at a constant 10 m/s, a separation strip ahead of the notch (MODEL 1 at 2 GPa, or `--model 3` cohesive), 0.3 ms ([`three_point_bend`](fn@three_point_bend)). |
//!
//! The builders return the [`Model`](cleave_core::model::Model); `example` applies the options and writes the deck.
//! `--erosion` turns each separation group into element erosion at the same strength (the
//! largest principal stress reaching SIGMAX, `*MAT_ADD_EROSION` SIGP1).
//! `--weibull M [--seed S]` turns the strength of every separation group into the scale of a
//! Weibull distribution of modulus M (`*MAT_ADD_SEPARATION` DIST 2).

pub mod ball_impact;
pub mod fragmenting_bar;
mod taylor_bar;
mod three_point_bend;

use std::path::PathBuf;

pub use ball_impact::ball_impact;
pub use fragmenting_bar::fragmenting_bar;
pub use taylor_bar::taylor_bar_of;
pub use three_point_bend::three_point_bend;

use crate::cli::ExampleArgs;
use crate::failure::Failure;
use cleave_core::element::Shape;
use cleave_core::model::StrengthDist;

/// The bundled examples: name and one-line description.
pub const EXAMPLES: &[(&str, &str)] = &[
    (
        "taylor-bar",
        "copper Taylor bar, 227 m/s onto a rigid wall, bilinear plasticity (4320 elements, 80 us; --shape hex2 runs ELFORM 2; wedge|tet|tet13 cut each into 2 wedges or 6 tetrahedra, ELFORM 10 or 13)",
    ),
    (
        "ball-impact",
        "alumina ball (D 10 mm) at 75 m/s onto a rigid plate, fracture by separation (--elements 256|425|648|2800|8775|20000|160000|1097440, default 2800; 10 ms)",
    ),
    (
        "fragmenting-bar",
        "ceramic bar stretched at a uniform strain rate, every interface cohesive with random strength (--strain-rate R in units of eps_dot0, default 1; --elements, default 2000; --spread W, strengths uniform in (1 -/+ W) x 300 MPa, default 0.1; --seed)",
    ),
    (
        "three-point-bend",
        "notched steel beam hit by a 10 m/s impactor, crack along the centre-line (16408 elements, --model 1|3, 0.3 ms)",
    ),
];

pub fn example(a: &ExampleArgs) -> Result<(), Failure> {
    let Some(name) = a.name.as_deref().filter(|_| !a.list) else {
        for (n, d) in EXAMPLES {
            println!("{n:<18} {d}");
        }
        return Ok(());
    };
    if !EXAMPLES.iter().any(|e| e.0 == name) {
        let names: Vec<&str> = EXAMPLES.iter().map(|e| e.0).collect();
        return Err(Failure::Input(format!(
            "unknown example '{name}'; available: {}",
            names.join(", ")
        )));
    }
    if let Some(t) = a.end_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(Failure::Input(format!(
                "--end-time {t}: must be a positive number"
            )));
        }
    }
    if a.elements.is_some() && name != "ball-impact" && name != "fragmenting-bar" {
        return Err(Failure::Input(format!(
            "--elements applies to ball-impact and fragmenting-bar only, not to {name}"
        )));
    }
    if (a.strain_rate.is_some() || a.spread.is_some()) && name != "fragmenting-bar" {
        return Err(Failure::Input(format!(
            "--strain-rate and --spread apply to fragmenting-bar only, not to {name}"
        )));
    }
    if a.model.is_some() && name != "three-point-bend" {
        return Err(Failure::Input(format!(
            "--model applies to three-point-bend only, not to {name}"
        )));
    }
    let (shape, elform) = match (a.shape.as_deref(), name) {
        (None, _) => (Shape::Hex, 1),
        (Some(s), "taylor-bar") => match s {
            "hex" => (Shape::Hex, 1),
            "hex2" => (Shape::Hex, 2),
            "wedge" => (Shape::Wedge, 1),
            "tet" => (Shape::Tet, 10),
            "tet13" => (Shape::Tet, 13),
            other => {
                return Err(Failure::Input(format!(
                    "--shape {other}: one of hex, hex2, wedge, tet, tet13"
                )))
            }
        },
        (Some(_), _) => {
            return Err(Failure::Input(format!(
                "--shape applies to taylor-bar only, not to {name}"
            )))
        }
    };
    let mut model = match name {
        "taylor-bar" => {
            let mut m = taylor_bar_of(shape, elform);
            if let Some(t) = a.end_time {
                m.control.end_time = t;
            }
            m
        }
        "ball-impact" => ball_impact(
            a.elements.unwrap_or(ball_impact::DEFAULT_ELEMENTS),
            a.end_time.unwrap_or(ball_impact::END_TIME),
        )
        .map_err(Failure::Input)?,
        "fragmenting-bar" => fragmenting_bar(fragmenting_bar::BarSpec {
            rate: a.strain_rate.unwrap_or(1.0),
            elements: a.elements,
            spread: a.spread,
            seed: a.seed,
            tssfac: None,
            end_time: a.end_time,
        })
        .map_err(Failure::Input)?,
        _ => three_point_bend(
            a.model.unwrap_or(1),
            a.end_time.unwrap_or(three_point_bend::END_TIME),
        )
        .map_err(Failure::Input)?,
    };
    if let Some(m) = a.weibull {
        if !(m.is_finite() && m > 0.0) {
            return Err(Failure::Input(format!(
                "--weibull {m}: the modulus must be a positive number"
            )));
        }
        if model.separations.is_empty() {
            return Err(Failure::Input(format!(
                "--weibull: {name} has no separation group"
            )));
        }
        for s in &mut model.separations {
            s.strength = StrengthDist::Weibull {
                m,
                aref: 0.0,
                smin: 0.0,
                seed: a.seed,
            };
        }
    }
    if a.erosion {
        if model.separations.is_empty() || a.no_separation || a.weibull.is_some() {
            return Err(Failure::Input(format!(
                "--erosion turns {name}'s separation groups into erosion: it needs some, and goes with neither --no-separation nor --weibull"
            )));
        }
        model.erosion = model
            .separations
            .drain(..)
            .map(|s| cleave_core::erosion::ErosionDef {
                material: s.material,
                rule: cleave_core::erosion::ErosionRule {
                    max_principal: Some(s.sigmax),
                    ncs: 1,
                    ..Default::default()
                },
            })
            .collect();
    }
    if a.no_separation {
        model.separations.clear();
    }
    let path = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{name}.k")));
    std::fs::write(&path, cleave_io::deck::write_deck(&model))
        .map_err(|e| crate::failure::io_failure("cannot write", &path, e))?;
    println!(
        "wrote {} ({} elements, {} nodes); run it with: cleave run {}",
        path.display(),
        model.num_elements(),
        model.num_nodes(),
        path.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::model::Model;

    /// What the generators build is what the deck says: written and read back, every example
    /// gives the same model (coordinates to the 9 to 10 significant digits that the deck's
    /// 16-character fields hold).
    #[test]
    fn decks_read_back_as_the_models_built() {
        let models: Vec<(&str, Model)> = vec![
            ("taylor-bar", taylor_bar_of(Shape::Hex, 1)),
            ("taylor-bar tet", taylor_bar_of(Shape::Tet, 13)),
            ("taylor-bar wedge", taylor_bar_of(Shape::Wedge, 1)),
            ("ball 256", ball_impact(256, 1e-5).unwrap()),
            ("ball 2800", ball_impact(2800, 10e-3).unwrap()),
            ("bend 1", three_point_bend(1, 0.3e-3).unwrap()),
            ("bend 3", three_point_bend(3, 0.3e-3).unwrap()),
        ];
        for (what, m) in models {
            let back = cleave_io::deck::parse_deck(&cleave_io::deck::write_deck(&m), what)
                .unwrap_or_else(|e| panic!("{what}: {e}"))
                .model;
            assert_eq!(m.title, back.title, "{what}");
            assert_eq!(m.node_ids, back.node_ids, "{what}");
            assert_eq!(m.elem_ids, back.elem_ids, "{what}");
            assert_eq!(m.conn, back.conn, "{what}");
            assert_eq!(m.elem_part, back.elem_part, "{what}");
            assert_eq!(m.parts, back.parts, "{what}");
            assert_eq!(m.sections, back.sections, "{what}");
            assert_eq!(m.materials, back.materials, "{what}");
            assert_eq!(m.separations, back.separations, "{what}");
            assert_eq!(m.contacts, back.contacts, "{what}");
            assert_eq!(m.curves, back.curves, "{what}");
            assert_eq!(m.prescribed, back.prescribed, "{what}");
            assert_eq!(m.v0, back.v0, "{what}");
            assert_eq!(m.control, back.control, "{what}");
            assert_eq!(m.rigid_walls, back.rigid_walls, "{what}");
            let o = (&m.output, &back.output);
            assert_eq!(o.0.history_nodes, o.1.history_nodes, "{what}");
            assert_eq!(o.0.history_solids, o.1.history_solids, "{what}");
            for (a, b) in [
                (o.0.glstat_dt, o.1.glstat_dt),
                (o.0.d3plot_dt, o.1.d3plot_dt),
                (o.0.nodout_dt, o.1.nodout_dt),
                (o.0.rcforc_dt, o.1.rcforc_dt),
            ] {
                assert!((a - b).abs() <= 1e-9 * a, "{what}: {a} vs {b}");
            }
            for (a, b) in m.x0.iter().zip(&back.x0) {
                let close = a
                    .iter()
                    .zip(b)
                    .all(|(p, q)| (p - q).abs() <= 1e-9 * p.abs() + 1e-15);
                assert!(close, "{what}: {a:?} vs {b:?}");
            }
        }
    }
}
