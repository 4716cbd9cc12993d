//! What a communication step costs the FMU itself, through its C ABI with
//! no Python in between: the FMU's default 5PK drive, stiff method at
//! relTol 1e-4, 0.1 s settled in 1 ms steps, then 0.2 s in steps of 1 ms
//! and 0.1 ms, reading pulley speeds, angles and mean belt torques and the
//! span mean tensions after each step; prints the wall time per call.
//! Instruction counts (deterministic, unlike times) come from running it
//! under callgrind, one step size at a time:
//!
//! `cargo build --release --lib --example comm_cost_abi`, then
//! `valgrind --tool=callgrind target/release/examples/comm_cost_abi 1 1e-4`
//! (and `... 1 1e-3`): arguments REPEATS [STEP].
#[path = "../tests/abi/mod.rs"]
mod abi;
use abi::*;
use std::os::raw::c_uint;
use std::time::Instant;

fn main() {
    let fmi = Fmi::load();
    let reps: usize = std::env::args()
        .nth(1)
        .map_or(3, |s| s.parse().expect("REPEATS: a count"));
    let only: Option<f64> = std::env::args()
        .nth(2)
        .map(|s| s.parse().expect("STEP: seconds"));
    let names = [
        "pulley[1].omega",
        "pulley[1].angle",
        "pulley[1].meanBeltTorque",
        "pulley[2].omega",
        "pulley[2].angle",
        "pulley[2].meanBeltTorque",
        "span[1].meanTension",
        "span[2].meanTension",
    ];
    let vrs: Vec<c_uint> = names.iter().map(|n| vr(n)).collect();
    for _ in 0..reps {
        for h in [1e-3, 1e-4] {
            if only.is_some_and(|o| o != h) {
                continue;
            }
            let i = Instance::initialized_with(
                &fmi,
                &[("solver.method", 2)],
                &[("solver.relTol", 1e-4)],
            );
            let mut t = 0.0;
            while t < 0.1 - 1e-12 {
                assert_eq!(i.step(t, 1e-3), OK);
                t += 1e-3;
            }
            let n = (0.2 / h).round() as usize;
            let mut out = vec![0.0; vrs.len()];
            let start = Instant::now();
            for k in 0..n {
                assert_eq!(i.step(0.1 + k as f64 * h, h), OK);
                unsafe { (fmi.get_real)(i.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
            }
            let dt = start.elapsed().as_secs_f64();
            println!("h {h:e}: {dt:.4} s, {:.2} us per call", dt / n as f64 * 1e6);
        }
    }
}
