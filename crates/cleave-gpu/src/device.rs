//! Finding a GPU that computes in f64.

use std::fmt;
use std::sync::{Arc, Mutex};

/// Why the GPU step cannot run a deck.
#[derive(Debug, Clone, PartialEq)]
pub enum GpuError {
    /// No adapter with 64-bit float shaders (`SHADER_F64`) was found.
    NoDevice(String),
    /// The deck asks for a feature that is not on the GPU yet (bad input for `--gpu`).
    Unsupported(String),
    /// An array of the model is larger than the device binds at once.
    TooLarge(String),
    /// The device failed while the step was made (lost, or an error it reported).
    Failed(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoDevice(m) => write!(f, "--gpu: {m}"),
            GpuError::Unsupported(m) => {
                write!(f, "--gpu does not run {m} yet; run this deck without --gpu")
            }
            GpuError::TooLarge(m) => write!(f, "--gpu: {m}"),
            GpuError::Failed(m) => write!(f, "--gpu: the GPU failed: {m}"),
        }
    }
}

impl std::error::Error for GpuError {}

/// A device and queue with `SHADER_F64`, and what the adapter is.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// Whether the device was opened with timestamp queries (`GpuStepper::profile`).
    pub timestamps: bool,
    /// Arrays to bind in parts of at most this many bytes, whatever the device binds, by
    /// their names in step.wgsl: for the tests of the splitting (split.rs) on devices that
    /// bind few arrays (lavapipe: 32, of which the step uses 31). Empty by default.
    pub force_split: Vec<(String, u64)>,
    /// The failures the device reported: the first error no call caught (wgpu's default
    /// handler panics on it), and the loss of the device (its driver reset it, or it was
    /// destroyed), which comes after the errors of the calls it fails. A lost device reads
    /// back nothing, so the stepper asks after each read-back and stops the run with the
    /// loss, or else the error ([`Gpu::failure`]).
    failed: Arc<Mutex<Failures>>,
}

impl Gpu {
    /// The first adapter that has f64 shaders, preferring a discrete, then an integrated GPU,
    /// then any (lavapipe, Mesa's Vulkan on the CPU, last).
    pub fn new() -> Result<Self, GpuError> {
        // wgpu checks the arguments of every indirect dispatch, in release builds too, by a
        // dispatch of its own and two barriers before each: two of the step's passes are
        // indirect (those over the node entries in use, and the softening faces'), and their
        // arguments are written by the host alone (separation.rs node_grid, Cohesive::groups),
        // within the limits, so the check is left off
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.flags
            .remove(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
        let instance = wgpu::Instance::new(desc);
        let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        if adapters.is_empty() {
            return Err(GpuError::NoDevice(
                "no GPU adapter found (Vulkan, Metal or DX12; on Linux without a GPU, Mesa's software Vulkan: apt-get install mesa-vulkan-drivers)".into(),
            ));
        }
        let rank = |a: &wgpu::Adapter| match a.get_info().device_type {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Other => 3,
            wgpu::DeviceType::Cpu => 4,
        };
        adapters.sort_by_key(rank);
        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        let Some(adapter) = adapters
            .into_iter()
            .find(|a| a.features().contains(wgpu::Features::SHADER_F64))
        else {
            return Err(GpuError::NoDevice(format!(
                "no adapter computes in 64-bit floats (SHADER_F64); found: {}",
                names.join(", ")
            )));
        };
        let limits = adapter.limits();
        // timestamps, where the device has them, time each pass in `cleave bench --gpu`
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = wgpu::Features::SHADER_F64;
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("cleave"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice(format!("cannot open {}: {e}", names[0])))?;
        let failed: Arc<Mutex<Failures>> = Arc::default();
        let on_error = failed.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            record(
                &on_error,
                false,
                format!("the device reported an error: {e}"),
            );
        }));
        let on_lost = failed.clone();
        device.set_device_lost_callback(move |reason, msg| {
            let msg = if msg.is_empty() {
                msg
            } else {
                format!(": {msg}")
            };
            record(
                &on_lost,
                true,
                format!("the device was lost ({reason:?}{msg})"),
            );
        });
        Ok(Self {
            device,
            queue,
            info: adapter.get_info(),
            limits,
            timestamps,
            force_split: vec![],
            failed,
        })
    }

    /// The device's loss, or else the first error it reported, if any: after either, nothing
    /// it computes or reads back can be trusted.
    pub fn failure(&self) -> Option<String> {
        self.failed.lock().map_or_else(
            |_| Some("the device's error record was poisoned".into()),
            |f| f.lost.clone().or_else(|| f.error.clone()),
        )
    }

    /// Wait until the device has done the work submitted. A device lost in the wait makes wgpu
    /// panic (wgpu 30's `Device::poll` has no error for a lost device in a fence wait): that
    /// panic is caught here and kept as the device's loss ([`Gpu::failure`]), without the
    /// panic hook's message (the hook is wrapped once to stay silent for it).
    pub fn wait(&self) {
        wait_with(&self.failed, || {
            let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
        });
    }

    /// "NAME (backend, driver)".
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {} {})",
            self.info.name, self.info.backend, self.info.driver, self.info.driver_info
        )
    }
}

/// What [`Gpu::failure`] reports.
#[derive(Default)]
struct Failures {
    /// The first error no call caught.
    error: Option<String>,
    /// The device's loss.
    lost: Option<String>,
}

/// Keep `what` as the device's loss (`lost`) or, if it is the first, its error.
fn record(failed: &Mutex<Failures>, lost: bool, what: String) {
    if let Ok(mut f) = failed.lock() {
        match lost {
            true => f.lost.get_or_insert(what),
            false => f.error.get_or_insert(what),
        };
    }
}

thread_local! {
    /// Whether this thread is in [`wait_with`] (the panic hook then stays silent).
    static WAITING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Run `wait`; a panic in it is kept in `failed` as the device's loss instead.
fn wait_with(failed: &Mutex<Failures>, wait: impl FnOnce()) {
    static QUIET: std::sync::Once = std::sync::Once::new();
    QUIET.call_once(|| {
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !WAITING.with(|w| w.get()) {
                hook(info);
            }
        }));
    });
    WAITING.with(|w| w.set(true));
    let got = std::panic::catch_unwind(std::panic::AssertUnwindSafe(wait));
    WAITING.with(|w| w.set(false));
    if let Err(p) = got {
        let why = (p.downcast_ref::<String>().map(String::as_str))
            .or_else(|| p.downcast_ref::<&str>().copied())
            .unwrap_or("no message");
        let what = format!("the device was lost while the host waited for it ({why})");
        record(failed, true, what);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wait that panics (as wgpu's poll does for a device lost in it) is kept as the loss,
    /// which wins over an error reported before; a wait that returns records nothing.
    #[test]
    fn a_panic_in_a_wait_is_kept_as_the_device_lost() {
        let failed = Mutex::new(Failures::default());
        wait_with(&failed, || {});
        assert!(failed.lock().unwrap().lost.is_none());
        record(&failed, false, "an error".into());
        wait_with(&failed, || panic!("Error in Device::poll: lost"));
        let f = failed.lock().unwrap();
        assert_eq!(f.error.as_deref(), Some("an error"));
        let lost = f.lost.as_deref().unwrap();
        assert!(
            lost.contains("waited") && lost.contains("Device::poll: lost"),
            "{lost}"
        );
    }
}
