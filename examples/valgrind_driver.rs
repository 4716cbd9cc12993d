//! Memory check driver: `cargo xtask valgrind` runs it under valgrind
//! memcheck. It loads the built FMU library with dlopen (the loader of the
//! ABI tests, `tests/abi/mod.rs`) and runs instantiate / set-up / step /
//! get-set-serialize-deserialize FMU state / free cycles, including the
//! refusal paths (unknown value references, illegal calls, damaged states)
//! and an FMU state left for fmi2FreeInstance to free.
//!
//! `cargo run --release --example valgrind_driver [cycles]` runs it without
//! valgrind.

#[path = "../tests/abi/mod.rs"]
mod abi;

use std::ptr;

use abi::*;

fn cycle(fmi: &Fmi, k: usize) {
    let i = Instance::initialized_with(
        fmi,
        &[("belt.nBodies", 40), ("probe.body", 1)],
        &[FAST_REALS, &[("belt.preload", 250.0 + k as f64)]].concat(),
    );
    i.log_categories(&["logEvents", "logStatusDiscard", "logAll"]);
    let mut t = 0.0;
    for _ in 0..3 {
        assert_eq!(i.step(t, 2e-4), OK);
        t += 2e-4;
    }
    let y = i.get(&["pulley[1].omega", "span[1].tension", "probe.sdeForce"]);
    assert!(y.iter().all(|x| x.is_finite()));
    // FMU state: get, reuse, serialize, deserialize, set, free.
    let s = i.get_state();
    let mut again = s;
    assert_eq!(unsafe { (fmi.get_state)(i.c, &mut again) }, OK);
    let bytes = i.serialize(s);
    let (status, s2) = i.deserialize(&bytes);
    assert_eq!(status, OK);
    assert_eq!(i.step(t, 2e-4), OK);
    assert_eq!(unsafe { (fmi.set_state)(i.c, s2) }, OK);
    assert_eq!(i.step(t, 2e-4), OK);
    i.free_state(s2);
    // Refusals (each puts the instance into Error; fmi2SetFMUstate recovers).
    let (status, bad) = i.deserialize(&bytes[..bytes.len() / 2]);
    assert_eq!((status, bad), (ERROR, ptr::null_mut()));
    let x = 1.0;
    assert_eq!(unsafe { (fmi.set_real)(i.c, &999_999, 1, &x) }, ERROR);
    assert_eq!(unsafe { (fmi.enter_init)(i.c) }, ERROR);
    assert_eq!(unsafe { (fmi.set_state)(i.c, s) }, OK);
    assert_eq!(i.set_real("pulley[1].torque", f64::NAN), ERROR);
    // Discarded step (step-count guard), reset, a second life.
    assert_eq!(unsafe { (fmi.reset)(i.c) }, OK);
    assert_eq!(i.set_integer("belt.nBodies", 40), OK);
    assert_eq!(i.set_integer("probe.body", 1), OK);
    for (n, x) in FAST_REALS {
        assert_eq!(i.set_real(n, *x), OK);
    }
    assert_eq!(i.set_integer("solver.maxSteps", 2), OK);
    unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 1, 1e-4, 0.0, 1, 1.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        assert_eq!((fmi.exit_init)(i.c), OK);
    }
    assert_eq!(i.step(0.0, 1e-3), DISCARD);
    assert_eq!(i.last_successful_time(), (OK, 0.0));
    assert_eq!(unsafe { (fmi.terminate)(i.c) }, OK);
    // `s` is left to fmi2FreeInstance (when `i` is dropped).
    if k.is_multiple_of(2) {
        i.free_state(s);
    }
    assert!(!i.log.borrow().is_empty());
}

fn main() {
    let cycles: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    let fmi = Fmi::load();
    for k in 0..cycles {
        cycle(&fmi, k);
    }
    // Two instances on two threads.
    std::thread::scope(|s| {
        for k in 0..2 {
            let fmi = &fmi;
            s.spawn(move || cycle(fmi, k));
        }
    });
    println!("valgrind_driver: {} cycles done", cycles + 2);
}
