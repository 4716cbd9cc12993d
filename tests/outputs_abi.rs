//! Outputs evaluated when read, through the C ABI of the built library: a
//! master that reads only speeds, angles and means pays for no force
//! evaluation (the benchmark measures what that saves), and whichever
//! output it reads first after a step, it gets the value a read of every
//! output gives, to the bit.

mod abi;

use abi::*;
use belt_drive::fmi::description::{Causality, VarType};
use belt_drive::fmu::variables::VARIABLES;

/// Every Real output of the model description.
fn real_outputs() -> Vec<&'static str> {
    VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|v| v.name)
        .collect()
}

/// The tensioner set (arm, decoupler, four pulleys) at 0.1 ms steps:
/// instance `a` reads one output first after each step (every output in
/// turn, the means also at the start, where the window is empty), then
/// every output; instance `b` reads every output at once. Both see the same
/// values, to the bit, so no output is left out of the evaluation on
/// demand or computed differently there.
#[test]
fn the_first_output_read_is_the_one_of_a_full_read() {
    let fmi = Fmi::load();
    let names = real_outputs();
    assert!(names.len() > 100, "{} outputs", names.len());
    let make = || {
        let i = Instance::new(&fmi);
        i.set_ssv("accessory-drive-tensioner.ssv");
        i.set_integer("solver.method", 2);
        i.initialize();
        i
    };
    let (a, b) = (make(), make());
    let h = 1e-4;
    for k in 0..=names.len() {
        let first = names[k % names.len()];
        let one = a.get(&[first])[0];
        let all_a = a.get(&names);
        let all_b = b.get(&names);
        let at = names.iter().position(|n| *n == first).unwrap();
        assert_eq!(one.to_bits(), all_b[at].to_bits(), "{first} after step {k}");
        for (n, (x, y)) in names.iter().zip(all_a.iter().zip(&all_b)) {
            assert_eq!(
                x.to_bits(),
                y.to_bits(),
                "{n} after step {k}, {first} read first"
            );
        }
        let t = k as f64 * h;
        assert_eq!(a.step(t, h), OK);
        assert_eq!(b.step(t, h), OK);
    }
}
