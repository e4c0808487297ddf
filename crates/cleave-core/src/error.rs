//! Errors of the solver, with the entity, time and step they happened at.

use std::fmt;

/// Why a model cannot be run or a run stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum SolverError {
    /// The model is inconsistent in a way the deck reader cannot see (bad input: exit code 2).
    Setup(String),
    /// An element's volume became non-positive (exit code 3).
    InvertedElement { element: i64, time: f64, step: u64 },
    /// A nodal value became non-finite (exit code 3); `element`: an element of that node whose
    /// stress is not finite either (where the failure started), if there is one.
    NonFinite {
        node: i64,
        element: Option<i64>,
        time: f64,
        step: u64,
    },
    /// An energy of the ledger became non-finite (exit code 3); `at` names where (an element,
    /// a node, a rigid body) when that can be found.
    NonFiniteEnergy {
        energy: &'static str,
        at: String,
        time: f64,
        step: u64,
    },
    /// The time step collapsed or is not finite (exit code 3).
    BadTimeStep {
        dt: f64,
        element: i64,
        time: f64,
        step: u64,
    },
    /// The time step fell below the floor DTMIN x the first step (exit code 3).
    TimeStepTooSmall {
        dt: f64,
        floor: f64,
        element: i64,
        time: f64,
        step: u64,
    },
}

impl SolverError {
    /// True for failures of the numerics (exit code 3), false for bad input.
    pub fn is_numerical(&self) -> bool {
        !matches!(self, SolverError::Setup(_))
    }
}

impl fmt::Display for SolverError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolverError::Setup(m) => write!(f, "{m}"),
            SolverError::InvertedElement { element, time, step } => write!(
                f,
                "element {element} has a negative or zero volume at time {time:e} (step {step}); \
                 the mesh is too distorted: reduce TSSFAC, refine the mesh or raise the hourglass control"
            ),
            SolverError::NonFinite {
                node,
                element,
                time,
                step,
            } => write!(
                f,
                "node {node} has a non-finite velocity or position at time {time:e} (step {step}){}",
                element.map_or(String::new(), |e| format!(
                    "; element {e}, on it, has a non-finite stress"
                ))
            ),
            SolverError::NonFiniteEnergy {
                energy,
                at,
                time,
                step,
            } => write!(
                f,
                "the {energy} is not finite at time {time:e} (step {step}){}",
                if at.is_empty() { String::new() } else { format!(": {at}") }
            ),
            SolverError::BadTimeStep { dt, element, time, step } => write!(
                f,
                "the time step {dt:e} controlled by element {element} is not usable at time {time:e} (step {step})"
            ),
            SolverError::TimeStepTooSmall {
                dt,
                floor,
                element,
                time,
                step,
            } => write!(
                f,
                "the time step {dt:e} controlled by element {element} fell below the floor {floor:e} (DTMIN of *CONTROL_TERMINATION times the first step) at time {time:e} (step {step}): the element is collapsing"
            ),
        }
    }
}

impl std::error::Error for SolverError {}
