//! `cleave check DECK.k`: validate a deck and print a model summary without running it.
//!
//! It validates what `cleave run` does before its first step, with the same functions and so
//! the same messages (a deck `check` accepts is not refused by `run`): the deck reader, the
//! ParaView state cap, the split of the separation groups and the solver with its interfaces
//! and contact definitions ([`crate::run::prepare`], [`crate::run::start_solver`]; a segment
//! set whose segment is no element face is refused there).

use cleave_core::element::Shape;
use cleave_core::model::MaterialKind;
use cleave_core::setup::{estimate_time_step, Setup};

use crate::cli::CheckArgs;
use crate::failure::Failure;

pub fn check(a: &CheckArgs) -> Result<(), Failure> {
    let d = cleave_io::deck::read_deck(&a.deck)?;
    for w in &d.warnings {
        eprintln!("warning: {w}");
    }
    let m = &d.model;
    crate::run::state_cap(m)?;
    let setup = Setup::new(m).map_err(Failure::Input)?;
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    // what `run` builds before its first step, refused as `run` refuses it
    {
        let prepared = crate::run::prepare(m.clone());
        let (_, warnings) = crate::run::start_solver(&prepared.model, prepared.interfaces)?;
        for w in warnings.iter().filter(|w| !setup.warnings.contains(w)) {
            eprintln!("warning: {w}");
        }
    }
    println!("deck        {}", a.deck.display());
    if d.files.len() > 1 {
        println!("files       {}", d.files.join(", "));
    }
    let kw: Vec<String> = d
        .keywords
        .iter()
        .map(|(k, n)| {
            if *n == 1 {
                k.clone()
            } else {
                format!("{k} x{n}")
            }
        })
        .collect();
    println!("keywords    {}", kw.join(", "));
    println!(
        "warnings    {}",
        if d.warnings.is_empty() {
            "none".to_string()
        } else {
            format!("{} (above)", d.warnings.len())
        }
    );
    if !m.title.is_empty() {
        println!("title       {}", m.title);
    }
    println!("nodes       {}", m.num_nodes());
    println!("elements    {}", m.num_elements());
    println!("parts       {}", m.parts.len());
    for (pi, p) in m.parts.iter().enumerate() {
        let mat = &m.materials[p.material];
        // elements of each shape in the part
        let mut shapes = [0usize; 3];
        for (e, _) in m
            .elem_part
            .iter()
            .enumerate()
            .filter(|(_, &q)| q as usize == pi)
        {
            shapes[setup.elem_shape[e] as usize] += 1;
        }
        let n: usize = shapes.iter().sum();
        let elform = m.sections[p.section].elform;
        let form: Vec<String> = [Shape::Hex, Shape::Wedge, Shape::Tet]
            .iter()
            .zip(shapes)
            .filter(|(_, k)| *k > 0)
            .map(|(s, k)| {
                let how = match (s, elform) {
                    (Shape::Tet, 13) => "tetrahedron with nodal pressure averaging",
                    (Shape::Tet, _) => "one-point tetrahedron",
                    (Shape::Hex, 2) => "fully integrated selectively reduced hexahedron",
                    (Shape::Wedge, _) => "degenerate one-point hexahedron",
                    _ => "one-point hexahedron",
                };
                format!("{k} {} ({how})", if k == 1 { s.name() } else { s.plural() })
            })
            .collect();
        let kind = match mat.kind {
            MaterialKind::Elastic => "elastic",
            MaterialKind::PlasticKinematic { .. } => "plastic-kinematic",
            MaterialKind::JohnsonCook(_) => "johnson-cook",
            MaterialKind::PiecewiseLinear(_) => "piecewise-linear-plasticity",
            MaterialKind::Rigid { .. } => "rigid",
        };
        println!(
            "  part {:>6}  {:>8} elements  material {} ({kind})  {}",
            p.id,
            n,
            mat.id,
            p.title.trim()
        );
        if !form.is_empty() {
            println!(
                "              section {} ELFORM {elform}: {}",
                m.sections[p.section].id,
                form.join(", ")
            );
        }
    }
    println!("materials   {}", m.materials.len());
    println!("separation  {} group(s)", m.separations.len());
    if !m.separations.is_empty() {
        let split = cleave_core::separation::split::split_model(m);
        println!(
            "interfaces  {} (nodes after splitting: {})",
            split.interfaces,
            split.model.num_nodes()
        );
        for (g, d) in m.separations.iter().enumerate() {
            let s: Vec<f64> = split.faces[..split.interfaces]
                .iter()
                .filter(|f| f.group as usize == g)
                .map(|f| f.strength)
                .collect();
            let (lo, hi) = s
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
            println!(
                "  group {}: material {}, MODEL {}, strength {}; {} interfaces, strength {}",
                g + 1,
                m.materials[d.material].id,
                d.model,
                describe_strength(d),
                s.len(),
                if s.is_empty() {
                    "-".to_string()
                } else {
                    format!("min {lo:.4e} mean {mean:.4e} max {hi:.4e}")
                }
            );
        }
    }
    if !m.erosion.is_empty() {
        println!("erosion     {} material(s)", m.erosion.len());
        for d in &m.erosion {
            let r = &d.rule;
            let mut what: Vec<String> = Vec::new();
            let mut add = |name: &str, v: Option<f64>| {
                if let Some(v) = v {
                    what.push(format!("{name} {v:e}"));
                }
            };
            add("plastic strain", r.plastic_strain);
            add("pressure >=", r.max_pressure);
            add("pressure <=", r.min_pressure);
            add("max principal stress >=", r.max_principal);
            add("von Mises stress >=", r.max_von_mises);
            add("time >=", r.failure_time);
            add("max principal strain >=", r.max_principal_strain);
            add("min principal strain <=", r.min_principal_strain);
            add("effective strain >=", r.effective_strain);
            add("volumetric strain reaching", r.volumetric_strain);
            if let Some(d) = r.johnson_cook {
                what.push(format!(
                    "Johnson-Cook damage 1 (D1..D5 {:?}, EFMIN {:e})",
                    d.d, d.efmin
                ));
            }
            let ncs = if r.criteria() > 1 {
                format!(" ({} of the *MAT_ADD_EROSION criteria at once)", r.ncs)
            } else {
                String::new()
            };
            println!(
                "  material {}: erodes at {}{ncs}",
                m.materials[d.material].id,
                what.join(", ")
            );
        }
    }
    println!("contacts    {}", m.contacts.len());
    if !m.tied.is_empty() {
        let ties = cleave_core::tied::Ties::new(m).map_err(Failure::Input)?;
        println!(
            "tied        {} contact(s): {} slave nodes tied",
            m.tied.len(),
            ties.ties.len()
        );
        for (id, n) in ties.untied.iter().filter(|u| u.1 > 0) {
            println!("  contact {id}: {n} slave node(s) find no master face and stay free");
        }
    }
    println!("rigid walls {}", m.rigid_walls.len());
    println!("rigid bodies {}", setup.rigid.len());
    for b in &setup.rigid {
        let what = match b.of {
            cleave_core::rigid::BodyOf::Part(_) => "part",
            cleave_core::rigid::BodyOf::Nodal(_) => "nodal rigid body",
        };
        println!(
            "  {what} {}: {} nodes, mass {:e}, centre ({:e}, {:e}, {:e}){}",
            b.id,
            b.nodes.len(),
            b.mass,
            b.x_cm0[0],
            b.x_cm0[1],
            b.x_cm0[2],
            if b.unlumped.is_some() {
                ", given inertia"
            } else {
                ""
            }
        );
    }
    // the given masses of *PART_INERTIA bodies are carried by no node
    let given: f64 = setup
        .rigid
        .iter()
        .filter_map(|b| b.unlumped.as_ref().map(|u| u.mass))
        .sum();
    println!("mass        {:e}", setup.mass.iter().sum::<f64>() + given);
    // whether `run --gpu` would take the deck, and if not, the first thing it lacks
    match cleave_gpu::support::unsupported(m, &setup) {
        None => println!("gpu         runs with --gpu"),
        Some(what) => println!("gpu         --gpu does not run {what} yet"),
    }
    println!("end time    {:e}", m.control.end_time);
    match estimate_time_step(m) {
        Some((dt, e)) if dt > 0.0 && dt.is_finite() => {
            println!(
                "time step   {:e} (element {}, TSSFAC {})",
                dt, m.elem_ids[e], m.control.tssfac
            );
            println!("steps       about {:.0}", (m.control.end_time / dt).ceil());
        }
        Some((dt, e)) => {
            // run stops at its first step on this element (exit 3); check says so first
            eprintln!(
                "warning: element {} allows no time step ({dt:e}): it is degenerate or its material is; `cleave run` will stop at once",
                m.elem_ids[e]
            );
            println!(
                "time step   none usable: element {} gives {dt:e}",
                m.elem_ids[e]
            );
        }
        None => println!("time step   none: no deformable element"),
    }
    println!("ok");
    Ok(())
}

/// A group's strength distribution in words, with its parameters.
fn describe_strength(d: &cleave_core::model::SeparationDef) -> String {
    use cleave_core::model::StrengthDist;
    match d.strength {
        StrengthDist::Constant => format!("SIGMAX {:e}", d.sigmax),
        StrengthDist::Uniform { smin, smax, seed } => {
            format!("uniform in [{smin:e}, {smax:e}], seed {seed}")
        }
        StrengthDist::Weibull {
            m,
            aref,
            smin,
            seed,
        } => format!(
            "Weibull, scale {:e}, modulus {m}, threshold {smin:e}, {}, seed {seed}",
            d.sigmax,
            if aref > 0.0 {
                format!("reference area {aref:e}")
            } else {
                "no size scaling".to_string()
            }
        ),
    }
}
