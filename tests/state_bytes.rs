//! Serialized FMU states through the C ABI: a real serialized state of the
//! fast drive is refused with fmi2Error (and `*FMUstate` left alone) when
//! truncated to every shorter length, extended, bit-flipped at random
//! (seeded), or replaced by random bytes; a state of another parameter set
//! (60 bodies) restores that parameter set, its mean outputs over the last
//! communication step, and continues bit-identically.
#![cfg(unix)]

mod abi;

use std::ptr;

use abi::*;

const OUTPUTS: &[&str] = &[
    "pulley[1].omega",
    "pulley[2].omega",
    "span[1].tension",
    "probe.sdeForce",
    "pulley[1].meanBeltTorque",
    "pulley[2].meanHubForce.x",
    "pulley[2].meanAlpha",
];

fn refused(i: &Instance, bytes: &[u8], what: &str) {
    let mut s: State = ptr::null_mut();
    let n0 = i.log.borrow().len();
    let status = unsafe { (i.fmi.deserialize)(i.c, bytes.as_ptr().cast(), bytes.len(), &mut s) };
    assert_eq!(status, ERROR, "{what} accepted");
    assert!(s.is_null(), "{what}: *FMUstate changed");
    let log = i.log.borrow();
    assert!(
        log[n0..]
            .iter()
            .any(|(s, _, m)| *s == ERROR && m.starts_with("fmi2DeSerializeFMUstate: ")),
        "{what}: no error log line"
    );
}

#[test]
fn damaged_serialized_states_are_refused() {
    let fmi = Fmi::load();
    let a = Instance::fast(&fmi, &[]);
    for k in 0..3 {
        assert_eq!(a.step(f64::from(k) * 1e-3, 1e-3), OK);
    }
    let s = a.get_state();
    let bytes = a.serialize(s);
    a.free_state(s);
    // fmi2DeSerializeFMUstate is allowed in every state, also Error: one
    // instance takes all the refusals.
    let i = Instance::new(&fmi);
    for n in 0..bytes.len() {
        refused(&i, &bytes[..n], &format!("truncation to {n} bytes"));
    }
    let mut longer = bytes.clone();
    longer.extend_from_slice(&[0; 8]);
    refused(&i, &longer, "8 extra bytes");
    let mut rng = Rng::new(seed(0x5eed));
    let flips = iterations("BELT_FUZZ_FLIPS", 2000);
    for _ in 0..flips {
        let mut bad = bytes.clone();
        for _ in 0..1 + rng.below(3) {
            let k = rng.below(bad.len());
            bad[k] ^= 1 << rng.below(8);
        }
        if bad != bytes {
            refused(&i, &bad, "bit flip");
        }
    }
    for n in [0, 1, 8, 64, bytes.len()] {
        let random: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
        refused(&i, &random, "random bytes");
    }
    println!(
        "state_bytes: {} byte state; {} truncations, {flips} random 1-3 bit flips, 5 random strings refused",
        bytes.len(),
        bytes.len()
    );
    // Damage inside the model data behind a valid frame (checksum and
    // length recomputed), so the model's own reader sees it: every 23rd byte
    // flipped, and the model data cut at every 23rd length. Each is either
    // refused with fmi2Error or accepted (a changed parameter value); none
    // crashes or reads past the end.
    let (model_at, model_len) = model_section(&bytes);
    let (mut accepted, mut refusals) = (0, 0);
    let mut try_model = |model: &[u8]| {
        let framed = reframe(&bytes[..model_at - 8], model);
        let (status, mut s) = i.deserialize(&framed);
        match status {
            OK => {
                accepted += 1;
                assert_eq!(unsafe { (fmi.free_state)(i.c, &mut s) }, OK);
            }
            ERROR => refusals += 1,
            other => panic!("status {other}"),
        }
    };
    let model = &bytes[model_at..model_at + model_len];
    for k in (0..model_len).step_by(23) {
        let mut m = model.to_vec();
        m[k] ^= 0x81;
        try_model(&m);
    }
    for n in (0..model_len).step_by(23) {
        try_model(&model[..n]);
    }
    println!("state_bytes: model data damaged behind a valid frame: {refusals} refused, {accepted} accepted (changed values)");
    assert!(refusals > 0);

    // The intact bytes still work.
    let (status, mut s2) = i.deserialize(&bytes);
    assert_eq!(status, OK);
    assert_eq!(unsafe { (fmi.free_state)(i.c, &mut s2) }, OK);
}

#[test]
fn a_state_of_another_parameter_set_restores_that_set() {
    let fmi = Fmi::load();
    // 60 bodies and another preload, stepped to 3 ms.
    let a = Instance::initialized_with(
        &fmi,
        &[("belt.nBodies", 60), ("probe.body", 1)],
        &[FAST_REALS, &[("belt.preload", 250.0)]].concat(),
    );
    for k in 0..3 {
        assert_eq!(a.step(f64::from(k) * 1e-3, 1e-3), OK);
    }
    let s = a.get_state();
    let bytes = a.serialize(s);
    a.free_state(s);
    let saved = a.get(OUTPUTS);
    assert_eq!(a.step(3e-3, 1e-3), OK);
    let expected = a.get(OUTPUTS);
    // Into an initialized 40-body instance.
    let b = Instance::fast(&fmi, &[]);
    assert_eq!(b.step(0.0, 1e-3), OK);
    let (status, s2) = b.deserialize(&bytes);
    assert_eq!(status, OK, "{:?}", b.log.borrow());
    assert_eq!(unsafe { (fmi.set_state)(b.c, s2) }, OK);
    assert_eq!(b.get(&["belt.preload"]), [250.0]);
    assert_eq!(b.last_successful_time(), (OK, 3e-3));
    // the means over the step before the save, not an empty window
    assert_eq!(b.get(OUTPUTS), saved, "outputs at the restored time");
    assert_eq!(b.step(3e-3, 1e-3), OK);
    assert_eq!(b.get(OUTPUTS), expected, "continues bit-identically");
    b.free_state(s2);
}

/// Offset and length of the model data in a serialized state (layout in
/// src/fmi/state.rs: magic, version, GUID, mode, time, stop time, model
/// length, model data, checksum).
fn model_section(bytes: &[u8]) -> (usize, usize) {
    let guid_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let len_at = 16 + guid_len + 1 + 8 + 1 + 8;
    let len = u64::from_le_bytes(bytes[len_at..len_at + 8].try_into().unwrap()) as usize;
    (len_at + 8, len)
}

/// `head` (everything before the model length) + model + FNV-1a checksum.
fn reframe(head: &[u8], model: &[u8]) -> Vec<u8> {
    let mut out = head.to_vec();
    out.extend_from_slice(&(model.len() as u64).to_le_bytes());
    out.extend_from_slice(model);
    let sum = out.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    out.extend_from_slice(&sum.to_le_bytes());
    out
}
