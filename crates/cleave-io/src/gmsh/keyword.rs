//! A [`Mesh`] as LS-DYNA keyword text: a `$` header that lists what was read, `*NODE`,
//! `*ELEMENT_SOLID`, and per physical group of dimension 0 to 2 a `*SET_NODE_LIST` (and, for a
//! surface, a `*SET_SEGMENT`), titled with the group's name (`_TITLE`) when it has one. No
//! `*PART`: the deck that includes the mesh defines its parts, sections and materials for the
//! part ids (the physical volume tags) listed in the header.
//!
//! Cards are fixed width with the deck writer's helpers (`deck/write.rs`). A coordinate is
//! written in its shortest form that reads back to the same `f64`; when one of a node's three
//! does not fit a 16-character field that way, that node's card is written comma-separated
//! instead (a free-format card, which LS-DYNA and cleave read within a fixed-format block), so
//! that every coordinate reads back bit for bit (a `-0.0` reads back as `0.0`).

use std::fmt::Write as _;

use super::assemble::dim_name;
use super::mapping::SolidKind;
use super::raw::Version;
use super::Mesh;
use crate::deck::write::{card, fmt_f64, id_cards, names, title_line, F, W10};

/// `tet4 12, hex8 3`: solids per kind.
fn by_kind<'a>(kinds: impl Iterator<Item = &'a SolidKind>) -> String {
    let mut n = std::collections::BTreeMap::new();
    for k in kinds {
        *n.entry(*k).or_insert(0usize) += 1;
    }
    n.iter()
        .map(|(k, c)| format!("{} {c}", k.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

fn quoted(name: &str) -> String {
    if name.is_empty() {
        String::new()
    } else {
        format!(" \"{name}\"")
    }
}

/// What was read from the file `label`, one line each: format, counts per element type,
/// parts and sets. `cleave import` prints these lines and the keyword text starts with them.
pub fn summary(mesh: &Mesh, label: &str) -> Vec<String> {
    let f = &mesh.format;
    let mut out = vec![format!(
        "Gmsh mesh {label}: MSH {} {}",
        match f.version {
            Version::V41 => "4.1",
            Version::V22 => "2.2",
        },
        if f.binary { "binary" } else { "ASCII" }
    )];
    out.push(format!(
        "elements in the file: {}",
        mesh.element_counts
            .iter()
            .map(|(t, n)| {
                let name = super::types::elem_type(*t).map_or("?", |t| t.name);
                format!("{n} x type {t} ({name})")
            })
            .collect::<Vec<_>>()
            .join(", ")
    ));
    out.push(format!("nodes {}", mesh.nodes.len()));
    out.push(format!(
        "solid elements {} ({}); {} turned the right way out",
        mesh.solids.len(),
        by_kind(mesh.solids.iter().map(|s| &s.kind)),
        mesh.reoriented
    ));
    let mut parts: Vec<i64> = mesh.solids.iter().map(|s| s.part).collect();
    parts.sort_unstable();
    parts.dedup();
    for p in parts {
        let name = mesh
            .groups
            .iter()
            .find(|g| g.dim == 3 && g.tag == p)
            .map_or_else(
                || " (volume entity, in no physical volume)".to_string(),
                |g| quoted(&g.name),
            );
        out.push(format!(
            "part {p}{name}: {}",
            by_kind(mesh.solids.iter().filter(|s| s.part == p).map(|s| &s.kind))
        ));
    }
    for g in mesh.groups.iter().filter(|g| g.dim < 3) {
        let mut line = format!(
            "node set {} (physical {}{}): {} nodes",
            g.tag,
            dim_name(g.dim),
            quoted(&g.name),
            g.nodes.len()
        );
        if g.dim == 2 {
            let _ = write!(line, "; segment set {}: {} segments", g.tag, g.faces.len());
        }
        out.push(line);
    }
    out
}

/// True when `v` reads back exactly from at most `w` characters (the deck writer's choice).
fn exact_in(v: f64, w: usize) -> bool {
    v == 0.0 || fmt_f64(v, w).parse::<f64>().ok() == Some(v)
}

/// The keyword text of `mesh`, read from the file `label`.
pub fn keyword_text(mesh: &Mesh, label: &str) -> String {
    let mut o = String::new();
    o.push_str("$ LS-DYNA keywords of a Gmsh mesh, converted by cleave (cleave import)\n");
    for l in summary(mesh, label) {
        let _ = writeln!(o, "$ {l}");
    }
    o.push_str("*KEYWORD\n*NODE\n");
    const NODE: [usize; 6] = [8, 16, 16, 16, 8, 8];
    names(&mut o, &["nid", "x", "y", "z", "tc", "rc"], &NODE);
    for n in &mesh.nodes {
        // the deck writer keeps a blank column in 16-character fields
        if n.x.iter().all(|&v| exact_in(v, 15)) {
            card(
                &mut o,
                &[F::I(n.tag), F::R(n.x[0]), F::R(n.x[1]), F::R(n.x[2])],
                &NODE,
            );
        } else {
            let _ = writeln!(o, "{},{:?},{:?},{:?}", n.tag, n.x[0], n.x[1], n.x[2]);
        }
    }
    o.push_str("*ELEMENT_SOLID\n");
    const ELEM: [usize; 10] = [8; 10];
    names(
        &mut o,
        &["eid", "pid", "n1", "n2", "n3", "n4", "n5", "n6", "n7", "n8"],
        &ELEM,
    );
    for s in &mesh.solids {
        let mut f = vec![F::I(s.tag), F::I(s.part)];
        f.extend(s.nodes.iter().map(|&n| F::I(n)));
        card(&mut o, &f, &ELEM);
    }
    for g in mesh.groups.iter().filter(|g| g.dim < 3) {
        let what = format!("physical {} {}{}", dim_name(g.dim), g.tag, quoted(&g.name));
        let title = title_line(&g.name);
        let head = |o: &mut String, kw: &str| {
            let _ = writeln!(o, "$ {what}");
            if title.trim().is_empty() {
                let _ = writeln!(o, "{kw}");
            } else {
                let _ = writeln!(o, "{kw}_TITLE\n{title}");
            }
            names(o, &["sid"], &W10);
            card(o, &[F::I(g.tag)], &W10);
        };
        head(&mut o, "*SET_NODE_LIST");
        id_cards(&mut o, g.nodes.iter().copied());
        if g.dim == 2 {
            head(&mut o, "*SET_SEGMENT");
            names(&mut o, &["n1", "n2", "n3", "n4"], &W10);
            for f in &g.faces {
                card(&mut o, &f.map(F::I), &W10);
            }
        }
    }
    o.push_str("*END\n");
    o
}
