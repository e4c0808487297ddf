//! No heap allocation in the steady time step: a counting global allocator watches 50 steps
//! of a split model (every element in a separation group, interfaces checked every step)
//! with single-surface contact against a rigid plate, after 20 steps of warm-up (the first
//! steps size the scratch buffers and the contact candidate lists) and one job on every thread
//! of the pool.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use cleave_core::contact::ContactSet;
use cleave_core::mesh::{Assembly, BoxMesh};
use cleave_core::model::{ContactDef, Material, MaterialKind, SeparationDef};
use cleave_core::separation::interfaces::Separation;
use cleave_core::separation::split::split_model;
use cleave_core::solver::Solver;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn the_steady_step_allocates_nothing() {
    let mut a = Assembly::new("allocation", 1.0);
    let steel = a.material(Material {
        id: 0,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    });
    let plate_mat = a.material(Material {
        id: 0,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Rigid {
            cmo: 1,
            con1: 7,
            con2: 7,
        },
    });
    let block = a.part("block", steel);
    let plate = a.part("plate", plate_mat);
    let (nodes, _) = a.mesh(BoxMesh::new([6, 6, 6], [0.01, 0.01, 0.01]), |_| block);
    let mut p = BoxMesh::new([4, 1, 4], [0.02, 0.002, 0.02]);
    p.translate([-0.005, -0.002, -0.005]);
    a.mesh(p, |_| plate);
    let mut m = a.finish();
    for i in nodes {
        m.v0[i as usize] = [1.0, 0.0, 0.5];
    }
    // gravity keeps the sliding block on the plate
    m.body_loads.push(cleave_core::model::BodyLoad {
        axis: 1,
        curve: None,
        sf: 1e4,
    });
    m.separations.push(SeparationDef {
        material: steel,
        model: 1,
        sigmax: 1e30,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    });
    m.contacts.push(ContactDef::single_surface_all(0.3, 0.2));
    let split = split_model(&m);
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
    s.attach_contact(ContactSet::new(&split.model, Some(&split.origin)).unwrap());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        for _ in 0..20 {
            s.advance_to_half_step().unwrap();
            s.update_positions().unwrap();
        }
        // every thread of the pool runs a job before the count: a worker's first job makes
        // rayon allocate its per-thread state, and under load a worker may first get one
        // inside the window (without this, 9 of 16 runs on a loaded machine counted 2)
        rayon::broadcast(|_| ());
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        for _ in 0..50 {
            s.advance_to_half_step().unwrap();
            s.update_positions().unwrap();
        }
        let during = ALLOCATIONS.load(Ordering::Relaxed) - before;
        let pairs: usize = s.contact().unwrap().forces().iter().map(|f| f.pairs).sum();
        println!("50 steps (in contact: {pairs} pairs at the end): {during} allocations");
        assert!(pairs > 0, "the block must be on the plate");
        assert_eq!(during, 0);
    });
}
