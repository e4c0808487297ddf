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
    /// The first failure the device reported: an error no call caught (wgpu's default
    /// handler panics on it), or the device lost (its driver reset it, or it was destroyed).
    /// A lost device reads back nothing, so the stepper asks here after each read-back and
    /// stops the run with this message ([`Gpu::failure`]).
    failed: Arc<Mutex<Option<String>>>,
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
        let failed = Arc::new(Mutex::new(None));
        let keep = |f: &Arc<Mutex<Option<String>>>| {
            let f = f.clone();
            move |what: String| {
                if let Ok(mut f) = f.lock() {
                    f.get_or_insert(what);
                }
            }
        };
        let on_error = keep(&failed);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            on_error(format!("the device reported an error: {e}"));
        }));
        let on_lost = keep(&failed);
        device.set_device_lost_callback(move |reason, msg| {
            let msg = if msg.is_empty() {
                msg
            } else {
                format!(": {msg}")
            };
            on_lost(format!("the device was lost ({reason:?}{msg})"));
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

    /// The first failure the device reported, if any: after it, nothing it computes or reads
    /// back can be trusted.
    pub fn failure(&self) -> Option<String> {
        self.failed.lock().map_or_else(
            |_| Some("the device's error record was poisoned".into()),
            |f| f.clone(),
        )
    }

    /// "NAME (backend, driver)".
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {} {})",
            self.info.name, self.info.backend, self.info.driver, self.info.driver_info
        )
    }
}
