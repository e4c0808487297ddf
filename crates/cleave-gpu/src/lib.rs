//! The whole explicit step of cleave on one GPU, written with wgpu (WGSL compute shaders in
//! f64, `Features::SHADER_F64`), so that one code runs on NVIDIA, AMD, Intel and Apple hardware
//! and on Mesa's software Vulkan (lavapipe) on any CPU.
//!
//! The state lives on the GPU: the element pass, the time step (reduced on the GPU and used
//! there), the nodal update and the energy ledger run as four or more dispatches a step
//! (`step.wgsl` lists them), and the host records many steps into one submission. It reads back
//! a few control words per submission (time, step, whether a halt was asked for) and the state
//! only when the output asks for it ([`cleave_core::solver::Observer::next_due`]), a step fails,
//! or interfaces fail (element separation, `separation.rs`).
//! Every sum is taken in a fixed order (forces gathered per node from the corner forces of
//! its elements, in element order; tree reductions of fixed shape), so a run gives the same
//! bits every time on the same device. An array larger than the device binds is bound in parts
//! (`split.rs`).
//!
//! What runs on the GPU today: the CPU step's parts, element separation with its cohesive laws
//! (`separation.rs`: the sets split on the host in the step their interface fails, the arrays
//! they change rewritten in place, `relayout.rs`) and automatic contact, with the faces of
//! failed interfaces and eroded elements (`contact.rs`, `contact.wgsl`);
//! [`support::unsupported`] names what a deck asks that is not there yet, and
//! `cleave run --gpu` refuses such a deck with that name (exit 2), never a silent fallback to
//! the CPU.

mod by_entry;
mod contact;
mod contact_tables;
pub mod device;
pub mod layout;
mod pass_times;
mod relayout;
mod separation;
mod split;
pub mod stepper;
pub mod support;

pub use device::{Gpu, GpuError};
pub use stepper::{Checkpointing, GpuStepper};
