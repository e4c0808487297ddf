//! `summary.json`: the one-object summary of a run.

use serde::Serialize;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// The run summary written to `summary.json` (see the interface page, section "Output").
///
/// Written as one pretty-printed JSON object whose keys are the field names below. A non-finite
/// float (NaN, infinity) is written as `null`, so the file is always valid JSON.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Elements in the deck.
    pub elements: usize,
    /// Nodes in the deck.
    pub nodes: usize,
    /// Nodes the solver integrates, after splitting nodes of separation groups.
    pub nodes_solved: usize,
    /// Interfaces that may fail.
    pub interfaces: usize,
    /// Interfaces no longer intact (softening or free) at the end.
    pub failed_interfaces: usize,
    /// Fragments at the end.
    pub fragments: usize,
    /// Elements eroded by the end (`*MAT_024` FAIL, `*MAT_003` FS, `*MAT_ADD_EROSION`).
    #[serde(default)]
    pub eroded_elements: usize,
    /// Time of the first failed interface (`null`: none failed).
    pub crack_initiation_time: Option<f64>,
    /// Mean crack speed while the crack length grows from 10% to 90% of its final value (m/s;
    /// `null` without a growing crack).
    pub crack_speed_mean: Option<f64>,
    /// Time steps taken.
    pub steps: u64,
    /// Simulated time reached.
    pub end_time: f64,
    /// Wall time of the whole run, in seconds.
    pub wall_seconds: f64,
    /// Wall time of the time-step loop divided by steps times elements, in microseconds.
    pub us_per_element_step: f64,
    /// Peak resident memory in MiB (see [`crate::output::mem::peak_rss_mb`]).
    pub peak_rss_mb: f64,
    /// Worker threads used (of the host, for a run on a GPU).
    pub threads: usize,
    /// Where the step ran: "cpu", or "gpu: " and the adapter's name (`cleave run --gpu`).
    pub device: String,
    /// Total energy over initial energy plus external work, at the end.
    pub energy_ratio: f64,
    /// Where the run stands: "running" (written at intervals during the run), "finished",
    /// "interrupted" (stopped by a signal, with a restart file) or "failed" (exit 3).
    pub status: String,
    /// Version of cleave that wrote the file.
    pub version: String,
    /// What the user should know of the run beyond the numbers (for example, a contact
    /// stiffness that would need a smaller time step than the elements); empty when all is well.
    pub warnings: Vec<String>,
}

impl Summary {
    /// The summary as pretty-printed JSON text (non-finite floats as `null`).
    pub fn to_json(&self) -> String {
        // serde_json writes non-finite f64 as `null`; serializing this plain struct cannot fail.
        serde_json::to_string_pretty(self).expect("a Summary always serializes")
    }

    /// Writes the summary to `path` as pretty-printed JSON followed by a newline, through a
    /// temporary file in the same folder renamed over it: a reader (or a kill) never sees half
    /// a file.
    pub fn write(&self, path: impl AsRef<Path>) -> io::Result<()> {
        let path = path.as_ref();
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let mut w = BufWriter::new(File::create(&tmp)?);
        w.write_all(self.to_json().as_bytes())?;
        w.write_all(b"\n")?;
        w.flush()?;
        drop(w);
        std::fs::rename(&tmp, path)
    }
}
