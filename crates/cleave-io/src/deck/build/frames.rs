//! Resolving the CID fields against the deck's `*DEFINE_COORDINATE_...` systems.

use std::collections::HashMap;

use super::Builder;
use crate::deck::error::DeckError;
use crate::deck::raw::Src;

/// How close to the global axes a system's must be to count as them: the axes are unit
/// vectors built from the deck's coordinates, so a system written with exact axis points (what
/// preprocessors write) lands on them to round-off, 1e-15.
const GLOBAL_TOL: f64 = 1e-12;

/// The systems by id: their axes, or why they have none ([`crate::deck::raw::RawFrame`]).
pub type Frames = HashMap<i64, Result<[[f64; 3]; 3], &'static str>>;

impl Builder<'_> {
    /// The deck's systems by id (a repeated id is an error), after checking every CID field
    /// that cleave reads in global axes: its system must exist and have the global axes.
    pub fn frames(&self) -> Result<Frames, DeckError> {
        let raw = self.raw;
        let index: HashMap<i64, usize> =
            self.index(&raw.frames, "coordinate system", |f| (f.id, &f.src))?;
        let frames: Frames = (index.iter())
            .map(|(&id, &k)| (id, raw.frames[k].axes))
            .collect();
        for u in &raw.global_frames {
            let axes = self.frame(&frames, u.cid, &u.src, u.field)?;
            let global = (0..3).all(|i| {
                (0..3).all(|j| {
                    let e = if i == j { 1.0 } else { 0.0 };
                    (axes[i][j] - e).abs() <= GLOBAL_TOL
                })
            });
            if !global {
                return Err(self
                    .err(
                        &u.src,
                        format!(
                            "coordinate system {}: its axes are turned from the global ones, and this card is read in global axes only; give the values in global axes and leave {} blank",
                            u.cid, u.field
                        ),
                    )
                    .with_field(u.field));
            }
        }
        Ok(frames)
    }

    /// The axes of system `cid` (rows: local x, y, z), named by `field` at `src`.
    pub fn frame(
        &self,
        frames: &Frames,
        cid: i64,
        src: &Src,
        field: &str,
    ) -> Result<[[f64; 3]; 3], DeckError> {
        match frames.get(&cid) {
            Some(Ok(axes)) => Ok(*axes),
            Some(Err(why)) => Err(self
                .err(src, format!("coordinate system {cid} {why}"))
                .with_field(field)),
            None => Err(self
                .err(src, format!("coordinate system {cid} is not defined"))
                .with_field(field)),
        }
    }
}
