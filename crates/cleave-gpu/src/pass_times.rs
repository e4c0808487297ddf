//! Device time of each pass over a whole run ([`crate::GpuStepper::time_passes`]): each pass
//! of the steps a run records goes in a compute pass of its own, with a timestamp at its start
//! and end, and the times are summed per pass as the batches come back. Unlike the profile of a
//! few steps at the start (`GpuStepper::profile`), this covers the steps that halt for the host
//! (a split, a crack released) and the rest of such a step, so it shows where a breaking
//! model's time goes. Left out: the steps a batch recorded past a halt (they run idle, each
//! pass returning at once) and the one dispatch at a batch's start that ends a halted step.
//! For benchmarks: separate compute passes cost more than a plain batch's one.

use std::cell::RefCell;

use crate::device::Gpu;

/// Timestamp queries a batch may use (wgpu's limit per query set).
const QUERIES: usize = wgpu::QUERY_SET_MAX_QUERIES as usize;

/// The query sets of the two batches in flight and of the rest of a halted step, and the
/// seconds summed so far per pass.
pub(crate) struct PassTimes {
    /// Per slot (0, 1: the batches' staging; 2: the rest of a step): the queries, their
    /// resolved values, the read-back, and the pass of each pair recorded.
    slots: [Slot; 3],
    /// Seconds per pass (in the step's order), summed over the batches read back.
    pub secs: Vec<f64>,
    /// Seconds per timestamp tick.
    period: f64,
    /// Steps a batch may hold (two queries per pass and step).
    pub max_steps: usize,
}

struct Slot {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    passes: RefCell<Vec<usize>>,
}

impl PassTimes {
    /// For a step of `passes` passes; `None` when the device has no timestamp queries.
    pub fn new(gpu: &Gpu, passes: usize) -> Option<Self> {
        if !gpu.timestamps || passes == 0 {
            return None;
        }
        let dev = &gpu.device;
        let bytes = 8 * QUERIES as u64;
        let slot = |k: usize| Slot {
            set: dev.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(["pass times 0", "pass times 1", "pass times 2"][k]),
                ty: wgpu::QueryType::Timestamp,
                count: QUERIES as u32,
            }),
            resolve: dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass times resolved"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            read: dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pass times read-back"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            passes: RefCell::new(Vec::new()),
        };
        Some(PassTimes {
            slots: [slot(0), slot(1), slot(2)],
            secs: vec![0.0; passes],
            period: f64::from(gpu.queue.get_timestamp_period()) * 1e-9,
            max_steps: (QUERIES / (2 * passes)).max(1),
        })
    }

    /// Start recording `slot` again: times recorded there and never collected are dropped.
    pub fn begin(&self, slot: usize) {
        self.slots[slot].passes.borrow_mut().clear();
    }

    /// The timestamps of the next compute pass recorded in `slot`, which runs pass `pass` of
    /// the step; `None` when the slot's queries are used up (the pass is then not timed).
    pub fn writes(&self, slot: usize, pass: usize) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let s = &self.slots[slot];
        let mut recorded = s.passes.borrow_mut();
        let q = 2 * recorded.len();
        if q + 2 > QUERIES {
            return None;
        }
        recorded.push(pass);
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &s.set,
            beginning_of_pass_write_index: Some(q as u32),
            end_of_pass_write_index: Some(q as u32 + 1),
        })
    }

    /// Record the resolve and read-back of the queries of `slot` (after its passes).
    pub fn finish(&self, enc: &mut wgpu::CommandEncoder, slot: usize) {
        let s = &self.slots[slot];
        let n = 2 * s.passes.borrow().len() as u32;
        if n > 0 {
            enc.resolve_query_set(&s.set, 0..n, &s.resolve, 0);
            enc.copy_buffer_to_buffer(&s.resolve, 0, &s.read, 0, 8 * u64::from(n));
        }
    }

    /// Add the times of the first `steps` steps of the batch recorded in `slot` (0 or 1: the
    /// staging of its control block), once its submission has run: those it ran before a halt,
    /// the halting step's included. The slot is then free for the next batch.
    pub fn collect(&mut self, gpu: &Gpu, slot: usize, steps: usize) {
        self.add(gpu, slot, steps * self.secs.len());
    }

    /// Add the times of the rest of a halted step (slot 2), if one was recorded since, once a
    /// submission after it has run.
    pub fn collect_rest(&mut self, gpu: &Gpu) {
        self.add(gpu, 2, usize::MAX);
    }

    /// Add the times of the first `keep` passes recorded in `slot`.
    fn add(&mut self, gpu: &Gpu, slot: usize, keep: usize) {
        let s = &self.slots[slot];
        let mut passes = std::mem::take(&mut *s.passes.borrow_mut());
        passes.truncate(keep);
        if passes.is_empty() {
            return;
        }
        let bytes = 16 * passes.len() as u64;
        s.read.slice(..bytes).map_async(wgpu::MapMode::Read, |_| {});
        gpu.wait();
        if let Ok(view) = s.read.slice(..bytes).get_mapped_range() {
            let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&view);
            for (k, &p) in passes.iter().enumerate() {
                if let Some(t) = self.secs.get_mut(p) {
                    *t += ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * self.period;
                }
            }
        }
        s.read.unmap();
    }
}
