//! The walk over an MSH file's sections: `$MeshFormat` first, then `$PhysicalNames`,
//! `$Entities` (4.1), `$Nodes` and `$Elements` read, any other section (`$PartitionedEntities`,
//! `$Periodic`, `$NodeData`, ...) skipped to its `$End` line by name.

use super::cursor::{shorten, Cursor};
use super::error::MshError;
use super::raw::{RawMsh, Version};
use super::{format, names, v2, v4};

/// Reads every section of `bytes` (the file `file`).
pub fn read(file: &str, bytes: &[u8]) -> Result<RawMsh, MshError> {
    let mut c = Cursor::new(file, bytes);
    let not_msh = |c: &Cursor<'_>, at: usize| {
        c.err_at(
            at,
            "not a Gmsh MSH file: it does not start with $MeshFormat",
        )
    };
    if c.at_end() {
        return Err(MshError::file(file, "the file is empty"));
    }
    let first = c.mark();
    let (at, line) = c.line("$MeshFormat").map_err(|_| not_msh(&c, first))?;
    if line != "$MeshFormat" {
        return Err(not_msh(&c, at));
    }
    let version = format::mesh_format(&mut c)?;
    let mut raw = RawMsh {
        version,
        binary: c.is_binary(),
        names: Vec::new(),
        entities: None,
        nodes: Vec::new(),
        elems: Vec::new(),
    };
    let mut seen: Vec<&str> = Vec::new();
    while !c.at_end() {
        let (at, name) = c.line("a section name")?;
        if !name.starts_with('$') || name.starts_with("$End") || name.len() < 2 {
            return Err(c.err_at(
                at,
                format!("expected a section ($Name), found '{}'", shorten(name)),
            ));
        }
        let known = matches!(
            name,
            "$MeshFormat" | "$PhysicalNames" | "$Entities" | "$Nodes" | "$Elements"
        );
        if known && seen.contains(&name) {
            return Err(c.err_at(at, format!("a second {name} section")));
        }
        match name {
            "$MeshFormat" => return Err(c.err_at(at, "a second $MeshFormat section")),
            "$PhysicalNames" => raw.names = names::physical_names(&mut c)?,
            "$Entities" if version == Version::V41 => raw.entities = Some(v4::entities(&mut c)?),
            "$Nodes" if version == Version::V41 => raw.nodes = v4::nodes(&mut c)?,
            "$Nodes" => raw.nodes = v2::nodes(&mut c)?,
            "$Elements" if version == Version::V41 => raw.elems = v4::elements(&mut c)?,
            "$Elements" => raw.elems = v2::elements(&mut c)?,
            _ => c.skip_section(name, at)?,
        }
        if known {
            seen.push(name);
        }
    }
    for s in ["$Nodes", "$Elements"] {
        if !seen.contains(&s) {
            return Err(MshError::file(file, format!("the file has no {s} section")));
        }
    }
    Ok(raw)
}
