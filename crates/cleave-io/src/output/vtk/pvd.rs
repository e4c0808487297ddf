//! `.pvd`: a ParaView collection that lists one dataset file per time.

use super::super::number::push_f64;
use super::xml::{escape, invalid, vtk_file_open};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Builds a ParaView collection file (`.pvd`) as states are written.
///
/// Format: `<VTKFile type="Collection">` holding one
/// `<DataSet timestep="T" group="" part="0" file="F"/>` per state, in the order added, `T` in
/// shortest round-trip decimal, `F` relative to the `.pvd` file's folder with `/` separators.
/// Each [`add`](PvdWriter::add) rewrites the whole file (through a temporary file renamed over
/// it), so a run stopped half way leaves a complete, readable collection.
#[derive(Debug, Clone)]
pub struct PvdWriter {
    path: PathBuf,
    entries: Vec<(f64, String)>,
}

impl PvdWriter {
    /// A collection to be written at `path` (nothing is written until [`add`](Self::add) or
    /// [`write`](Self::write)).
    pub fn new(path: impl Into<PathBuf>) -> Self {
        PvdWriter {
            path: path.into(),
            entries: Vec::new(),
        }
    }

    /// A collection at `path` that goes on from `entries` (a restart), written at once: states
    /// written after the restart file are dropped from it (and written again).
    pub fn with_entries(path: impl Into<PathBuf>, entries: Vec<(f64, String)>) -> io::Result<Self> {
        let p = PvdWriter {
            path: path.into(),
            entries,
        };
        p.write()?;
        Ok(p)
    }

    /// The `.pvd` file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The (time, file) entries added so far.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// Adds the dataset `relative_file` (relative to the `.pvd` file's folder, e.g.
    /// `states/state_0001.vtu`) at `time`, then rewrites the file. Errors with `InvalidInput`
    /// if `time` is not finite or the file name is empty.
    pub fn add(&mut self, time: f64, relative_file: &str) -> io::Result<()> {
        if !time.is_finite() {
            return Err(invalid(format!("collection time {time} is not finite")));
        }
        if relative_file.is_empty() {
            return Err(invalid("collection entry with an empty file name".into()));
        }
        self.entries.push((time, relative_file.replace('\\', "/")));
        self.write()
    }

    /// The collection's XML text.
    pub fn to_xml(&self) -> String {
        let mut xml = vtk_file_open("Collection");
        xml.push_str("  <Collection>\n");
        for (time, file) in &self.entries {
            xml.push_str("    <DataSet timestep=\"");
            push_f64(&mut xml, *time);
            xml.push_str(&format!(
                "\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                escape(file)
            ));
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        xml
    }

    /// Writes the whole collection to its path (through a temporary file in the same folder,
    /// renamed over the old one).
    pub fn write(&self) -> io::Result<()> {
        let mut tmp = self.path.clone().into_os_string();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        fs::write(&tmp, self.to_xml())?;
        fs::rename(&tmp, &self.path)
    }
}
