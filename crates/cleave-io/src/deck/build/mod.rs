//! Second pass: resolving the deck ids of a [`RawDeck`] into the dense indices of a
//! [`Model`], checking every reference, duplicate id and element geometry.
//!
//! Indices follow the order of appearance in the deck (nodes, elements, parts, materials,
//! sections, curves and sets alike).

mod conditions;
mod eos;
mod frames;
mod mesh;

use std::collections::HashMap;

use cleave_core::model::Model;

use super::error::DeckError;
use super::raw::{RawDeck, Src};

/// Builds and validates the model; returns it with the warnings of the build.
pub fn build(raw: RawDeck, file: &str) -> Result<(Model, Vec<String>), DeckError> {
    if raw.elems.is_empty() {
        return Err(DeckError::deck(
            file,
            "the deck defines no elements (*ELEMENT_SOLID): nothing to run",
        ));
    }
    let mut model = Model {
        title: raw.title.clone(),
        control: raw.control.clone(),
        ..Model::default()
    };
    let b = Builder {
        raw: &raw,
        warnings: Default::default(),
    };
    let ids = b.mesh(&mut model)?;
    b.conditions(&mut model, &ids)?;
    if let Some((id, src)) = &raw.lctm {
        let k = b.find(&ids.curves, *id, src, "LCTM", "curve")?;
        let c = &model.curves[k];
        if c.y.iter().any(|&y| y.is_nan() || y < 0.0) {
            return Err(b
                .err(
                    src,
                    format!(
                        "curve {id} (LCTM): a largest time step must not be negative (0: no limit)"
                    ),
                )
                .with_field("LCTM"));
        }
        model.control.dt_max_curve = Some(k);
    }
    if raw.termination.is_none() {
        return Err(DeckError::deck(
            file,
            "no *CONTROL_TERMINATION with a positive ENDTIM: the run has no end time",
        ));
    }
    Ok((model, b.warnings.into_inner()))
}

/// Deck id to index maps of everything that can be referenced.
#[derive(Default)]
pub struct Ids {
    pub nodes: HashMap<i64, u32>,
    pub elems: HashMap<i64, u32>,
    pub parts: HashMap<i64, usize>,
    pub sections: HashMap<i64, usize>,
    pub materials: HashMap<i64, usize>,
    pub curves: HashMap<i64, usize>,
    pub node_sets: HashMap<i64, usize>,
    pub part_sets: HashMap<i64, usize>,
    pub segment_sets: HashMap<i64, usize>,
    pub solid_sets: HashMap<i64, usize>,
}

pub struct Builder<'a> {
    pub raw: &'a RawDeck,
    /// What the build found worth saying (one line each, naming file and line).
    pub warnings: std::cell::RefCell<Vec<String>>,
}

impl Builder<'_> {
    /// Adds a warning.
    pub fn warn(&self, message: String) {
        self.warnings.borrow_mut().push(message);
    }

    /// An error at an item's line (in the file it was read from).
    pub fn err(&self, src: &Src, message: impl Into<String>) -> DeckError {
        DeckError::at(&src.file, src.line, Some(&src.keyword), message)
    }

    /// The id to index map of `items`; a repeated id is an error naming both lines.
    pub fn index<T, I: TryFrom<usize>>(
        &self,
        items: &[T],
        what: &str,
        key: impl Fn(&T) -> (i64, &Src),
    ) -> Result<HashMap<i64, I>, DeckError> {
        let mut map: HashMap<i64, I> = HashMap::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let (id, src) = key(item);
            let Ok(idx) = I::try_from(i) else {
                return Err(self.err(src, format!("too many {what}s")));
            };
            if map.insert(id, idx).is_some() {
                let first = items.iter().map(&key).find(|(k, _)| *k == id).map_or(
                    String::new(),
                    |(_, s)| {
                        if s.file == src.file {
                            format!("line {}", s.line)
                        } else {
                            format!("{}:{}", s.file, s.line)
                        }
                    },
                );
                return Err(self.err(
                    src,
                    format!("{what} {id} is defined twice (first at {first})"),
                ));
            }
        }
        Ok(map)
    }

    /// Looks up a reference; an undefined id is an error naming the id, the field and the line.
    pub fn find<I: Copy>(
        &self,
        map: &HashMap<i64, I>,
        id: i64,
        src: &Src,
        field: &str,
        what: &str,
    ) -> Result<I, DeckError> {
        map.get(&id).copied().ok_or_else(|| {
            self.err(src, format!("{what} {id} is not defined"))
                .with_field(field)
        })
    }
}
