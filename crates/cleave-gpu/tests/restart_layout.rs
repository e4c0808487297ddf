//! The layout of the GPU state in a restart file stays that of the host, whatever the device
//! stores: the positions of one step (the device keeps two), and the stresses and hourglass
//! forces element by element (the device keeps them by component). A file written before the
//! device's layout changed must still be taken up (`GpuStepper::save`, `load`).

mod common;

use cleave_core::model::Hourglass;
use cleave_core::solver::{Observer, Solver};
use cleave_gpu::{Checkpointing, GpuStepper};
use common::{block, gpu};

/// A saved state, the step it was taken at, and the mirror's positions, stresses and
/// hourglass forces there.
type Taken = (Vec<u8>, u64, Vec<f64>, Vec<f64>, Vec<f64>);

/// Halts at `at` and at the step after, and keeps the states the GPU hands over there with
/// the mirror's arrays (two steps in a row: the device's positions in either half).
struct TakeTwo {
    at: f64,
    taken: Vec<Taken>,
}

impl Observer for TakeTwo {
    fn observe(&mut self, _: &Solver) -> std::io::Result<()> {
        Ok(())
    }
    fn next_due(&self) -> f64 {
        f64::INFINITY
    }
}

impl Checkpointing for TakeTwo {
    fn checkpoint_due(&self) -> f64 {
        match self.taken.len() {
            0 => self.at,
            1 => self.at * (1.0 + 1e-9),
            _ => f64::INFINITY,
        }
    }
    fn stop_asked(&mut self) -> bool {
        false
    }
    fn checkpoint(&mut self, s: &Solver, gpu_state: Vec<u8>) -> std::io::Result<()> {
        let x: Vec<f64> = s.positions().entries().iter().flatten().copied().collect();
        let sig: Vec<f64> = s.state.stress.iter().flatten().copied().collect();
        let hg: Vec<f64> = s.state.hg.iter().flatten().copied().collect();
        self.taken.push((gpu_state, s.state.step, x, sig, hg));
        // the next one at the step after this
        self.at = s.state.t;
        Ok(())
    }
}

/// The arrays of a saved state: each a length (u64) and its bytes, as f64s.
fn parts(bytes: &[u8]) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    let mut rest = bytes;
    while rest.len() >= 8 {
        let len = u64::from_le_bytes(rest[..8].try_into().unwrap()) as usize;
        let data = &rest[8..8 + len];
        out.push(
            data.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect(),
        );
        rest = &rest[8 + len..];
    }
    out
}

#[test]
fn a_saved_state_holds_the_hosts_layout() {
    let Some(g) = gpu() else { return };
    let m = block(Hourglass::Stiffness);
    let mut s = Solver::new(&m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut obs = TakeTwo {
        at: m.control.end_time / 3.0,
        taken: Vec::new(),
    };
    st.run_checkpointed(&mut s, &mut obs).unwrap();
    assert_eq!(obs.taken.len(), 2, "two states taken");
    assert_eq!(obs.taken[1].1, obs.taken[0].1 + 1, "two steps in a row");
    for (bytes, step, x, sig, hg) in &obs.taken {
        let p = parts(bytes);
        // the order of GpuStepper::save: control floats, control integers, x, v, v^n,
        // stresses, histories, hourglass forces, ...
        assert!(p.len() >= 11, "{} arrays", p.len());
        let nonzero = |a: &[f64]| a.iter().filter(|v| **v != 0.0).count();
        assert_eq!(p[2].len(), x.len(), "one step's positions, 3 per node");
        assert_eq!(&p[2], x, "the positions at step {step}");
        assert_eq!(p[5][..sig.len()], sig[..], "stresses element by element");
        assert_eq!(
            p[7][..hg.len()],
            hg[..],
            "hourglass forces element by element"
        );
        // (the state is not trivially zero: the block has been loaded and has yielded)
        assert!(nonzero(sig) > sig.len() / 2 && nonzero(hg) > hg.len() / 2);
        eprintln!(
            "state saved at step {step}: {} positions, {} stresses, {} hourglass values as on the host",
            x.len(),
            sig.len(),
            hg.len()
        );
    }
}

/// The positions at the end of a run, and the GPU state taken once at `at`.
struct EndAndOne {
    at: f64,
    state: Option<Vec<u8>>,
    end: Vec<f64>,
}

impl Observer for EndAndOne {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        if s.is_finished() {
            self.end = s.positions().entries().iter().flatten().copied().collect();
        }
        Ok(())
    }
    fn next_due(&self) -> f64 {
        f64::INFINITY
    }
}

impl Checkpointing for EndAndOne {
    fn checkpoint_due(&self) -> f64 {
        if self.state.is_none() {
            self.at
        } else {
            f64::INFINITY
        }
    }
    fn stop_asked(&mut self) -> bool {
        false
    }
    fn checkpoint(&mut self, _: &Solver, gpu_state: Vec<u8>) -> std::io::Result<()> {
        self.state = Some(gpu_state);
        Ok(())
    }
}

/// A state saved by a build whose control block was shorter (64 floats and 8 integers, before
/// the contact's energy and step and the erosion flag were added) is taken up, the missing
/// values zero and the contact's step the deck's, and the run ends in the same bits as the one
/// that went through.
#[test]
fn a_state_of_an_earlier_control_block_is_taken_up() {
    let Some(g) = gpu() else { return };
    let m = block(Hourglass::Viscous);
    let mut s = Solver::new(&m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut obs = EndAndOne {
        at: m.control.end_time / 2.0,
        state: None,
        end: Vec::new(),
    };
    st.run_checkpointed(&mut s, &mut obs).unwrap();
    let state = obs.state.expect("a state taken");
    // the first two arrays cut to the earlier lengths
    let mut old = Vec::new();
    let mut rest = &state[..];
    for k in 0.. {
        if rest.is_empty() {
            break;
        }
        let len = u64::from_le_bytes(rest[..8].try_into().unwrap()) as usize;
        let keep = match k {
            0 => 8 * 64,
            1 => 4 * 8,
            _ => len,
        };
        assert!(keep <= len);
        old.extend_from_slice(&(keep as u64).to_le_bytes());
        old.extend_from_slice(&rest[8..8 + keep]);
        rest = &rest[8 + len..];
    }
    assert!(old.len() < state.len());
    let mut s2 = Solver::new(&m).unwrap();
    let mut st2 = GpuStepper::new(st.into_gpu(), &mut s2).unwrap();
    st2.load(&mut s2, &old).unwrap();
    let mut again = EndAndOne {
        at: f64::INFINITY,
        state: Some(Vec::new()),
        end: Vec::new(),
    };
    st2.run_checkpointed(&mut s2, &mut again).unwrap();
    assert!(!obs.end.is_empty());
    assert!(again.end == obs.end, "the run taken up ends elsewhere");
}
