//! Keeping a pool's workers awake through a run ([`KeepAwake`]).
//!
//! A step of an explicit code is a chain of short parallel loops (the elements colour by
//! colour, the interface checks, the contact's passes, the averaging, the nodal updates) with
//! short serial parts between them (the ordered force scatters, the time step, the energy
//! sums). A rayon worker that finds no work spins a little and then sleeps; the next parallel
//! loop wakes it, and on this project's virtual machine (2 vCPUs, KVM) a wake-up costs tens of
//! microseconds, about as much as a loop of the 2800-element ball's step. Measured with a
//! scratch program (2 threads, 2000 steps, each a serial part then parallel loops of 147 us on
//! two threads): with a serial part of about 22 us, 179-206 us a step where about 169 are the
//! ideal; with about 155 us, 334-349 us where about 302 are; with the workers kept polling,
//! 168-179 and 306-311 us. On the 2800-element ball, two threads: 0.2932-0.3019 us per element
//! step before, 0.2712-0.2811 after (BENCHMARKS.md, session 12).
//!
//! So, as OpenMP runtimes do by default for a while (`OMP_WAIT_POLICY=active`), the workers
//! other than the one running the step poll the pool for jobs while the run goes on
//! ([`rayon::yield_now`], which runs any job another thread shares), and never fall asleep.
//! They take work the moment it is offered; the cost is that the run keeps every core of its
//! pool busy until it ends. Results do not change: which thread runs a job never changes what
//! the job computes (the determinism of the step, module docs of `solver`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// While alive, the other workers of the current rayon pool poll it for jobs instead of
/// sleeping (module docs). A no-op outside a pool or in a pool of one thread.
#[must_use = "the workers poll only while the guard lives"]
pub struct KeepAwake {
    stop: Option<Arc<AtomicBool>>,
}

impl KeepAwake {
    /// Start polling on every worker of the current pool but this one.
    ///
    /// One job per worker ([`rayon::spawn_broadcast`]); this thread's returns at once, so
    /// this thread never gets stuck in a polling loop while it waits for a join.
    pub fn start() -> Self {
        let (Some(me), n) = (rayon::current_thread_index(), rayon::current_num_threads()) else {
            return Self { stop: None };
        };
        if n < 2 {
            return Self { stop: None };
        }
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        rayon::spawn_broadcast(move |ctx| {
            if ctx.index() == me {
                return;
            }
            while !flag.load(Ordering::Acquire) {
                if rayon::yield_now() != Some(rayon::Yield::Executed) {
                    // nothing to do: let the OS run another thread if one waits for this core
                    std::thread::yield_now();
                }
            }
        });
        Self { stop: Some(stop) }
    }

    /// Whether workers were set polling.
    pub fn is_active(&self) -> bool {
        self.stop.is_some()
    }
}

impl Drop for KeepAwake {
    fn drop(&mut self) {
        if let Some(stop) = &self.stop {
            stop.store(true, Ordering::Release);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    fn pool(n: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    }

    #[test]
    fn outside_a_pool_and_with_one_thread_nothing_polls() {
        assert!(!KeepAwake::start().is_active());
        assert!(!pool(1).install(KeepAwake::start).is_active());
    }

    #[test]
    fn parallel_loops_finish_and_give_the_same_sums_while_the_workers_poll() {
        // (a deadlock here would hang the test: the step's thread must never run a poller)
        let data: Vec<f64> = (0..100_000).map(|i| (i as f64).sqrt()).collect();
        let chunked =
            |d: &[f64]| -> Vec<f64> { d.par_chunks(1000).map(|c| c.iter().sum()).collect() };
        let expected = chunked(&data);
        for threads in [2, 3] {
            pool(threads).install(|| {
                let guard = KeepAwake::start();
                assert!(guard.is_active());
                for _ in 0..200 {
                    assert_eq!(chunked(&data), expected);
                    let (a, b) =
                        rayon::join(|| chunked(&data[..50_000]), || chunked(&data[50_000..]));
                    assert_eq!([a, b].concat(), expected);
                }
            });
        }
    }

    #[test]
    fn the_pollers_stop_with_the_guard() {
        let p = pool(2);
        let flag = p.install(|| {
            let guard = KeepAwake::start();
            Arc::clone(guard.stop.as_ref().unwrap())
        });
        assert!(flag.load(Ordering::Acquire));
        // the pool is free again: a job on every worker completes
        let ran = p.broadcast(|_| 1);
        assert_eq!(ran.iter().sum::<i32>(), 2);
    }
}
