//! `$PhysicalNames`: a count, then one line per group, `dimension tag "name"` (ASCII in binary
//! files too; Gmsh reference manual, "MSH file format").

use super::cursor::{shorten, Cursor};
use super::error::MshError;
use super::raw::RawName;

/// Reads the section after its `$PhysicalNames` line.
pub fn physical_names(c: &mut Cursor<'_>) -> Result<Vec<RawName>, MshError> {
    let n = c.ascii_count("the number of physical names")?;
    let mut out = Vec::new();
    for _ in 0..n {
        let (at, line) = c.line("a physical name line 'dimension tag \"name\"'")?;
        let bad = |why: &str| {
            c.err_at(
                at,
                format!(
                    "{why}: expected 'dimension tag \"name\"', found '{}'",
                    shorten(line)
                ),
            )
        };
        let quote = line
            .find('"')
            .ok_or_else(|| bad("the name is not in double quotes"))?;
        let (head, rest) = line.split_at(quote);
        let mut it = head.split_whitespace();
        let dim = it
            .next()
            .and_then(|d| d.parse::<u8>().ok())
            .filter(|d| *d <= 3)
            .ok_or_else(|| bad("the dimension is not 0, 1, 2 or 3"))?;
        let tag = it
            .next()
            .and_then(|t| t.parse::<i64>().ok())
            .ok_or_else(|| bad("the tag is not an integer"))?;
        if it.next().is_some() {
            return Err(bad("more than two numbers before the name"));
        }
        let name = rest
            .strip_prefix('"')
            .and_then(|r| r.strip_suffix('"'))
            .ok_or_else(|| bad("the name is not in double quotes"))?;
        out.push(RawName {
            dim,
            tag,
            name: name.to_string(),
        });
    }
    c.expect_end("$PhysicalNames")?;
    Ok(out)
}
