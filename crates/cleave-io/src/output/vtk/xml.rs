//! Small XML text helpers shared by the VTK writers.

use super::DataArray;
use std::io;

/// The first line and the opening `VTKFile` tag of a VTK XML file of the given `type`.
pub(super) fn vtk_file_open(file_type: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"{file_type}\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
    )
}

/// `text` with the five XML special characters escaped, for attribute values.
pub(super) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

/// Checks that every array of a `PointData` or `CellData` section has `expected` tuples and a
/// unique, non-empty name; `what` names the section in the error.
pub(super) fn check_arrays(
    arrays: &[(&str, DataArray)],
    expected: usize,
    what: &str,
) -> io::Result<()> {
    for (k, (name, array)) in arrays.iter().enumerate() {
        if name.is_empty() {
            return Err(invalid(format!("{what} array {k} has an empty name")));
        }
        if arrays[..k].iter().any(|(other, _)| other == name) {
            return Err(invalid(format!("{what} array name {name:?} is used twice")));
        }
        if array.len() != expected {
            return Err(invalid(format!(
                "{what} array {name:?} has {} tuples, expected {expected}",
                array.len()
            )));
        }
    }
    Ok(())
}

/// Checks that every node index of `cells` is below `points`.
pub(super) fn check_indices<const N: usize>(
    cells: &[[u32; N]],
    points: usize,
    what: &str,
) -> io::Result<()> {
    for (c, cell) in cells.iter().enumerate() {
        if let Some(&n) = cell.iter().find(|&&n| n as usize >= points) {
            return Err(invalid(format!(
                "{what} {c} uses point index {n}, but there are {points} points"
            )));
        }
    }
    Ok(())
}

/// An `InvalidInput` I/O error with `message`.
pub(super) fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}
