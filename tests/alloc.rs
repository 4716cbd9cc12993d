//! The hot path (right-hand side and integrator steps) allocates nothing.

use belt_drive::model::params::{ArmStops, DecouplerParams, Method, TensionerArm};
use belt_drive::model::system::{NoRecord, Workspace};
use belt_drive::{Drive, DriveParams};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn rhs_and_steps_do_not_allocate() {
    // both integrators: RKF45, and the stiff method with its Jacobian,
    // factorizations and stage solves
    // (and with a grooved pulley and a decoupler on the driven one, which
    // also sits on a tensioner arm)
    // (and with the contact along the body, 1 and 3 contact points)
    for (method, fead, points) in [
        (Method::Rkf45, false, 1),
        (Method::Rosenbrock, false, 1),
        (Method::Rkf45, true, 1),
        (Method::Rosenbrock, true, 1),
        (Method::Rkf45, false, 3),
        (Method::Rosenbrock, true, 3),
    ] {
        let mut p = DriveParams::kubas_section4();
        p.solver.method = method;
        p.contact.points = points;
        if fead {
            p.pulleys[0].groove_angle = 0.7;
            p.pulleys[1].decoupler = Some(DecouplerParams {
                clockwise: true,
                ..Default::default()
            });
            p.pulleys[1].arm = Some(TensionerArm {
                pivot: [0.515, 0.08],
                friction: 0.5,
                // on its upper stop from the start: the stop's law runs too
                stops: Some(ArmStops {
                    min_angle: -0.1,
                    max_angle: 0.0,
                    ..Default::default()
                }),
                ..Default::default()
            });
        }
        let mut d = Drive::new(&p, 0.0).unwrap();
        let y = d.state().to_vec();
        let mut dy = vec![0.0; y.len()];
        let mut ws = Workspace::new();
        d.advance(1e-4).unwrap(); // warm-up
        let before = ALLOCS.load(Ordering::Relaxed);
        let steps = d.stats().steps;
        for _ in 0..100 {
            d.system().rhs(&mut ws, 0.0, &y, &mut dy, &mut NoRecord);
        }
        d.advance(2e-2).unwrap();
        let after = ALLOCS.load(Ordering::Relaxed);
        assert!(
            d.stats().steps > steps + 20,
            "{method:?} {fead} {points}: {:?}",
            d.stats()
        );
        assert_eq!(
            after - before,
            0,
            "{method:?} {fead} {points}: allocations on the hot path"
        );
    }
}
