//! The run's output: the observer that writes glstat, nodout, elout, rwforc, rcforc, the ParaView
//! states, the fracture files ([`crate::fracture`]), and at the end the plots (file formats
//! in `shared/spec/interface.md`).
//!
//! A split model reports deck nodes: a history node's displacement and velocity are the
//! mass-weighted means over its copies.
//!
//! Intervals: each CSV uses its `*DATABASE_*` DT; where the deck gives none, glstat uses
//! ENDTIM/200 (so the energy plot has a curve), and the other histories also ENDTIM/200 when
//! they have something to report. ParaView states use the `*DATABASE_BINARY_D3PLOT` DT, or only
//! the first and last state without it. Every file has a row at t = 0 and at the end time.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use cleave_core::math::{add, scale, sub, von_mises, Vec3};
use cleave_core::model::Model;
use cleave_core::solver::{Observer, Solver};
use cleave_io::output::csv::{CsvWriter, Field};
use cleave_io::output::plot::plot_lines;
use cleave_io::output::vtk::{write_vtu, DataArray, PvdWriter};

use crate::fracture::{fragment_table, fragments_of, FractureOutput, FractureSaved};
use crate::progress::Progress;
use crate::restart::Checkpoints;
use crate::run_status::RunStatus;
use cleave_core::separation::fragments::Fragments;

type Csv = CsvWriter<BufWriter<File>>;

/// When a periodic output is due.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct Schedule {
    dt: f64,
    next: f64,
}

impl Schedule {
    fn new(dt: f64) -> Self {
        Self { dt, next: 0.0 }
    }
    /// Due at t = 0, then at every multiple of dt (the first step at or after it), and last.
    /// At most once a step: a DT shorter than the time step writes every step. The next time
    /// is found in one go (a DT of 1e-30 once counted its multiples up to t one by one, for
    /// ever).
    fn due(&mut self, t: f64, last: bool) -> bool {
        let hit = last || t >= self.next * (1.0 - 1e-12);
        if hit {
            if self.dt > 0.0 && self.dt.is_finite() {
                let beyond = t * (1.0 + 1e-12);
                if self.next <= beyond {
                    // the first multiple of dt past `beyond`
                    let k = (beyond / self.dt).floor() + 1.0;
                    self.next = (k * self.dt).max(self.next + self.dt);
                    if self.next <= beyond {
                        self.next = beyond + self.dt.max(beyond * 1e-12);
                    }
                }
            } else {
                self.next = f64::INFINITY;
            }
        }
        hit
    }
}

/// How far the energy ratio may stray from 1 before a run warns ([`RunOutput::energy_warning`]):
/// 5%, where LS-DYNA users start to distrust a run.
pub const ENERGY_DRIFT: f64 = 0.05;

/// One row of the energy history kept for the plot.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct EnergyRow {
    pub t: f64,
    pub kinetic: f64,
    pub internal: f64,
    pub hourglass: f64,
    pub contact: f64,
    pub fracture: f64,
    pub total: f64,
    pub external: f64,
    pub ratio: f64,
}

/// Writes every output of a run.
pub struct RunOutput<'m> {
    dir: PathBuf,
    model: &'m Model,
    glstat: (Csv, Schedule),
    nodout: Option<(Csv, Schedule)>,
    elout: Option<(Csv, Schedule)>,
    rwforc: Option<(Csv, Schedule)>,
    rcforc: Option<(Csv, Schedule)>,
    states: (PvdWriter, Schedule),
    state_count: usize,
    part_ids: Vec<i32>,
    /// History nodes: deck id and the solved nodes that are its copies.
    history_nodes: Vec<(i64, Vec<u32>)>,
    pub fracture: FractureOutput,
    /// Fragments of an unsplit mesh (fixed), or None to count them at each row.
    static_fragments: Option<usize>,
    pub energy: Vec<EnergyRow>,
    /// Fragments at the last glstat row.
    pub fragments: usize,
    progress: Progress,
    /// Restart files: when to write them and whether a signal asked to stop.
    pub checkpoints: Option<Checkpoints>,
    /// summary.json while the run goes on ([`RunStatus`]).
    pub status: Option<RunStatus>,
}

/// `dir/name` with its header: a new file, or with `len` (a restart) the file written before,
/// cut back to its first `len` bytes.
pub fn open_csv(dir: &Path, name: &str, header: &[&str], len: Option<u64>) -> std::io::Result<Csv> {
    match len {
        None => CsvWriter::create(dir.join(name), header),
        Some(len) => CsvWriter::append(dir.join(name), header, len),
    }
}

/// What a restart file keeps of the output: where each file stood and each schedule, the
/// ParaView states written, and the histories the plots are made from.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct OutputSaved {
    /// glstat, nodout, elout, rwforc, rcforc: length in bytes and schedule (None: no file).
    csv: [Option<(u64, Schedule)>; 5],
    states: (Vec<(f64, String)>, Schedule),
    state_count: usize,
    fracture: FractureSaved,
    energy: Vec<EnergyRow>,
    fragments: usize,
}

impl<'m> RunOutput<'m> {
    /// `history_nodes`: each history node's deck id and its solved copies; `split`: whether the
    /// model is split (its fragments change during the run).
    pub fn create(
        dir: &Path,
        model: &'m Model,
        history_nodes: Vec<(i64, Vec<u32>)>,
        split: bool,
        progress: Progress,
        resume: Option<&OutputSaved>,
    ) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir.join("states"))?;
        let len = |k: usize| resume.and_then(|r| r.csv[k].map(|c| c.0));
        let o = &model.output;
        let end = model.control.end_time;
        let or_default = |dt: f64| if dt > 0.0 { dt } else { end / 200.0 };
        // the columns of erosion only in a model that erodes (the interface page's columns
        // otherwise)
        let erodes = !model.erosion.is_empty();
        let glstat_columns: &[&str] = if erodes {
            &["eroded_elements", "eroded_energy"]
        } else {
            &[]
        };
        let glstat = open_csv(
            dir,
            "glstat.csv",
            &[
                "time",
                "dt",
                "kinetic_energy",
                "internal_energy",
                "hourglass_energy",
                "contact_energy",
                "fracture_energy",
                "external_work",
                "total_energy",
                "energy_ratio",
                "failed_interfaces",
                "fragments",
            ]
            .iter()
            .chain(glstat_columns)
            .copied()
            .collect::<Vec<_>>(),
            len(0),
        )?;
        let nodout = if history_nodes.is_empty() {
            None
        } else {
            let h = [
                "time", "node", "x_disp", "y_disp", "z_disp", "x_vel", "y_vel", "z_vel",
            ];
            Some((
                open_csv(dir, "nodout.csv", &h, len(1))?,
                Schedule::new(or_default(o.nodout_dt)),
            ))
        };
        let elout = if o.history_solids.is_empty() {
            None
        } else {
            let h = [
                "time",
                "element",
                "sxx",
                "syy",
                "szz",
                "sxy",
                "syz",
                "szx",
                "eff_plastic_strain",
            ];
            Some((
                open_csv(dir, "elout.csv", &h, len(2))?,
                Schedule::new(or_default(o.elout_dt)),
            ))
        };
        let rwforc = if model.rigid_walls.is_empty() {
            None
        } else {
            let h = ["time", "wall", "normal_force", "fx", "fy", "fz"];
            Some((
                open_csv(dir, "rwforc.csv", &h, len(3))?,
                Schedule::new(or_default(o.rwforc_dt)),
            ))
        };
        let rcforc = if model.contacts.is_empty() {
            None
        } else {
            // the interface page's columns, then the total normal force and the number of
            // node-face pairs in contact (the resultant of a single-surface contact between
            // two touching bodies nearly cancels: see `ContactForce::force`)
            let h = ["time", "contact", "fx", "fy", "fz", "normal_force", "pairs"];
            Some((
                open_csv(dir, "rcforc.csv", &h, len(4))?,
                Schedule::new(or_default(o.rcforc_dt)),
            ))
        };
        let part_ids = model
            .elem_part
            .iter()
            .map(|&p| model.parts[p as usize].id as i32)
            .collect();
        let mut out = Self {
            dir: dir.to_path_buf(),
            model,
            glstat: (glstat, Schedule::new(or_default(o.glstat_dt))),
            nodout,
            elout,
            rwforc,
            rcforc,
            states: (
                PvdWriter::new(dir.join("results.pvd")),
                Schedule::new(o.d3plot_dt),
            ),
            state_count: 0,
            part_ids,
            history_nodes,
            fracture: FractureOutput::create(
                dir,
                model.control.end_time / 30.0,
                crate::crack_growth::thickness_axis(&model.x0),
                resume.map(|r| &r.fracture),
            )?,
            static_fragments: (!split).then(|| cleave_core::setup::count_components(model)),
            energy: Vec::new(),
            fragments: 0,
            progress,
            checkpoints: None,
            status: None,
        };
        if let Some(r) = resume {
            out.restore(r)?;
        }
        Ok(out)
    }

    /// Go on from a restart file's output state (the files are already cut back).
    fn restore(&mut self, r: &OutputSaved) -> std::io::Result<()> {
        for (mine, saved) in self.histories().into_iter().zip(&r.csv) {
            if let (Some(mine), Some(saved)) = (mine, saved) {
                mine.1 = saved.1;
            }
        }
        let path = self.dir.join("results.pvd");
        self.states = (
            PvdWriter::with_entries(path, r.states.0.clone())?,
            r.states.1,
        );
        self.state_count = r.state_count;
        self.energy = r.energy.clone();
        self.fragments = r.fragments;
        Ok(())
    }

    /// Where every output stands now, for a restart file (every row is flushed first).
    pub fn saved(&mut self) -> std::io::Result<OutputSaved> {
        let mut csv = [None; 5];
        for (k, f) in self.histories().into_iter().enumerate() {
            if let Some((w, sch)) = f {
                csv[k] = Some((w.written_len()?, *sch));
            }
        }
        Ok(OutputSaved {
            csv,
            states: (self.states.0.entries().to_vec(), self.states.1),
            state_count: self.state_count,
            fracture: self.fracture.saved()?,
            energy: self.energy.clone(),
            fragments: self.fragments,
        })
    }

    /// A glstat and crack.csv row; `fr`: the fragments now (None: the mesh's, fixed).
    fn write_glstat(&mut self, s: &Solver, fr: Option<&Fragments>) -> std::io::Result<()> {
        self.fragments = match (fr, self.static_fragments) {
            (Some(f), _) => f.count,
            (None, Some(n)) => n,
            (None, None) => unreachable!("a split model's fragments are counted at each row"),
        };
        self.fracture.write_row(s, self.fragments)?;
        let failed = s.separation().map_or(0, |sep| sep.num_failed());
        let e = &s.state.energy;
        let total = e.total();
        let denom = s.state.initial_energy + e.external_work;
        // 1 with nothing in the model; a non-finite figure goes through (the solver stops on
        // one)
        let ratio = if denom == 0.0 { 1.0 } else { total / denom };
        self.energy.push(EnergyRow {
            t: s.state.t,
            kinetic: e.kinetic,
            internal: e.internal,
            hourglass: e.hourglass,
            contact: e.contact,
            fracture: e.fracture,
            total,
            external: e.external_work,
            ratio,
        });
        let mut row = vec![
            Field::F(s.state.t),
            Field::F(s.state.dt),
            Field::F(e.kinetic),
            Field::F(e.internal),
            Field::F(e.hourglass),
            Field::F(e.contact),
            Field::F(e.fracture),
            Field::F(e.external_work),
            Field::F(total),
            Field::F(ratio),
            Field::I(failed as i64),
            Field::I(self.fragments as i64),
        ];
        if !self.model.erosion.is_empty() {
            row.extend([Field::I(s.eroded_count() as i64), Field::F(e.eroded)]);
        }
        self.glstat.0.row(&row)
    }

    fn write_nodout(
        csv: &mut Csv,
        m: &Model,
        nodes: &[(i64, Vec<u32>)],
        s: &Solver,
    ) -> std::io::Result<()> {
        let (x, vel) = (s.positions(), s.velocities());
        for (id, copies) in nodes {
            let (mut u, mut v, mut mass) = ([0.0; 3], [0.0; 3], 0.0);
            for &n in copies {
                let i = n as usize;
                let mi = s.setup.mass[i];
                u = add(u, scale(sub(x[i], m.x0[i]), mi));
                v = add(v, scale(vel[i], mi));
                mass += mi;
            }
            if mass > 0.0 {
                u = scale(u, 1.0 / mass);
                v = scale(v, 1.0 / mass);
            }
            csv.row(&[
                Field::F(s.state.t),
                Field::I(*id),
                Field::F(u[0]),
                Field::F(u[1]),
                Field::F(u[2]),
                Field::F(v[0]),
                Field::F(v[1]),
                Field::F(v[2]),
            ])?;
        }
        Ok(())
    }

    fn write_elout(csv: &mut Csv, m: &Model, s: &Solver) -> std::io::Result<()> {
        for &e in &m.output.history_solids {
            let k = e as usize;
            let st = s.state.stress[k];
            let mut row = vec![Field::F(s.state.t), Field::I(m.elem_ids[k])];
            row.extend(st.iter().map(|&x| Field::F(x)));
            row.push(Field::F(s.state.hist[k].eps_p));
            csv.row(&row)?;
        }
        Ok(())
    }

    fn write_rwforc(csv: &mut Csv, m: &Model, s: &Solver) -> std::io::Result<()> {
        for (w, f) in m.rigid_walls.iter().zip(&s.wall_forces) {
            csv.row(&[
                Field::F(s.state.t),
                Field::I(w.id),
                Field::F(f.normal),
                Field::F(f.force[0]),
                Field::F(f.force[1]),
                Field::F(f.force[2]),
            ])?;
        }
        Ok(())
    }

    fn write_rcforc(csv: &mut Csv, s: &Solver) -> std::io::Result<()> {
        let Some(c) = s.contact() else {
            return Ok(());
        };
        for f in c.forces() {
            csv.row(&[
                Field::F(s.state.t),
                Field::I(f.id),
                Field::F(f.force[0]),
                Field::F(f.force[1]),
                Field::F(f.force[2]),
                Field::F(f.normal),
                Field::I(f.pairs as i64),
            ])?;
        }
        Ok(())
    }

    fn write_state(&mut self, s: &Solver) -> std::io::Result<()> {
        let m = self.model;
        let name = format!("states/state_{:05}.vtu", self.state_count);
        // per node (a split model's positions and velocities are kept per coincident set)
        let x = s.positions().to_vec();
        let vel = s.velocities().to_vec();
        let disp: Vec<Vec3> = x.iter().zip(&m.x0).map(|(x, x0)| sub(*x, *x0)).collect();
        let vm: Vec<f64> = s.state.stress.iter().map(von_mises).collect();
        let eps_p: Vec<f64> = s.state.hist.iter().map(|h| h.eps_p).collect();
        // in a model that erodes, 1 for an eroded element (ParaView's Threshold on it hides
        // them), 0 otherwise
        let eroded: Vec<i32> = s.state.eroded.iter().map(|&d| i32::from(d)).collect();
        let mut w = BufWriter::new(File::create(self.dir.join(&name))?);
        write_vtu(
            &mut w,
            &x,
            &m.conn,
            &[
                ("displacement", DataArray::Vector(&disp)),
                ("velocity", DataArray::Vector(&vel)),
            ],
            &[
                ("part", DataArray::Int(&self.part_ids)),
                ("von_mises", DataArray::Scalar(&vm)),
                ("stress", DataArray::SymTensor(&s.state.stress)),
                ("eff_plastic_strain", DataArray::Scalar(&eps_p)),
                ("eroded", DataArray::Int(&eroded)),
            ][..if m.erosion.is_empty() { 4 } else { 5 }],
        )?;
        std::io::Write::flush(&mut w)?;
        self.states.0.add(s.state.t, &name)?;
        self.state_count += 1;
        Ok(())
    }

    /// summary.json of the state `s` with `status` (every history flushed first, so the
    /// files hold at least what the summary says).
    pub fn write_summary(&mut self, s: &Solver, status: &str) -> std::io::Result<()> {
        let Some(st) = &self.status else {
            return Ok(());
        };
        let ratio = self.energy.last().map_or(1.0, |r| r.ratio);
        let g = self.fracture.growth();
        let summary = st.summary(
            s,
            self.fragments,
            ratio,
            (g.initiation(), g.mean_speed()),
            status,
        );
        let path = st.path.clone();
        self.flush()?;
        summary.write(path)
    }

    /// glstat, nodout, elout, rwforc, rcforc with their schedules (None: the run has no such
    /// file), in the order of [`OutputSaved`].
    fn histories(&mut self) -> [Option<&mut (Csv, Schedule)>; 5] {
        [
            Some(&mut self.glstat),
            self.nodout.as_mut(),
            self.elout.as_mut(),
            self.rwforc.as_mut(),
            self.rcforc.as_mut(),
        ]
    }

    /// Flush every history file.
    fn flush(&mut self) -> std::io::Result<()> {
        for f in self.histories().into_iter().flatten() {
            f.0.flush()?;
        }
        self.fracture.flush()
    }

    /// Flush every file and write the energy plot (at the end, or after a failure).
    pub fn finish(&mut self) -> std::io::Result<()> {
        self.progress.finish();
        self.flush()?;
        self.fracture.finish()?;
        self.plot_energy()
    }

    /// A warning when the energy ratio (total energy over initial energy plus external work,
    /// glstat's `energy_ratio`) strayed from 1 by more than [`ENERGY_DRIFT`] at some output
    /// time: the discrete system then creates or loses energy, and its results are suspect.
    pub fn energy_warning(&self) -> Option<String> {
        let worst = self
            .energy
            .iter()
            .filter(|r| r.ratio.is_finite())
            .max_by(|a, b| (a.ratio - 1.0).abs().total_cmp(&(b.ratio - 1.0).abs()))?;
        ((worst.ratio - 1.0).abs() > ENERGY_DRIFT).then(|| {
            format!(
                "the energy ratio reached {:.4} at t = {:e} (total energy over the initial energy plus the external work; 1 when energy is conserved): energy was created or lost numerically, so the results are suspect; see energy.png (time step, hourglass energy, a material driven beyond its range)",
                worst.ratio, worst.t
            )
        })
    }

    fn plot_energy(&self) -> std::io::Result<()> {
        let pick =
            |f: fn(&EnergyRow) -> f64| self.energy.iter().map(|r| (r.t, f(r))).collect::<Vec<_>>();
        let series = [
            ("kinetic", pick(|r| r.kinetic)),
            ("internal", pick(|r| r.internal)),
            ("hourglass", pick(|r| r.hourglass)),
            ("contact", pick(|r| r.contact)),
            ("fracture", pick(|r| r.fracture)),
            ("external work", pick(|r| r.external)),
            ("total", pick(|r| r.total)),
            ("initial + external work", pick(|r| r.total / r.ratio)),
        ];
        let refs: Vec<(&str, &[(f64, f64)])> =
            series.iter().map(|(n, v)| (*n, v.as_slice())).collect();
        plot_lines(
            &self.dir.join("energy.png"),
            "Energy balance",
            "time",
            "energy",
            &refs,
        )
        .map_err(|e| std::io::Error::other(e.to_string()))
    }
}

/// A GPU run's restart files: the same schedule and signals as the CPU's, the device's state.
impl cleave_gpu::Checkpointing for RunOutput<'_> {
    fn checkpoint_due(&self) -> f64 {
        self.checkpoints
            .as_ref()
            .map_or(f64::INFINITY, Checkpoints::next_due)
    }

    fn stop_asked(&mut self) -> bool {
        self.checkpoints
            .as_mut()
            .is_some_and(Checkpoints::signalled)
    }

    fn checkpoint(&mut self, s: &Solver, gpu_state: Vec<u8>) -> std::io::Result<()> {
        let Some(mut c) = self.checkpoints.take() else {
            return Ok(());
        };
        let written = self.saved().and_then(|o| c.write(s, o, Some(gpu_state)));
        self.checkpoints = Some(c);
        written
    }
}

impl Observer for RunOutput<'_> {
    /// The earliest of the next times of every output.
    fn next_due(&self) -> f64 {
        let mut t = self.glstat.1.next.min(self.states.1.next);
        for o in [&self.nodout, &self.elout, &self.rwforc, &self.rcforc]
            .into_iter()
            .flatten()
        {
            t = t.min(o.1.next);
        }
        t
    }

    fn tick(&mut self, s: &Solver) {
        self.progress
            .update(s, s.separation().map_or(0, |sep| sep.num_failed()));
    }

    /// A restart file when one is due or a signal asks to stop ([`Checkpoints`]).
    fn between_steps(&mut self, s: &Solver) -> std::io::Result<bool> {
        let Some(mut c) = self.checkpoints.take() else {
            return Ok(false);
        };
        let (write, stop) = c.poll(s.state.t);
        let written = if write {
            self.saved().and_then(|o| c.write(s, o, None))
        } else {
            Ok(())
        };
        self.checkpoints = Some(c);
        written.map(|()| stop)
    }

    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        let t = s.state.t;
        let last = s.is_finished();
        let m = self.model;
        // glstat is always due at the last step, where fragments.csv needs the fragments too
        if self.glstat.1.due(t, last) {
            let fr = (self.static_fragments.is_none() || last).then(|| fragments_of(s));
            self.write_glstat(s, fr.as_ref())?;
            if let (true, Some(fr)) = (last, &fr) {
                let rows = fragment_table(s, fr);
                self.fracture.write_fragments(&rows)?;
                self.fracture.record_strengths(s);
            }
        }
        if let Some((csv, sch)) = &mut self.nodout {
            if sch.due(t, last) {
                Self::write_nodout(csv, m, &self.history_nodes, s)?;
            }
        }
        if let Some((csv, sch)) = &mut self.elout {
            if sch.due(t, last) {
                Self::write_elout(csv, m, s)?;
            }
        }
        if let Some((csv, sch)) = &mut self.rwforc {
            if sch.due(t, last) {
                Self::write_rwforc(csv, m, s)?;
            }
        }
        if let Some((csv, sch)) = &mut self.rcforc {
            if sch.due(t, last) {
                Self::write_rcforc(csv, s)?;
            }
        }
        if self.states.1.due(t, last) {
            self.write_state(s)?;
            self.fracture.write_surfaces(s)?;
        }
        self.progress
            .update(s, s.separation().map_or(0, |sep| sep.num_failed()));
        if self.status.as_mut().is_some_and(|st| st.due()) {
            self.write_summary(s, "running")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::Schedule;

    #[test]
    fn a_tiny_interval_writes_every_step_and_does_not_hang() {
        let mut s = Schedule::new(1e-30);
        let mut hits = 0;
        for k in 0..1000 {
            hits += usize::from(s.due(k as f64 * 1e-7, false));
        }
        assert_eq!(hits, 1000);
    }

    #[test]
    fn schedule_hits_first_multiples_and_last() {
        let mut s = Schedule::new(1.0);
        let hits: Vec<f64> = [0.0, 0.4, 0.9, 1.05, 1.5, 2.0, 2.2]
            .iter()
            .copied()
            .filter(|&t| s.due(t, t == 2.2))
            .collect();
        assert_eq!(hits, vec![0.0, 1.05, 2.0, 2.2]);
        let mut z = Schedule::new(0.0);
        let hits: Vec<f64> = [0.0, 0.5, 1.0]
            .iter()
            .copied()
            .filter(|&t| z.due(t, t == 1.0))
            .collect();
        assert_eq!(hits, vec![0.0, 1.0]);
    }
}
