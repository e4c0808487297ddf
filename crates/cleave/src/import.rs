//! `cleave import MESH.msh [-o MESH.k]`: a Gmsh mesh as LS-DYNA keyword text (nodes, solids,
//! node and segment sets; `cleave_io::gmsh` has the rules), with a `$` header listing what was
//! read, which is also printed. The text is what a deck's `*INCLUDE` of the .msh reads.

use crate::cli::ImportArgs;
use crate::failure::{io_failure, Failure};

pub fn import(a: &ImportArgs) -> Result<(), Failure> {
    let label = a.mesh.display().to_string();
    let out = a.out.clone().unwrap_or_else(|| a.mesh.with_extension("k"));
    if out == a.mesh {
        return Err(Failure::Input(format!(
            "{}: the output would overwrite the mesh; name another with -o",
            out.display()
        )));
    }
    let mesh = cleave_io::gmsh::read_msh(&a.mesh).map_err(|e| Failure::Input(e.to_string()))?;
    let text = cleave_io::gmsh::keyword_text(&mesh, &label);
    std::fs::write(&out, text).map_err(|e| io_failure("cannot write", &out, e))?;
    for l in cleave_io::gmsh::summary(&mesh, &label) {
        println!("{l}");
    }
    println!("written {}", out.display());
    Ok(())
}
