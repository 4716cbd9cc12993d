//! Instances share nothing: 8 instances of the fast drive stepped
//! concurrently on 8 threads (each with its own inputs) give outputs
//! bit-identical to the same instances run one after the other.
#![cfg(unix)]

mod abi;

use abi::*;

const THREADS: usize = 8;
const STEPS: usize = 20;
const H: f64 = 5e-4;
const OUTPUTS: &[&str] = &[
    "pulley[1].omega",
    "pulley[2].omega",
    "pulley[1].angle",
    "span[1].tension",
    "span[2].tension",
    "probe.sdeForce",
    "solver.steps",
];

/// Instance `k` with its own preload and load torque; every output after
/// every step.
fn run(fmi: &Fmi, k: usize) -> Vec<Vec<f64>> {
    let i = Instance::fast(fmi, &[("belt.preload", 250.0 + 10.0 * k as f64)]);
    assert_eq!(i.set_real("pulley[2].torque", 0.1 * k as f64), OK);
    (0..STEPS)
        .map(|n| {
            assert_eq!(i.step(n as f64 * H, H), OK);
            i.get(OUTPUTS)
        })
        .collect()
}

#[test]
fn concurrent_instances_match_serial_runs() {
    let fmi = Fmi::load();
    let serial: Vec<_> = (0..THREADS).map(|k| run(&fmi, k)).collect();
    let concurrent: Vec<_> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..THREADS)
            .map(|k| {
                let fmi = &fmi;
                scope.spawn(move || run(fmi, k))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for k in 0..THREADS {
        // Bit-identical, NaN-safe comparison.
        let bits =
            |r: &Vec<Vec<f64>>| -> Vec<u64> { r.iter().flatten().map(|x| x.to_bits()).collect() };
        assert_eq!(bits(&serial[k]), bits(&concurrent[k]), "instance {k}");
    }
    assert_ne!(serial[0], serial[1], "the instances differ from each other");
    println!("threads: {THREADS} instances x {STEPS} steps, concurrent == serial bit for bit");
}
