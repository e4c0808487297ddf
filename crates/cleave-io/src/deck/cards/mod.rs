//! Decoding each supported keyword's cards into a [`RawDeck`] (first pass: no references are
//! resolved here, so the order of keywords in the deck does not matter).
//!
//! Card layouts follow the LS-DYNA Keyword User's Manual (Vol. I); each decoder's doc comment
//! gives its layout.

mod constrained;
mod control;
mod curve;
mod eos;
mod erosion;
mod frames;
mod interaction;
mod johnson_cook;
mod loads;
mod material;
mod mesh;
mod piecewise;
mod sets;
mod transform;

use std::rc::Rc;

use super::error::DeckError;
use super::fields::{Card, Format};
use super::lex::{Block, Line};
use super::params::Params;
use super::raw::{RawDeck, Src};

/// Decodes every block. Unsupported keywords are errors; `*TITLE`, `*COMMENT` and unknown
/// `*DATABASE_...` keywords are accepted (the latter with a warning, their data skipped).
/// `params` are the whole deck's (`Params::read`).
pub fn read_blocks<'a>(blocks: &[&'a Block<'a>], params: &'a Params) -> Result<RawDeck, DeckError> {
    let mut deck = RawDeck::default();
    // a `*DEFINE_TABLE` read and how many of its curves are still to come (they must follow
    // it: its id, values, line)
    let mut table_curves: Option<(i64, usize, usize, usize)> = None;
    for &block in blocks {
        let kw = block.keyword.as_str();
        if let Some((id, n, left, line)) = table_curves {
            if kw.starts_with("*DEFINE_CURVE") {
                table_curves = (left > 1).then_some((id, n, left - 1, line));
            } else if kw != "*COMMENT" {
                return Err(DeckError::at(
                    &block.file,
                    block.line,
                    Some(kw),
                    format!("*DEFINE_TABLE {id} (line {line}) has {n} values, so the {n} keywords after it must be its *DEFINE_CURVEs; {} found here (use *DEFINE_TABLE_2D to name the curves instead)", n - left),
                ));
            }
        }
        let (base, titled) = match kw.strip_suffix("_TITLE") {
            Some(b)
                if b.starts_with("*MAT_")
                    || b.starts_with("*EOS_")
                    || b.starts_with("*SECTION_")
                    || b.starts_with("*SET_")
                    || b.starts_with("*BOUNDARY_")
                    || b.starts_with("*CONTACT_")
                    || b == "*DEFINE_CURVE"
                    || b == "*DEFINE_TRANSFORMATION"
                    || b == "*DEFINE_TABLE"
                    || b == "*DEFINE_TABLE_2D"
                    || b == "*DEFINE_VECTOR"
                    || b.starts_with("*DEFINE_COORDINATE_") =>
            {
                (b, true)
            }
            _ => (kw, false),
        };
        // the `_ID` option of boundary conditions and contacts (what LS-PrePost writes): a
        // first card `ID HEADING`, read past as a title
        let (base, titled) = match base.strip_suffix("_ID") {
            Some(b) if !titled && (b.starts_with("*BOUNDARY_") || b.starts_with("*CONTACT_")) => {
                (b, true)
            }
            _ => (base, titled),
        };
        let mut r = Reader::new(block, params);
        if titled {
            r.title()?;
        }
        match base {
            "*KEYWORD" | "*COMMENT" => continue,
            "*DEFINE_COORDINATE_SYSTEM" => frames::system(&mut r, &mut deck)?,
            "*DEFINE_COORDINATE_VECTOR" => frames::vector(&mut r, &mut deck)?,
            "*DEFINE_COORDINATE_NODES" => frames::nodes(&mut r, &mut deck)?,
            "*DEFINE_VECTOR" => frames::direction(&mut r, &mut deck)?,
            // read before every other card (`Params::read`)
            "*PARAMETER"
            | "*PARAMETER_DUPLICATION"
            | "*PARAMETER_LOCAL"
            | "*PARAMETER_EXPRESSION"
            | "*PARAMETER_EXPRESSION_LOCAL" => continue,
            "*TITLE" if r.at_end() => deck.title.clear(),
            "*TITLE" => deck.title = r.title()?,
            "*NODE" => mesh::node(&mut r, &mut deck)?,
            "*ELEMENT_SOLID" => mesh::element_solid(&mut r, &mut deck)?,
            "*PART" => mesh::part(&mut r, &mut deck, false)?,
            "*PART_INERTIA" => mesh::part(&mut r, &mut deck, true)?,
            k if k.starts_with("*CONSTRAINED_") => constrained::constrained(&mut r, &mut deck)?,
            "*SECTION_SOLID" => mesh::section_solid(&mut r, &mut deck, titled)?,
            "*HOURGLASS" => control::hourglass_def(&mut r, &mut deck)?,
            "*MAT_ELASTIC" | "*MAT_001" => material::elastic(&mut r, &mut deck, titled)?,
            "*MAT_PLASTIC_KINEMATIC" | "*MAT_003" => {
                material::plastic_kinematic(&mut r, &mut deck)?
            }
            "*MAT_RIGID" | "*MAT_020" => material::rigid(&mut r, &mut deck)?,
            "*MAT_PIECEWISE_LINEAR_PLASTICITY" | "*MAT_024" => {
                piecewise::piecewise_linear(&mut r, &mut deck)?
            }
            "*MAT_JOHNSON_COOK" | "*MAT_015" => johnson_cook::johnson_cook(&mut r, &mut deck)?,
            "*MAT_ELASTIC_PLASTIC_HYDRO" | "*MAT_010" => {
                johnson_cook::elastic_plastic_hydro(&mut r, &mut deck)?
            }
            "*MAT_SIMPLIFIED_JOHNSON_COOK" | "*MAT_098" => {
                johnson_cook::simplified(&mut r, &mut deck)?
            }
            "*MAT_ADD_SEPARATION" => material::separation(&mut r, &mut deck)?,
            "*MAT_ADD_EROSION" => erosion::add_erosion(&mut r, &mut deck)?,
            "*EOS_LINEAR_POLYNOMIAL" => eos::linear_polynomial(&mut r, &mut deck)?,
            "*EOS_GRUNEISEN" => eos::gruneisen(&mut r, &mut deck)?,
            "*SET_NODE_LIST" => sets::node_list(&mut r, &mut deck)?,
            "*SET_NODE_GENERAL" => sets::node_general(&mut r, &mut deck)?,
            "*SET_PART_LIST" | "*SET_PART" => sets::part_list(&mut r, &mut deck)?,
            "*SET_SEGMENT" => sets::segment(&mut r, &mut deck)?,
            "*SET_NODE_LIST_GENERATE" => sets::node_generate(&mut r, &mut deck)?,
            "*SET_SOLID" | "*SET_SOLID_LIST" => sets::solid_list(&mut r, &mut deck)?,
            "*SET_SOLID_GENERATE" | "*SET_SOLID_LIST_GENERATE" => {
                sets::solid_generate(&mut r, &mut deck)?
            }
            "*SET_PART_LIST_GENERATE" => sets::part_generate(&mut r, &mut deck)?,
            "*DEFINE_CURVE" => curve::define_curve(&mut r, &mut deck)?,
            "*DEFINE_TABLE" => {
                curve::define_table(&mut r, &mut deck, false)?;
                let t = deck.tables.last().expect("just read");
                let n = t.values.len();
                table_curves = Some((t.id, n, n, block.line));
            }
            "*DEFINE_TABLE_2D" => curve::define_table(&mut r, &mut deck, true)?,
            "*DEFINE_TRANSFORMATION" => transform::define_transformation(&mut r, &mut deck)?,
            "*INCLUDE_TRANSFORM" => transform::include_transform(&mut r, &mut deck, block.group)?,
            "*INITIAL_VELOCITY_GENERATION" => loads::velocity_generation(&mut r, &mut deck)?,
            "*INITIAL_VELOCITY_NODE" => loads::velocity_node(&mut r, &mut deck)?,
            "*INITIAL_VELOCITY" => loads::velocity(&mut r, &mut deck)?,
            "*BOUNDARY_SPC_NODE" => loads::spc(&mut r, &mut deck, false)?,
            "*BOUNDARY_SPC_SET" => loads::spc(&mut r, &mut deck, true)?,
            "*BOUNDARY_PRESCRIBED_MOTION_NODE"
            | "*BOUNDARY_PRESCRIBED_MOTION_SET"
            | "*BOUNDARY_PRESCRIBED_MOTION_RIGID" => loads::prescribed(&mut r, &mut deck)?,
            "*LOAD_NODE_POINT" => loads::node_load(&mut r, &mut deck, false)?,
            "*LOAD_NODE_SET" => loads::node_load(&mut r, &mut deck, true)?,
            "*LOAD_SEGMENT" => loads::segment_load(&mut r, &mut deck)?,
            "*LOAD_SEGMENT_SET" => loads::segment_set_load(&mut r, &mut deck)?,
            "*LOAD_BODY_X" => loads::body(&mut r, &mut deck, 0)?,
            "*LOAD_BODY_Y" => loads::body(&mut r, &mut deck, 1)?,
            "*LOAD_BODY_Z" => loads::body(&mut r, &mut deck, 2)?,
            k if k.starts_with("*RIGIDWALL_PLANAR") => {
                interaction::rigidwall_planar(&mut r, &mut deck)?
            }
            k if k.starts_with("*RIGIDWALL_GEOMETRIC_") => {
                interaction::rigidwall_geometric(&mut r, &mut deck)?
            }
            "*CONTACT_TIED_SURFACE_TO_SURFACE" | "*CONTACT_TIED_NODES_TO_SURFACE" => {
                interaction::tied(&mut r, &mut deck)?
            }
            // the eroding contacts: cleave's contacts all take the faces erosion exposes
            // (`ContactSet::erode`); their card 4 (ISYM EROSOP IADJ) is not read
            "*CONTACT_ERODING_SINGLE_SURFACE" => {
                interaction::contact(&mut r, &mut deck, true, false)?
            }
            "*CONTACT_ERODING_SURFACE_TO_SURFACE" => {
                interaction::contact(&mut r, &mut deck, false, false)?
            }
            "*CONTACT_ERODING_NODES_TO_SURFACE" => {
                interaction::contact(&mut r, &mut deck, false, true)?
            }
            "*CONTACT_AUTOMATIC_SINGLE_SURFACE" => {
                interaction::contact(&mut r, &mut deck, true, false)?
            }
            "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE" => {
                interaction::contact(&mut r, &mut deck, false, false)?
            }
            "*CONTACT_AUTOMATIC_NODES_TO_SURFACE" => {
                interaction::contact(&mut r, &mut deck, false, true)?
            }
            "*CONTACT_FORCE_TRANSDUCER_PENALTY" => {
                deck.warnings.push(format!(
                    "{}:{}: {kw}: force transducer output is not written, ignored",
                    block.file, block.line
                ));
                r.ignore_rest();
            }
            k if k.starts_with("*CONTROL_") || k.starts_with("*DATABASE_") => {
                control::control_or_database(&mut r, &mut deck)?
            }
            _ => {
                return Err(DeckError::at(
                    &block.file,
                    block.line,
                    Some(kw),
                    "keyword not supported (see the supported keyword list in the README)",
                ))
            }
        }
        r.finish()?;
    }
    if let (Some((id, n, left, line)), Some(b)) = (table_curves, blocks.last()) {
        return Err(DeckError::at(
            &b.file,
            line,
            Some("*DEFINE_TABLE"),
            format!(
                "table {id} has {n} values but only {} *DEFINE_CURVE follow it",
                n - left
            ),
        ));
    }
    Ok(deck)
}

/// A cursor over a block's data lines.
pub struct Reader<'a> {
    pub file: &'a str,
    file_rc: Rc<str>,
    pub keyword: &'a str,
    kw_rc: Rc<str>,
    block_line: usize,
    lines: &'a [Line<'a>],
    pos: usize,
    params: &'a Params,
    /// The layout of the block's fixed-format cards.
    pub format: Format,
}

impl<'a> Reader<'a> {
    fn new(block: &'a Block<'a>, params: &'a Params) -> Self {
        Self {
            file: &block.file,
            file_rc: block.file.clone(),
            keyword: &block.keyword,
            kw_rc: Rc::from(block.keyword.as_str()),
            block_line: block.line,
            lines: &block.lines,
            pos: 0,
            params,
            format: block.format.unwrap_or_default(),
        }
    }

    /// Provenance of an item read at `line`.
    pub fn src(&self, line: usize) -> Src {
        Src {
            file: self.file_rc.clone(),
            keyword: self.kw_rc.clone(),
            line,
        }
    }

    /// Line of the keyword itself.
    pub fn line_of_keyword(&self) -> usize {
        self.block_line
    }

    /// The lines not read yet.
    pub fn remaining(&self) -> &'a [Line<'a>] {
        &self.lines[self.pos.min(self.lines.len())..]
    }

    /// An error at the keyword's line.
    pub fn error_at_keyword(&self, message: impl Into<String>) -> DeckError {
        DeckError::at(self.file, self.block_line, Some(self.keyword), message)
    }

    /// Text of the line most recently returned as a card.
    pub fn current_text(&self) -> &'a str {
        self.pos
            .checked_sub(1)
            .and_then(|i| self.lines.get(i))
            .map_or("", |l| l.text)
    }

    /// Whether every line has been consumed.
    pub fn at_end(&self) -> bool {
        self.pos >= self.lines.len()
    }

    /// Skips blank lines.
    pub fn skip_blank(&mut self) {
        while self.lines.get(self.pos).is_some_and(|l| l.is_blank()) {
            self.pos += 1;
        }
    }

    /// The next line as a card (a blank line is a card of defaults); `None` at the end.
    pub fn next(&mut self, widths: &'static [usize]) -> Result<Option<Card<'a>>, DeckError> {
        match self.lines.get(self.pos) {
            None => Ok(None),
            Some(&l) => {
                self.pos += 1;
                Card::in_format(self.file, self.keyword, l, widths, self.format)?
                    .substitute(self.params)
                    .map(Some)
            }
        }
    }

    /// The next non-blank line as a card; `None` at the end (for repeated cards).
    pub fn next_nonblank(
        &mut self,
        widths: &'static [usize],
    ) -> Result<Option<Card<'a>>, DeckError> {
        self.skip_blank();
        self.next(widths)
    }

    /// The next line as a card, which must exist; `what` names its fields for the message.
    pub fn required(
        &mut self,
        widths: &'static [usize],
        what: &str,
    ) -> Result<Card<'a>, DeckError> {
        let line = self.lines.last().map_or(self.block_line, |l| l.no);
        self.next(widths)?.ok_or_else(|| {
            DeckError::at(
                self.file,
                line,
                Some(self.keyword),
                format!("missing card ({what})"),
            )
        })
    }

    /// The next line as a card, or a card of defaults (at the keyword's line) if there is
    /// none: for keywords whose only card may be omitted.
    pub fn card_or_defaults(&mut self, widths: &'static [usize]) -> Result<Card<'a>, DeckError> {
        match self.next(widths)? {
            Some(c) => Ok(c),
            None => Ok(Card::in_format(
                self.file,
                self.keyword,
                Line {
                    no: self.block_line,
                    text: "",
                },
                widths,
                self.format,
            )?),
        }
    }

    /// The next line as a title (free text, at most 80 characters, 160 in the long layout;
    /// never split at commas).
    pub fn title(&mut self) -> Result<String, DeckError> {
        let line = self.lines.last().map_or(self.block_line, |l| l.no);
        match self.lines.get(self.pos) {
            None => Err(DeckError::at(
                self.file,
                line,
                Some(self.keyword),
                "missing title line",
            )),
            Some(l) => {
                self.pos += 1;
                Ok(l.text
                    .chars()
                    .take(self.format.columns(&[80], 1))
                    .collect::<String>()
                    .trim()
                    .to_string())
            }
        }
    }

    /// Ignores up to `n` further lines (optional cards this reader does not use).
    pub fn ignore(&mut self, n: usize) {
        self.pos = (self.pos + n).min(self.lines.len());
    }

    /// Ignores every remaining line.
    pub fn ignore_rest(&mut self) {
        self.pos = self.lines.len();
    }

    /// Errors if a non-blank line remains.
    fn finish(&mut self) -> Result<(), DeckError> {
        self.skip_blank();
        match self.lines.get(self.pos) {
            None => Ok(()),
            Some(l) => Err(DeckError::at(
                self.file,
                l.no,
                Some(self.keyword),
                "unexpected data line (this keyword has no further cards)",
            )),
        }
    }
}
