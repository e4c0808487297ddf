//! CSV histories: `glstat.csv`, `nodout.csv`, `elout.csv` and the others.
//!
//! Format: UTF-8, `\n` line ends, one header line of column names, then one line per row; fields
//! separated by `,` with no quoting and no spaces. Floats are written in the shortest text that
//! parses back to the same bits (plain decimal for magnitudes in [1e-5, 1e16), scientific such as
//! `1.25e-7` otherwise); integers in decimal; an empty field for a missing value. Non-finite
//! floats are written `nan`, `inf`, `-inf`: Rust, Python, NumPy and pandas read them, some other
//! tools do not (the solver stops on non-finite values, so they should not appear).

use super::number::push_f64;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// One field of a CSV row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Field {
    /// A float, written in shortest round-trip form.
    F(f64),
    /// An integer (ids, counts).
    I(i64),
    /// A missing value: an empty field.
    Empty,
}

impl From<f64> for Field {
    fn from(x: f64) -> Self {
        Field::F(x)
    }
}

impl From<i64> for Field {
    fn from(i: i64) -> Self {
        Field::I(i)
    }
}

impl From<Option<f64>> for Field {
    fn from(x: Option<f64>) -> Self {
        x.map_or(Field::Empty, Field::F)
    }
}

/// Writes a CSV file row by row, checking each row against the header's column count.
#[derive(Debug)]
pub struct CsvWriter<W: Write> {
    out: W,
    columns: usize,
    line: String,
}

impl CsvWriter<BufWriter<File>> {
    /// Creates (or truncates) the file at `path` and writes the header line.
    pub fn create(path: impl AsRef<Path>, header: &[&str]) -> io::Result<Self> {
        CsvWriter::new(BufWriter::new(File::create(path)?), header)
    }

    /// Opens the file at `path`, written by [`Self::create`] with the same header, to go on
    /// after its first `len` bytes (a restart: what was written after the restart file is
    /// cut off and written again). Errors if the file does not start with this header or is
    /// shorter than `len`.
    pub fn append(path: impl AsRef<Path>, header: &[&str], len: u64) -> io::Result<Self> {
        let path = path.as_ref();
        let mut file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)?;
        let mut line = header.join(",");
        line.push('\n');
        let mut head = vec![0u8; line.len()];
        let size = file.metadata()?.len();
        if size < len || len < line.len() as u64 {
            return Err(invalid(format!(
                "{} has {size} bytes, fewer than the {len} written before the restart file",
                path.display()
            )));
        }
        io::Read::read_exact(&mut file, &mut head)?;
        if head != line.as_bytes() {
            return Err(invalid(format!(
                "{} does not start with the header {:?}",
                path.display(),
                line.trim_end()
            )));
        }
        file.set_len(len)?;
        io::Seek::seek(&mut file, io::SeekFrom::End(0))?;
        Ok(CsvWriter {
            out: BufWriter::new(file),
            columns: header.len(),
            line,
        })
    }

    /// Flushes the rows written so far and returns the file's length in bytes: every row in
    /// it is complete.
    pub fn written_len(&mut self) -> io::Result<u64> {
        self.out.flush()?;
        Ok(self.out.get_ref().metadata()?.len())
    }
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header line to `out`. A column name may not be empty nor contain `,`, `"` or a
    /// line break (there is no quoting); the header may not be empty.
    pub fn new(mut out: W, header: &[&str]) -> io::Result<Self> {
        if header.is_empty() {
            return Err(invalid("a CSV header needs at least one column".into()));
        }
        if let Some(bad) = header
            .iter()
            .find(|h| h.is_empty() || h.contains([',', '"', '\n', '\r']))
        {
            return Err(invalid(format!("invalid CSV column name {bad:?}")));
        }
        let mut line = header.join(",");
        line.push('\n');
        out.write_all(line.as_bytes())?;
        Ok(CsvWriter {
            out,
            columns: header.len(),
            line,
        })
    }

    /// Number of columns of the header.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Writes one row. Errors (`InvalidInput`) if it does not have as many fields as the header.
    pub fn row(&mut self, fields: &[Field]) -> io::Result<()> {
        if fields.len() != self.columns {
            return Err(invalid(format!(
                "CSV row has {} fields, the header has {} columns",
                fields.len(),
                self.columns
            )));
        }
        self.line.clear();
        for (k, field) in fields.iter().enumerate() {
            if k > 0 {
                self.line.push(',');
            }
            match *field {
                Field::F(x) => push_f64(&mut self.line, x),
                Field::I(i) => self.line.push_str(&i.to_string()),
                Field::Empty => {}
            }
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())
    }

    /// Flushes buffered rows to the underlying writer.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    /// Flushes and returns the underlying writer.
    pub fn into_inner(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}
