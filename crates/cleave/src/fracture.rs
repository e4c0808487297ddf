//! Fracture output: crack.csv (at the glstat interval; crack length and speed as
//! [`crate::crack_growth`] defines them), the crack surfaces as their own ParaView series
//! (cracks.pvd with cracks/*.vtp, at the state interval), fragments.csv at the end, and the
//! plots crack.png (crack length and speed over time), crack_area.png (crack area and
//! fragments over time), fragments.png (the fragment mass distribution) and, when interface
//! strengths are drawn from a distribution, strength.png (their histogram).
//!
//! Fragments are the connected components of elements through shared nodes and every face
//! still holding (bonds, intact and softening interfaces); a model without separation has the
//! components of its mesh. They are numbered by decreasing mass in fragments.csv.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use crate::crack_growth::CrackGrowth;
use cleave_core::math::Vec3;
use cleave_core::model::StrengthDist;
use cleave_core::separation::fragments::{FragmentSummary, Fragments};
use cleave_core::separation::interfaces::{face_centroid, Status};
use cleave_core::solver::Solver;
use cleave_core::topology::element_components;
use cleave_io::output::csv::{CsvWriter, Field};
use cleave_io::output::plot::{plot_histogram, plot_two_axes};
use cleave_io::output::vtk::{write_vtp_quads, DataArray, PvdWriter};

type Csv = CsvWriter<BufWriter<File>>;

/// The fragments of the current state.
pub fn fragments_of(s: &Solver) -> Fragments {
    match s.separation() {
        Some(sep) => sep.fragments(&s.model.conn, s.model.num_nodes()),
        None => {
            let (label, count) = element_components(s.model);
            Fragments { label, count }
        }
    }
}

/// Mass, centroid and velocity of each fragment at t^n, by decreasing mass.
pub fn fragment_table(s: &Solver, fr: &Fragments) -> Vec<FragmentSummary> {
    fr.summaries(&s.model.conn, &s.setup.mass, s.positions(), s.velocities())
}

/// What a restart file keeps of the fracture output: crack.csv's length, the crack surfaces
/// written, and the history the plots and the crack speed are made from.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct FractureSaved {
    crack_len: u64,
    cracks: Vec<(f64, String)>,
    count: usize,
    history: Vec<(f64, f64, usize, f64)>,
    growth: CrackGrowth,
}

/// The fracture files of a run.
pub struct FractureOutput {
    dir: PathBuf,
    crack: Csv,
    cracks: PvdWriter,
    count: usize,
    /// (t, crack area, fragments, crack speed) of every crack.csv row, for the plots.
    history: Vec<(f64, f64, usize, f64)>,
    growth: CrackGrowth,
    centroids: Vec<Vec3>,
    final_masses: Vec<f64>,
    /// With a strength distribution: every interface's strength and how many failed, for
    /// strength.png.
    strengths: Option<(Vec<f64>, usize)>,
}

impl FractureOutput {
    /// Crack speeds are slopes over the last `speed_window` of time; `thickness`: the axis
    /// crack lengths leave out ([`crate::crack_growth::thickness_axis`]).
    /// `resume`: the state of a restart file, to go on from (crack.csv is cut back to its
    /// length then).
    pub fn create(
        dir: &Path,
        speed_window: f64,
        thickness: Option<usize>,
        resume: Option<&FractureSaved>,
    ) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir.join("cracks"))?;
        let crack = crate::results::open_csv(
            dir,
            "crack.csv",
            &[
                "time",
                "failed_interfaces",
                "crack_area",
                "fragments",
                "min_x",
                "max_x",
                "min_y",
                "max_y",
                "min_z",
                "max_z",
                "crack_length",
                "crack_speed",
            ],
            resume.map(|r| r.crack_len),
        )?;
        let mut out = Self {
            dir: dir.to_path_buf(),
            crack,
            cracks: PvdWriter::new(dir.join("cracks.pvd")),
            count: 0,
            history: Vec::new(),
            growth: CrackGrowth::new(speed_window, thickness),
            centroids: Vec::new(),
            final_masses: Vec::new(),
            strengths: None,
        };
        if let Some(r) = resume {
            out.cracks = PvdWriter::with_entries(dir.join("cracks.pvd"), r.cracks.clone())?;
            out.count = r.count;
            out.history = r.history.clone();
            out.growth = r.growth.clone();
        }
        Ok(out)
    }

    /// What a restart file keeps (every row is flushed first).
    pub fn saved(&mut self) -> std::io::Result<FractureSaved> {
        Ok(FractureSaved {
            crack_len: self.crack.written_len()?,
            cracks: self.cracks.entries().to_vec(),
            count: self.count,
            history: self.history.clone(),
            growth: self.growth.clone(),
        })
    }

    /// One crack.csv row: failed interfaces, their reference area, the fragment count, the
    /// extent of the current centroids of the failed interfaces (empty while none has failed),
    /// the crack length and speed.
    pub fn write_row(&mut self, s: &Solver, fragments: usize) -> std::io::Result<()> {
        let (failed, area) = s
            .separation()
            .map_or((0, 0.0), |sep| (sep.num_failed(), sep.crack_area()));
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        self.centroids.clear();
        if let Some(sep) = s.separation() {
            for i in sep.failed_interfaces() {
                self.centroids
                    .push(face_centroid(&sep.faces()[i], &s.model.x0));
                let c = face_centroid(&sep.faces()[i], &s.positions());
                for d in 0..3 {
                    lo[d] = lo[d].min(c[d]);
                    hi[d] = hi[d].max(c[d]);
                }
            }
        }
        let mut row = vec![
            Field::F(s.state.t),
            Field::I(failed as i64),
            Field::F(area),
            Field::I(fragments as i64),
        ];
        for d in 0..3 {
            if failed > 0 {
                row.push(Field::F(lo[d]));
                row.push(Field::F(hi[d]));
            } else {
                row.push(Field::Empty);
                row.push(Field::Empty);
            }
        }
        let (length, speed) = self.growth.record(s.state.t, &self.centroids);
        row.push(Field::F(length));
        row.push(Field::F(speed));
        self.history.push((s.state.t, area, fragments, speed));
        self.crack.row(&row)
    }

    /// The crack surfaces now: both faces of every interface no longer intact, at the current
    /// positions, with the interface number, its status (1 softening, 2 free) and its
    /// strength.
    pub fn write_surfaces(&mut self, s: &Solver) -> std::io::Result<()> {
        let mut points: Vec<Vec3> = Vec::new();
        let mut quads: Vec<[u32; 4]> = Vec::new();
        let mut ids: Vec<i32> = Vec::new();
        let mut status: Vec<i32> = Vec::new();
        let mut strength: Vec<f64> = Vec::new();
        let x = s.positions();
        if let Some(sep) = s.separation() {
            for i in sep.failed_interfaces() {
                let face = &sep.faces()[i];
                let st = match sep.status(i) {
                    Status::Softening => 1,
                    _ => 2,
                };
                // side a in its outward order; side b reversed, so that it faces the other way
                for side in [[0, 1, 2, 3], [7, 6, 5, 4]] {
                    let base = points.len() as u32;
                    for k in side {
                        points.push(x[face.nodes[k] as usize]);
                    }
                    quads.push([base, base + 1, base + 2, base + 3]);
                    ids.push(i as i32);
                    status.push(st);
                    strength.push(face.strength);
                }
            }
        }
        let name = format!("cracks/cracks_{:05}.vtp", self.count);
        let mut w = BufWriter::new(File::create(self.dir.join(&name))?);
        write_vtp_quads(
            &mut w,
            &points,
            &quads,
            &[
                ("interface", DataArray::Int(&ids)),
                ("status", DataArray::Int(&status)),
                ("strength", DataArray::Scalar(&strength)),
            ],
        )?;
        std::io::Write::flush(&mut w)?;
        self.cracks.add(s.state.t, &name)?;
        self.count += 1;
        Ok(())
    }

    /// fragments.csv: `fragment,elements,mass,cx,cy,cz,vx,vy,vz`, by decreasing mass.
    pub fn write_fragments(&mut self, rows: &[FragmentSummary]) -> std::io::Result<()> {
        let mut csv: Csv = CsvWriter::create(
            self.dir.join("fragments.csv"),
            &[
                "fragment", "elements", "mass", "cx", "cy", "cz", "vx", "vy", "vz",
            ],
        )?;
        for (k, r) in rows.iter().enumerate() {
            csv.row(&[
                Field::I(k as i64 + 1),
                Field::I(r.elements as i64),
                Field::F(r.mass),
                Field::F(r.centroid[0]),
                Field::F(r.centroid[1]),
                Field::F(r.centroid[2]),
                Field::F(r.velocity[0]),
                Field::F(r.velocity[1]),
                Field::F(r.velocity[2]),
            ])?;
        }
        csv.flush()?;
        self.final_masses = rows.iter().map(|r| r.mass).collect();
        Ok(())
    }

    /// Keep the interface strengths of the run for strength.png when a separation group draws
    /// them from a distribution (`*MAT_ADD_SEPARATION` DIST).
    pub fn record_strengths(&mut self, s: &Solver) {
        let random = s
            .model
            .separations
            .iter()
            .any(|d| d.strength != StrengthDist::Constant);
        if let (true, Some(sep)) = (random, s.separation()) {
            let all = sep.faces()[..sep.num_interfaces()]
                .iter()
                .map(|f| f.strength)
                .collect();
            self.strengths = Some((all, sep.num_failed()));
        }
    }

    /// Time of the first failure and mean crack speed after the slow start
    /// ([`CrackGrowth`]).
    pub fn growth(&self) -> &CrackGrowth {
        &self.growth
    }

    /// Flush crack.csv; plot crack.png, crack_area.png and, once fragments.csv is written,
    /// fragments.png.
    /// Flush crack.csv.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.crack.flush()
    }

    pub fn finish(&mut self) -> std::io::Result<()> {
        self.crack.flush()?;
        let area: Vec<(f64, f64)> = self.history.iter().map(|r| (r.0, r.1)).collect();
        let frags: Vec<(f64, f64)> = self.history.iter().map(|r| (r.0, r.2 as f64)).collect();
        let speed: Vec<(f64, f64)> = self.history.iter().map(|r| (r.0, r.3)).collect();
        let io = |e: cleave_io::output::plot::PlotError| std::io::Error::other(e.to_string());
        plot_two_axes(
            &self.dir.join("crack.png"),
            "Crack length and speed",
            "time",
            ("crack length", self.growth.lengths()),
            ("crack speed", &speed),
        )
        .map_err(io)?;
        plot_two_axes(
            &self.dir.join("crack_area.png"),
            "Crack area and fragments",
            "time",
            ("crack area", &area),
            ("fragments", &frags),
        )
        .map_err(io)?;
        if let Some(strengths) = &self.strengths {
            plot_histogram(
                &self.dir.join("strength.png"),
                &format!(
                    "Interface strengths ({} interfaces, {} failed)",
                    strengths.0.len(),
                    strengths.1
                ),
                "strength",
                "interfaces",
                &strengths.0,
                40,
                false,
            )
            .map_err(io)?;
        }
        if !self.final_masses.is_empty() {
            let total: f64 = self.final_masses.iter().sum();
            let fractions: Vec<f64> = self.final_masses.iter().map(|m| m / total).collect();
            plot_histogram(
                &self.dir.join("fragments.png"),
                "Fragment masses at the end",
                "fragment mass / total mass",
                "fragments",
                &fractions,
                20,
                true,
            )
            .map_err(io)?;
        }
        Ok(())
    }
}
