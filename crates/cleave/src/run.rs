//! `cleave run DECK.k`: read, prepare, run, write.

use std::path::{Path, PathBuf};
use std::time::Instant;

use cleave_core::contact::ContactSet;
use cleave_core::model::Model;
use cleave_core::separation::interfaces::Separation;
use cleave_core::separation::split::{copies_of, split_model, SharedFace};
use cleave_core::setup::estimate_time_step;
use cleave_core::solver::{RunError, Solver};

use crate::cli::RunArgs;
use crate::failure::{io_failure, Failure};
use crate::interrupt::{signal_name, Interrupt};
use crate::progress::Progress;
use crate::restart::{self, Checkpoints};
use crate::results::RunOutput;
use crate::run_status::RunStatus;

/// DECK.k -> DECK.out beside it.
pub fn default_out_dir(deck: &Path) -> PathBuf {
    deck.with_extension("out")
}

/// Read a deck, print its warnings, apply the command-line overrides.
pub fn load_model(
    deck: &Path,
    end_time: Option<f64>,
    no_separation: bool,
) -> Result<Model, Failure> {
    let d = cleave_io::deck::read_deck(deck)?;
    for w in &d.warnings {
        eprintln!("warning: {w}");
    }
    let mut model = d.model;
    if let Some(t) = end_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(Failure::Input(format!(
                "--end-time {t}: must be a positive number"
            )));
        }
        model.control.end_time = t;
    }
    if no_separation {
        model.separations.clear();
    }
    state_cap(&model)?;
    Ok(model)
}

/// The cap on the ParaView states ([`MAX_STATES`]): `*DATABASE_BINARY_D3PLOT` DT against the
/// end time (`cleave check` applies it too).
pub fn state_cap(model: &Model) -> Result<(), Failure> {
    let (dt, end) = (model.output.d3plot_dt, model.control.end_time);
    if dt > 0.0 && end / dt > MAX_STATES {
        return Err(Failure::Input(format!(
            "*DATABASE_BINARY_D3PLOT: DT {dt:e} asks for {:.3e} ParaView states over ENDTIM {end:e}; cleave writes at most {MAX_STATES} (a file each): give a larger DT",
            end / dt
        )));
    }
    Ok(())
}

/// The most ParaView states a run may ask for (each is a file of the whole mesh). The CSV
/// histories need no cap: they write at most one row a step.
pub const MAX_STATES: f64 = 10_000.0;

/// The interface table of a split model: its shared faces and how many of them are
/// interfaces (they come first).
pub type InterfaceTable = (Vec<SharedFace>, usize);

/// The model the solver runs, and what the output needs to know of the deck.
pub struct Prepared {
    pub model: Model,
    pub interfaces: Option<InterfaceTable>,
    /// Each history node of the deck: its id and the solved nodes that are its copies.
    pub history_nodes: Vec<(i64, Vec<u32>)>,
    pub deck_nodes: usize,
}

/// With separation groups, every group element gets nodes of its own (the paper's
/// preprocessing) and the deck's mesh is dropped; the interface table moves into the run's
/// interfaces.
pub fn prepare(deck: Model) -> Prepared {
    let deck_nodes = deck.num_nodes();
    if deck.separations.is_empty() {
        let history_nodes = history_copies(&deck, None);
        Prepared {
            model: deck,
            interfaces: None,
            history_nodes,
            deck_nodes,
        }
    } else {
        let sp = split_model(&deck);
        Prepared {
            history_nodes: history_copies(&deck, Some(&sp.origin)),
            model: sp.model,
            interfaces: Some((sp.faces, sp.interfaces)),
            deck_nodes,
        }
    }
}

/// A solver for `model`, with its interfaces when it is split and its contact definitions
/// (a split model's `x0` knows the deck node of each solved node).
///
/// When the contact's penalty springs need a smaller time step than the elements, the run
/// takes it and the returned warning says so; it goes to the terminal and to summary.json.
pub fn start_solver<'m>(
    model: &'m Model,
    interfaces: Option<InterfaceTable>,
) -> Result<(Solver<'m>, Vec<String>), Failure> {
    let origin = model.x0.origin();
    let mut solver = Solver::new(model)?;
    let mut warnings = solver.setup.warnings.clone();
    if let Some((faces, n)) = interfaces {
        solver.attach_separation(Separation::from_parts(model, faces, n).map_err(Failure::Input)?);
    }
    if !model.contacts.is_empty() {
        solver.attach_contact(ContactSet::new(model, origin).map_err(Failure::Input)?);
        let dt_contact = model.control.tssfac * solver.contact_time_step();
        let dt_elem = estimate_time_step(model).map_or(model.control.dt_init, |(dt, _)| dt);
        if dt_contact < dt_elem {
            warnings.push(format!(
                "the contact penalty springs limit the time step to {dt_contact:.3e} s, below the element step {dt_elem:.3e} s (lower SLSFAC on *CONTROL_CONTACT for the element step)"
            ));
        }
    }
    Ok((solver, warnings))
}

/// Each history node of the deck: its id and the solved nodes that are its copies (`origin`:
/// the deck node of each solved node of a split model; itself when the model is not split).
fn history_copies(deck: &Model, origin: Option<&[u32]>) -> Vec<(i64, Vec<u32>)> {
    let copies = origin.map(|o| copies_of(o, deck.num_nodes()));
    deck.output
        .history_nodes
        .iter()
        .map(|&n| {
            let list = copies.as_ref().map_or(vec![n], |c| c.of(n).to_vec());
            (deck.node_ids[n as usize], list)
        })
        .collect()
}

/// A rayon pool of `threads` workers (all cores by default).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, Failure> {
    let n = threads.unwrap_or(0);
    if threads == Some(0) {
        return Err(Failure::Input("--threads 0: give at least 1".into()));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| Failure::Other(format!("cannot start worker threads: {e}")))
}

pub fn run(a: &RunArgs) -> Result<(), Failure> {
    let started = Instant::now();
    let resume = a.restart.as_deref().map(restart::read).transpose()?;
    if let Some(t) = a.checkpoint_every {
        if !(t.is_finite() && t > 0.0) {
            return Err(Failure::Input(format!(
                "--checkpoint-every {t}: must be a positive time"
            )));
        }
    }
    // a continued run keeps its end time unless told another
    let end_time = a.end_time.or(resume.as_ref().map(|r| r.header.end_time));
    let mut deck_model = load_model(&a.deck, end_time, a.no_separation)?;
    let fingerprint = restart::fingerprint(&mut deck_model);
    if let (Some(r), Some(file)) = (&resume, &a.restart) {
        r.header
            .check(file, &a.deck, fingerprint, a.no_separation, a.gpu)?;
        if deck_model.control.end_time <= r.header.t {
            return Err(Failure::Input(format!(
                "--restart {}: it holds the state at t = {:e}, not before the end time {:e}: give a later --end-time",
                file.display(),
                r.header.t,
                deck_model.control.end_time
            )));
        }
    }
    let pool = thread_pool(a.threads)?;
    let dir = a.out.clone().unwrap_or_else(|| default_out_dir(&a.deck));
    let Prepared {
        model,
        interfaces,
        history_nodes,
        deck_nodes,
    } = prepare(deck_model);
    let model = &model;
    let split = interfaces.is_some();
    let (mut solver, warnings) = start_solver(model, interfaces)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let cannot_continue = |e: String| {
        Failure::Input(format!(
            "--restart {}: cannot continue from it: {e}",
            a.restart.as_deref().unwrap_or(Path::new("")).display()
        ))
    };
    if let (Some(r), false) = (&resume, a.gpu) {
        solver.restore_state(&r.solver).map_err(cannot_continue)?;
    }
    // the GPU: found and the deck checked before any output is written
    let mut gpu = if a.gpu {
        // what the GPU step lacks is refused before a device is looked for
        if let Some(what) = cleave_gpu::support::unsupported(model, &solver.setup) {
            return Err(cleave_gpu::GpuError::Unsupported(what).into());
        }
        let mut stepper = cleave_gpu::GpuStepper::new(cleave_gpu::Gpu::new()?, &mut solver)?;
        // a GPU run's restart file holds the device's state
        if let Some(r) = &resume {
            stepper
                .load(&mut solver, &r.solver)
                .map_err(cannot_continue)?;
        }
        if !a.quiet {
            eprintln!("running on the GPU: {}", stepper.gpu().describe());
        }
        Some(stepper)
    } else {
        None
    };
    let progress = Progress::new(model.control.end_time, a.quiet);
    let mut out = RunOutput::create(
        &dir,
        model,
        history_nodes,
        split,
        progress,
        resume.as_ref().map(|r| &r.output),
    )
    .map_err(|e| io_failure("cannot create output in", &dir, e))?;
    let device = gpu
        .as_ref()
        .map_or("cpu".into(), |g| format!("gpu: {}", g.gpu().info.name));
    let threads = pool.current_num_threads();
    let mut status = RunStatus::new(
        dir.join("summary.json"),
        deck_nodes,
        threads,
        device,
        warnings,
        started,
    );
    status.first_step = solver.state.step;
    out.status = Some(status);
    {
        // signals stop the loop between two steps (the GPU's at its next halt), with a
        // restart file
        let interrupt = Interrupt::listen()
            .map_err(|e| Failure::Other(format!("cannot listen to signals: {e}")))?;
        let header = restart::Header {
            version: env!("CARGO_PKG_VERSION").into(),
            deck: a.deck.display().to_string(),
            fingerprint,
            no_separation: a.no_separation,
            gpu: a.gpu,
            end_time: model.control.end_time,
            t: 0.0,
            step: 0,
        };
        out.checkpoints = Some(Checkpoints::new(
            a.checkpoint_every,
            &dir,
            header,
            Some(interrupt),
            solver.state.t,
        ));
    }
    let loop_start = Instant::now();
    if let Some(st) = &mut out.status {
        st.loop_start = loop_start;
    }
    let result = match &mut gpu {
        Some(g) => g.run_checkpointed(&mut solver, &mut out),
        None => pool.install(|| solver.run(&mut out)),
    };
    let loop_seconds = loop_start.elapsed().as_secs_f64();
    out.finish()
        .map_err(|e| io_failure("cannot write output in", &dir, e))?;
    if let Some(w) = out.energy_warning() {
        if !a.quiet {
            eprintln!("warning: {w}");
        }
        if let Some(st) = &mut out.status {
            st.warnings.push(w);
        }
    }
    let state = match &result {
        Ok(()) if solver.is_finished() => "finished",
        Ok(()) => "interrupted",
        Err(_) => "failed",
    };
    out.write_summary(&solver, state)
        .map_err(|e| io_failure("cannot write the summary in", &dir, e))?;
    match result {
        Ok(()) if !solver.is_finished() => {
            let c = out.checkpoints.as_ref();
            let sig = c.and_then(|c| c.stopped_by).unwrap_or(0);
            let file = c.map_or(dir.join(restart::FILE), |c| c.path().to_path_buf());
            Err(Failure::Interrupted(
                format!(
                    "{} at t = {:e}, step {}; the restart file {} holds this state and the output in {} is complete up to it: continue with `cleave run {} --restart {}{}`",
                    signal_name(sig),
                    solver.state.t,
                    solver.state.step,
                    file.display(),
                    dir.display(),
                    a.deck.display(),
                    file.display(),
                    if a.gpu { " --gpu" } else { "" }
                ),
                sig,
            ))
        }
        Ok(()) => {
            if !a.quiet {
                let steps = solver.state.step + 1;
                let looped = (steps - out.status.as_ref().map_or(0, |s| s.first_step)).max(1);
                let us = 1e6 * loop_seconds / (looped as f64 * model.num_elements().max(1) as f64);
                let on = match &gpu {
                    Some(g) => format!("GPU {}", g.gpu().info.name),
                    None => format!("{threads} threads"),
                };
                eprintln!(
                    "done: {} steps to t = {:e} in {:.2} s ({:.4} us per element step, {on}), energy ratio {:.5}; output in {}",
                    steps,
                    solver.state.t,
                    loop_seconds,
                    us,
                    out.energy.last().map_or(1.0, |r| r.ratio),
                    dir.display()
                );
            }
            Ok(())
        }
        Err(RunError::Solver(e)) => {
            let mut f = Failure::from(e);
            if let Failure::Numerical(m) = &mut f {
                m.push_str(&format!(
                    "; the output up to this point is in {}",
                    dir.display()
                ));
            }
            Err(f)
        }
        Err(RunError::Output(e)) => Err(io_failure("cannot write output in", &dir, e)),
        Err(RunError::Device(m)) => Err(Failure::Other(format!(
            "{m}; the output up to this point is in {}",
            dir.display()
        ))),
    }
}
