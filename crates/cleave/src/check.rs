//! `cleave check DECK.k`: validate a deck and print a model summary without running it.

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
    let setup = Setup::new(m).map_err(Failure::Input)?;
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    println!("deck        {}", a.deck.display());
    if !m.title.is_empty() {
        println!("title       {}", m.title);
    }
    println!("nodes       {}", m.num_nodes());
    println!("elements    {}", m.num_elements());
    println!("parts       {}", m.parts.len());
    for p in &m.parts {
        let mat = &m.materials[p.material];
        let n = m
            .elem_part
            .iter()
            .filter(|&&q| m.parts[q as usize].id == p.id)
            .count();
        let kind = match mat.kind {
            MaterialKind::Elastic => "elastic",
            MaterialKind::PlasticKinematic { .. } => "plastic-kinematic",
            MaterialKind::Rigid { .. } => "rigid",
        };
        println!(
            "  part {:>6}  {:>8} elements  material {} ({kind})  {}",
            p.id,
            n,
            mat.id,
            p.title.trim()
        );
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
    }
    println!("contacts    {}", m.contacts.len());
    println!("rigid walls {}", m.rigid_walls.len());
    println!("rigid bodies {}", setup.rigid.len());
    println!("mass        {:e}", setup.mass.iter().sum::<f64>());
    println!("end time    {:e}", m.control.end_time);
    match estimate_time_step(m) {
        Some((dt, e)) => {
            println!(
                "time step   {:e} (element {}, TSSFAC {})",
                dt, m.elem_ids[e], m.control.tssfac
            );
            println!(
                "steps       about {}",
                (m.control.end_time / dt).ceil() as u64
            );
        }
        None => println!("time step   none: no deformable element"),
    }
    println!("ok");
    Ok(())
}
