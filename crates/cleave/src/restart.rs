//! Restart files (`cleave run DECK --checkpoint-every T`, SIGINT/SIGTERM, `--restart FILE`).
//!
//! A restart file holds the complete state between two steps: the solver's
//! ([`Solver::save_state`]: nodes, elements, interfaces and coincident sets, cohesive faces,
//! contact search state) and the output's ([`OutputSaved`]: each history file's length and
//! schedule, the ParaView states written, the histories behind the plots). A run continued
//! from it cuts every history back to that length and appends, so a run stopped and continued
//! writes the same bytes as one that was not stopped (`tests/restart.rs`).
//!
//! It is written to `OUTDIR/restart.ckpt` through a temporary file renamed over the last one,
//! so a kill never leaves half a file. It starts with a header: the version of cleave, the deck,
//! a fingerprint of the model read from the deck ([`fingerprint`]), the end time and the time and step it was taken at. A file made by
//! another version or from another deck is refused with a message that says which (exit 2).
//!
//! Format: the 22 bytes `cleave restart file 3\n`, postcard (serde) of the header and of the
//! output's state, the length of the solver's state (u64, little-endian) and that state
//! ([`Solver::save_state`], postcard too); floats as their IEEE bits.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use cleave_core::model::Model;
use cleave_core::solver::Solver;

use crate::failure::Failure;
use crate::interrupt::Interrupt;
use crate::results::OutputSaved;

/// The restart file's name in the output folder.
pub const FILE: &str = "restart.ckpt";
/// The format's number (2: the header says which kind of run made it; 3: the coincident sets
/// no longer save their scratch). Postcard's bytes carry no field names, so a change to the
/// layout of the saved state takes a new number.
macro_rules! format_number {
    () => {
        "3"
    };
}
/// What every restart file starts with, whatever its format.
const WORDS: &str = "cleave restart file";
/// The first bytes: the words, then the format's number.
const MAGIC: &[u8] = concat!("cleave restart file ", format_number!(), "\n").as_bytes();
const _: () = assert!(MAGIC.len() == WORDS.len() + 3);

/// What a restart file says of itself.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Header {
    pub version: String,
    /// The deck as given on the command line.
    pub deck: String,
    pub fingerprint: u64,
    pub no_separation: bool,
    /// Made by a GPU run (`--gpu`): the state is the device's ([`cleave_gpu::GpuStepper::save`]),
    /// which only a GPU run of the same deck continues.
    pub gpu: bool,
    /// The run's end time (a continued run keeps it unless `--end-time` says otherwise).
    pub end_time: f64,
    /// Time and step of the state it holds.
    pub t: f64,
    pub step: u64,
}

/// A restart file read back.
pub struct RestartFile {
    pub header: Header,
    pub output: OutputSaved,
    pub solver: Vec<u8>,
}

/// FNV-1a 64 of the model as read (its `Debug` text: every node, element, card and value,
/// floats in their shortest exact form), the end time left out: a continued run may go on to
/// another end time. `--no-separation` changes the model, and so the fingerprint.
pub fn fingerprint(model: &mut Model) -> u64 {
    struct Fnv(u64);
    impl std::fmt::Write for Fnv {
        fn write_str(&mut self, s: &str) -> std::fmt::Result {
            for b in s.bytes() {
                self.0 ^= u64::from(b);
                self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
            }
            Ok(())
        }
    }
    let end = std::mem::replace(&mut model.control.end_time, 0.0);
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    std::fmt::Write::write_fmt(&mut h, format_args!("{model:?}")).expect("hashing cannot fail");
    model.control.end_time = end;
    h.0
}

/// Read a restart file; errors name the file (exit 2).
pub fn read(path: &Path) -> Result<RestartFile, Failure> {
    let bad = |what: String| Failure::Input(format!("--restart {}: {what}", path.display()));
    let bytes = std::fs::read(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    let Some(rest) = bytes.strip_prefix(MAGIC) else {
        if let Some(line) = bytes.strip_prefix(WORDS.as_bytes()) {
            // the number up to the line's end (format 1 had none)
            let end = line.iter().position(|&b| b == b'\n').unwrap_or(line.len());
            let format = String::from_utf8_lossy(&line[..end.min(8)]);
            let format = match format.trim() {
                "" => "1",
                f => f,
            };
            return Err(bad(format!(
                "made by another cleave (restart format {format}, this one reads {}), which \
                 this one cannot continue",
                format_number!()
            )));
        }
        return Err(bad("not a cleave restart file".into()));
    };
    let (header, rest): (Header, _) = postcard::take_from_bytes(rest).map_err(|e| {
        bad(format!(
            "unreadable header ({e}): not a cleave restart file?"
        ))
    })?;
    let version = env!("CARGO_PKG_VERSION");
    if header.version != version {
        return Err(bad(format!(
            "made by cleave {}; this is cleave {version}, which cannot continue it",
            header.version
        )));
    }
    let damaged = |e: String| bad(format!("truncated or damaged ({e})"));
    let (output, rest): (OutputSaved, _) =
        postcard::take_from_bytes(rest).map_err(|e| damaged(e.to_string()))?;
    let (len, solver) = rest
        .split_at_checked(8)
        .ok_or_else(|| damaged("no solver state".into()))?;
    let len = u64::from_le_bytes(len.try_into().expect("8 bytes"));
    if solver.len() as u64 != len {
        return Err(damaged(format!(
            "{} bytes of solver state where {len} were written",
            solver.len()
        )));
    }
    Ok(RestartFile {
        header,
        output,
        solver: solver.to_vec(),
    })
}

impl Header {
    /// Refuse to continue a file made from another deck (or with another `--no-separation`).
    pub fn check(
        &self,
        file: &Path,
        deck: &Path,
        fingerprint: u64,
        no_separation: bool,
        gpu: bool,
    ) -> Result<(), Failure> {
        if self.gpu != gpu {
            return Err(Failure::Input(format!(
                "--restart {}: it was made by a run {} --gpu, which keeps its state {}; continue it {} --gpu",
                file.display(),
                if self.gpu { "with" } else { "without" },
                if self.gpu { "on the device" } else { "on the CPU" },
                if self.gpu { "with" } else { "without" },
            )));
        }
        if self.no_separation != no_separation {
            return Err(Failure::Input(format!(
                "--restart {}: it was made {} --no-separation; give the same option",
                file.display(),
                if self.no_separation {
                    "with"
                } else {
                    "without"
                }
            )));
        }
        if self.fingerprint != fingerprint {
            return Err(Failure::Input(format!(
                "--restart {}: it was made from the deck {} as it was then; the model read from {} differs from it, so the state cannot be continued with it",
                file.display(),
                self.deck,
                deck.display()
            )));
        }
        Ok(())
    }
}

/// When restart files are written: every `every` of simulated time (if given), and when a
/// signal asks the run to stop.
pub struct Checkpoints {
    every: Option<f64>,
    next: f64,
    path: PathBuf,
    header: Header,
    interrupt: Option<Interrupt>,
    /// The signal that stopped the run, if one did.
    pub stopped_by: Option<i32>,
    /// Time and step of the last restart file written.
    pub written: Option<(f64, u64)>,
}

impl Checkpoints {
    /// `header`: the run's (its time and step are filled in at each write); `t`: the time the
    /// loop starts from.
    pub fn new(
        every: Option<f64>,
        dir: &Path,
        header: Header,
        interrupt: Option<Interrupt>,
        t: f64,
    ) -> Self {
        let next = every.map_or(f64::INFINITY, |e| next_multiple(t, e));
        Self {
            every,
            next,
            path: dir.join(FILE),
            header,
            interrupt,
            stopped_by: None,
            written: None,
        }
    }

    /// The restart file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// After the step that reached `t`: whether a restart file is due, and whether a signal
    /// asks the run to stop (a file is then written too).
    pub fn poll(&mut self, t: f64) -> (bool, bool) {
        let stop = self.signalled();
        let due = t >= self.next * (1.0 - 1e-12);
        (due || stop, stop)
    }

    /// The next time a restart file is due (infinity: none).
    pub fn next_due(&self) -> f64 {
        self.next
    }

    /// Whether a signal asks the run to stop (and which, in `stopped_by`).
    pub fn signalled(&mut self) -> bool {
        self.stopped_by = self.interrupt.as_ref().and_then(|i| i.received());
        self.stopped_by.is_some()
    }

    /// Write the restart file of the state `s` (the solver's, or a GPU run's `state` when
    /// given) with the output's `out`, and move the next time due past `s`'s.
    pub fn write(
        &mut self,
        s: &Solver,
        out: OutputSaved,
        state: Option<Vec<u8>>,
    ) -> std::io::Result<()> {
        if let Some(e) = self.every {
            if s.state.t >= self.next * (1.0 - 1e-12) {
                self.next = next_multiple(s.state.t, e);
            }
        }
        self.header.t = s.state.t;
        self.header.step = s.state.step;
        let head = postcard::to_stdvec(&self.header).map_err(std::io::Error::other)?;
        let out = postcard::to_stdvec(&out).map_err(std::io::Error::other)?;
        let solver = state.unwrap_or_else(|| s.save_state());
        let mut tmp = self.path.as_os_str().to_owned();
        tmp.push(".tmp");
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(MAGIC)?;
        f.write_all(&head)?;
        f.write_all(&out)?;
        f.write_all(&(solver.len() as u64).to_le_bytes())?;
        f.write_all(&solver)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, &self.path)?;
        self.written = Some((s.state.t, s.state.step));
        Ok(())
    }
}

/// The first multiple of `every` after `t` (by more than round-off).
fn next_multiple(t: f64, every: f64) -> f64 {
    ((t * (1.0 + 1e-12) / every).floor() + 1.0) * every
}
