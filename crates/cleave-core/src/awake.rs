//! Keeping a pool's workers awake through a run ([`KeepAwake`]).
//!
//! A step of an explicit code is a chain of short parallel loops (the elements colour by
//! colour, the interface checks, the contact's passes, the nodal updates) with
//! short serial parts between them (the ordered force scatters, the time step, the energy
//! sums). A rayon worker that finds no work spins a little and then sleeps; the next parallel
//! loop wakes it, and on this project's virtual machine (2 vCPUs, KVM) a wake-up costs tens of
//! microseconds, about as much as a loop of the 2800-element ball's step. Measured with a
//! scratch program (2 threads, 2000 steps, each a serial part then parallel loops of 147 us on
//! two threads): with a serial part of about 22 us, 179-206 us a step where about 169 are the
//! ideal; with about 155 us, 334-349 us where about 302 are; with the workers kept polling,
//! 168-179 and 306-311 us. On the 2800-element ball, two threads: 0.2932-0.3019 us per element
//! step before, 0.2712-0.2811 after (the history of BENCHMARKS.md).
//!
//! So, as an OpenMP runtime does with `OMP_WAIT_POLICY=active` (its default spins a while and
//! then sleeps), the workers other than the one running the step poll the pool for jobs while
//! the run goes on ([`rayon::yield_now`], which runs any job another thread shares), and do not
//! sleep between jobs. They take work the moment it is offered. Wake-ups are fewer, not gone: a
//! worker inside a job that waits for a join, or the step's thread waiting for a half another
//! worker took, may still sleep in rayon's wait. The cost is that the run keeps every core of
//! its pool busy until it ends. Results do not change: which thread runs a job never changes
//! what the job computes (the determinism of the step, module docs of `solver`).
//!
//! Several runs in one pool at once: each thread polls for at most one of them, and a thread
//! running a guarded run polls for none ([`KeepAwake::start`]). Otherwise a run's thread,
//! waiting for a join, would take another run's polling job from its broadcast queue and spin
//! in it until that run ended, while that run's thread did the same: a deadlock (the test
//! `two_guarded_runs_at_once_in_one_pool_finish`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// While alive, the other workers of the current rayon pool poll it for jobs instead of
/// sleeping (module docs). A no-op outside a pool or in a pool of one thread.
#[must_use = "the workers poll only while the guard lives"]
pub struct KeepAwake {
    stop: Option<Arc<AtomicBool>>,
    /// `BUSY` as it was before `start`, restored on drop.
    was_busy: bool,
    /// The guard must drop on the thread that started it (it restores a thread-local).
    _not_send: std::marker::PhantomData<*const ()>,
}

thread_local! {
    /// Set while this thread runs a guarded run or a polling job. A polling job of another
    /// run that reaches such a thread (its broadcast queue is read in any join wait) returns
    /// at once instead of parking the frames below it until that other run ends.
    static BUSY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

impl KeepAwake {
    /// Start polling on every worker of the current pool but this one.
    ///
    /// One job per worker ([`rayon::spawn_broadcast`], read by that worker only, before it
    /// steals). This thread's returns at once, and so does one reaching a thread that already
    /// polls or runs a guarded run (the thread-local `BUSY`, which this guard sets here and
    /// restores when it drops, on this thread: the guard is not `Send`). So no thread ever
    /// polls for a run while it runs one, or polls for two.
    pub fn start() -> Self {
        let (Some(me), n) = (rayon::current_thread_index(), rayon::current_num_threads()) else {
            return Self::inactive();
        };
        if n < 2 {
            return Self::inactive();
        }
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        rayon::spawn_broadcast(move |ctx| {
            if ctx.index() == me || BUSY.get() {
                return;
            }
            BUSY.set(true);
            while !flag.load(Ordering::Acquire) {
                if rayon::yield_now() != Some(rayon::Yield::Executed) {
                    // nothing to do: let the OS run another thread if one waits for this core
                    std::thread::yield_now();
                }
            }
            BUSY.set(false);
        });
        Self {
            stop: Some(stop),
            was_busy: BUSY.replace(true),
            _not_send: std::marker::PhantomData,
        }
    }

    fn inactive() -> Self {
        Self {
            stop: None,
            was_busy: false,
            _not_send: std::marker::PhantomData,
        }
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
            BUSY.set(self.was_busy);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::time::{Duration, Instant};

    fn pool(n: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    }

    /// Run `f` on its own thread: a hang (a deadlock of the polling) fails after `secs`.
    fn within(secs: u64, f: impl FnOnce() + Send + 'static) {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            f();
            let _ = tx.send(());
        });
        rx.recv_timeout(Duration::from_secs(secs))
            .expect("the polling deadlocked");
    }

    #[test]
    fn outside_a_pool_and_with_one_thread_nothing_polls() {
        assert!(!KeepAwake::start().is_active());
        assert!(!pool(1).install(|| KeepAwake::start().is_active()));
    }

    #[test]
    fn parallel_loops_finish_and_give_the_same_sums_while_the_workers_poll() {
        within(60, || {
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
        });
    }

    #[test]
    fn the_polling_jobs_end_with_the_guard() {
        // each polling job's closure holds a clone of the flag until every copy has returned
        let p = pool(3);
        let flag = p.install(|| {
            let guard = KeepAwake::start();
            std::thread::sleep(Duration::from_millis(10));
            Arc::clone(guard.stop.as_ref().unwrap())
        });
        assert!(flag.load(Ordering::Acquire));
        let deadline = Instant::now() + Duration::from_secs(10);
        while Arc::strong_count(&flag) > 1 {
            assert!(
                Instant::now() < deadline,
                "a worker still polls after the guard dropped"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn two_guarded_runs_at_once_in_one_pool_finish() {
        // run Y starts its guard before run X: each run's thread then finds the other run's
        // polling job in its broadcast queue when it waits for a stolen half
        within(20, || {
            let p = pool(3);
            let data: Vec<f64> = (0..100_000).map(|i| i as f64).collect();
            let y_started = AtomicBool::new(false);
            let steps = || {
                for _ in 0..1000 {
                    data.par_chunks(1000)
                        .map(|c| c.iter().sum::<f64>())
                        .sum::<f64>();
                }
            };
            p.install(|| {
                rayon::join(
                    || {
                        while !y_started.load(Ordering::Acquire) {
                            std::hint::spin_loop();
                        }
                        let _x = KeepAwake::start();
                        steps();
                    },
                    || {
                        let _y = KeepAwake::start();
                        y_started.store(true, Ordering::Release);
                        steps();
                    },
                )
            });
        });
    }
}
