//! `$MeshFormat`: `version file-type data-size` (ASCII), then, in a binary file, the integer 1
//! in binary to tell the byte order (Gmsh reference manual, "MSH file format").
//!
//! - version: 4.1, or 2.2 (2.0 and 2.1 are read as 2.2); 4.0 and 3.0 are refused with the
//!   option that writes a readable file (`Mesh.MshFileVersion`).
//! - file-type: 0 ASCII, 1 binary.
//! - data-size: in 4.1 the size of a `size_t` (4 or 8 bytes, the width of binary counts and
//!   tags); in 2.2 the size of a floating point number, which must be 8 (`double`).

use super::cursor::{shorten, Cursor};
use super::error::MshError;
use super::raw::Version;

/// Reads the section after its `$MeshFormat` line; sets the cursor's encoding.
pub fn mesh_format(c: &mut Cursor<'_>) -> Result<Version, MshError> {
    let (at, line) = c.line("the format line 'version file-type data-size'")?;
    let f: Vec<&str> = line.split_whitespace().collect();
    let [v, ft, ds] = f[..] else {
        return Err(c.err_at(
            at,
            format!(
                "expected 'version file-type data-size' (e.g. '4.1 0 8'), found '{}'",
                shorten(line)
            ),
        ));
    };
    let version = match v {
        "4.1" => Version::V41,
        "2.2" | "2.1" | "2" | "2.0" => Version::V22,
        _ => {
            return Err(c.err_at(
                at,
                format!(
                    "MSH version {} is not supported: save the mesh as MSH 4.1 or 2.2 (Gmsh option Mesh.MshFileVersion)",
                    shorten(v)
                ),
            ))
        }
    };
    let binary = match ft {
        "0" => false,
        "1" => true,
        _ => {
            return Err(c.err_at(
                at,
                format!(
                    "file-type '{}' is neither 0 (ASCII) nor 1 (binary)",
                    shorten(ft)
                ),
            ))
        }
    };
    if binary {
        let size = match (version, ds) {
            (Version::V41, "4") => 4,
            (Version::V41, "8") => 8,
            (Version::V22, "8") => 8,
            _ => {
                return Err(c.err_at(
                    at,
                    format!(
                        "data-size '{}' is not supported in a binary MSH {} file (4.1: 4 or 8, the size of size_t; 2.2: 8, the size of a double)",
                        shorten(ds),
                        if version == Version::V41 { "4.1" } else { "2.2" }
                    ),
                ))
            }
        };
        c.set_binary(size);
        c.endianness()?;
    }
    c.expect_end("$MeshFormat")?;
    Ok(version)
}
