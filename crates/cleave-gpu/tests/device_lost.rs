//! A device that fails in the middle of a run (lost: its driver reset it, or it was
//! destroyed) stops the run with an error that says so, at the last time the host read; it
//! neither panics (wgpu's default error handler would) nor hands the observer what a lost
//! device reads back.

mod common;

use cleave_core::model::Hourglass;
use cleave_core::solver::{Observer, RunError, Solver};
use cleave_gpu::{Checkpointing, GpuStepper};
use common::{block, gpu};

/// Takes output every microsecond and destroys the device at the second output.
struct Destroy {
    dev: wgpu::Device,
    times: Vec<f64>,
}

impl Observer for Destroy {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.times.push(s.state.t);
        if self.times.len() == 2 {
            self.dev.destroy();
        }
        Ok(())
    }
    fn next_due(&self) -> f64 {
        1e-6 * self.times.len() as f64
    }
}

#[test]
fn a_device_lost_mid_run_stops_it_with_a_clear_error() {
    let Some(g) = gpu() else { return };
    let dev = g.device.clone();
    let m = block(Hourglass::Viscous);
    let mut s = Solver::new(&m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut obs = Destroy { dev, times: vec![] };
    let r = st.run(&mut s, &mut obs);
    let Err(RunError::Device(msg)) = r else {
        panic!("the run goes on or fails otherwise: {r:?}");
    };
    assert!(msg.contains("the device was lost"), "{msg}");
    // no output after the loss, and the host's state that of the last output
    assert_eq!(obs.times.len(), 2);
    assert_eq!(s.state.t, obs.times[1]);
    assert!(
        msg.contains(&format!("after t = {:e}", obs.times[1])),
        "{msg}"
    );
}

/// [`Destroy`] with a restart file due at every output: the one of the output at which the
/// device is destroyed is not handed over (it would hold what a lost device reads back).
struct DestroyAndKeep {
    inner: Destroy,
    kept: Vec<f64>,
}

impl Observer for DestroyAndKeep {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.inner.observe(s)
    }
    fn next_due(&self) -> f64 {
        self.inner.next_due()
    }
}

impl Checkpointing for DestroyAndKeep {
    fn checkpoint_due(&self) -> f64 {
        1e-6 * self.kept.len() as f64
    }
    fn stop_asked(&mut self) -> bool {
        false
    }
    fn checkpoint(&mut self, s: &Solver, _: Vec<u8>) -> std::io::Result<()> {
        self.kept.push(s.state.t);
        Ok(())
    }
}

#[test]
fn no_restart_file_is_handed_over_after_the_device_is_lost() {
    let Some(g) = gpu() else { return };
    let dev = g.device.clone();
    let m = block(Hourglass::Viscous);
    let mut s = Solver::new(&m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut obs = DestroyAndKeep {
        inner: Destroy { dev, times: vec![] },
        kept: vec![],
    };
    let r = st.run_checkpointed(&mut s, &mut obs);
    assert!(matches!(r, Err(RunError::Device(_))), "{r:?}");
    assert_eq!(obs.inner.times.len(), 2);
    // the restart file of the first output only
    assert_eq!(obs.kept, vec![obs.inner.times[0]]);
}

/// Takes output every microsecond and keeps the host's positions at each.
struct Keep {
    times: Vec<f64>,
    x: Vec<Vec<[f64; 3]>>,
}

impl Observer for Keep {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.times.push(s.state.t);
        self.x.push(s.positions().iter().copied().collect());
        Ok(())
    }
    fn next_due(&self) -> f64 {
        1e-6 * self.times.len() as f64
    }
}

/// A device lost during the read of the host's mirror (destroyed as the read starts): nothing
/// of what it read back reaches the host, whose state stays that of the last output (finite
/// positions, the same bits), and the run stops with the device's error.
#[test]
fn a_device_lost_in_the_mirrors_read_leaves_the_host_state_of_the_last_output() {
    let Some(g) = gpu() else { return };
    let m = block(Hourglass::Viscous);
    let mut s = Solver::new(&m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    st.lose_device_in_read(3);
    let mut obs = Keep {
        times: vec![],
        x: vec![],
    };
    let r = st.run(&mut s, &mut obs);
    let Err(RunError::Device(msg)) = r else {
        panic!("the run goes on or fails otherwise: {r:?}");
    };
    assert!(msg.contains("the device was lost"), "{msg}");
    assert!(obs.times.len() >= 2, "{:?}", obs.times);
    let last = obs.x.last().unwrap();
    assert_eq!(s.state.t, *obs.times.last().unwrap());
    let now: Vec<[f64; 3]> = s.positions().iter().copied().collect();
    assert!(now.iter().flatten().all(|v| v.is_finite()));
    assert_eq!(&now, last);
}
