//! Fingerprints of the model's behaviour, for refactorings that must not
//! change it by a bit: ten drives (the parameter files of parameters/ and
//! drives built from the FMU's own variables: the default, the paper's two,
//! the accessory drive with and without tensioner or decoupler, a heavy belt,
//! unequal pulleys, many bodies, the other friction law), each under both
//! methods, advanced in 1 ms steps over H s (default 0.2 s). After every step
//! the full state vector (its IEEE bit patterns) and every output (`Debug`,
//! the shortest text that reads back to the same bits) go into a 64-bit
//! FNV-1a hash; one line per run gives the hash, the steps and the rejected
//! steps. Two builds behave bit-identically on these drives when their lines
//! match.
//!
//! `cargo run --profile ci --example state_hash -- [H [DRIVE]]`

use belt_drive::fmi::FmuModel;
use belt_drive::fmu::variables::{by_name, VarType};
use belt_drive::fmu::BeltDrive;
use belt_drive::Drive;

/// A drive: a parameter file (or none: the FMU's start values) and
/// variables set on top, by the names of the model description.
struct Case {
    name: &'static str,
    file: Option<&'static str>,
    set: &'static [(&'static str, &'static str)],
}

const CASES: &[Case] = &[
    Case {
        name: "default",
        file: None,
        set: &[],
    },
    Case {
        name: "kubas2014-section3",
        file: Some("kubas2014-section3.ssv"),
        set: &[],
    },
    Case {
        name: "kubas2014-section4",
        file: Some("kubas2014-section4.ssv"),
        set: &[],
    },
    Case {
        name: "accessory-drive-4",
        file: Some("accessory-drive-4.ssv"),
        set: &[],
    },
    Case {
        name: "accessory-tensioner",
        file: Some("accessory-drive-tensioner.ssv"),
        set: &[],
    },
    Case {
        name: "accessory-decoupler",
        file: Some("accessory-drive-decoupler.ssv"),
        set: &[],
    },
    // examples/common/heavy_belt.rs in the FMU's variables
    Case {
        name: "heavy-belt",
        file: None,
        set: &[
            ("belt.nBodies", "120"),
            ("belt.massPerLength", "0.3"),
            ("pulley[1].radius", "0.06"),
            ("pulley[1].speedDriven", "true"),
            ("pulley[1].omegaRamp", "-150"),
            ("pulley[1].torqueRamp", "0"),
            ("pulley[1].rampTime", "0.1"),
            ("pulley[2].x", "0.35"),
            ("pulley[2].loadDamping", "0.01"),
            ("pulley[2].rampTime", "0.1"),
        ],
    },
    Case {
        name: "unequal-pulleys",
        file: None,
        set: &[
            ("pulley[1].radius", "0.1"),
            ("pulley[2].radius", "0.03"),
            ("pulley[2].x", "0.4"),
            ("pulley[2].y", "0.05"),
        ],
    },
    Case {
        name: "many-bodies",
        file: None,
        set: &[("belt.nBodies", "400")],
    },
    Case {
        name: "section3-kubas2014-law",
        file: Some("kubas2014-section3.ssv"),
        set: &[("friction.law", "1")],
    },
];

fn set(m: &mut BeltDrive, name: &str, value: &str) {
    let v = by_name(name).unwrap_or_else(|| panic!("no variable {name}"));
    match v.ty {
        VarType::Real => m.set_real(v, value.parse().unwrap()),
        VarType::Integer => m.set_integer(v, value.parse().unwrap()),
        VarType::Boolean => m.set_boolean(v, value == "true" || value == "1"),
        _ => panic!("{name}: not a parameter type"),
    }
    .unwrap_or_else(|e| panic!("{name} = {value}: {e}"));
}

/// 64-bit FNV-1a.
struct Fnv(u64);

impl Fnv {
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x100_0000_01b3);
        }
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let horizon: f64 = a.first().map_or(0.2, |s| s.parse().expect("horizon [s]"));
    let only = a.get(1).cloned();
    for case in CASES {
        if only.as_deref().is_some_and(|o| o != case.name) {
            continue;
        }
        for method in ["1", "2"] {
            let mut m = BeltDrive::new();
            if let Some(file) = case.file {
                let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("parameters")
                    .join(file);
                let text = std::fs::read_to_string(&path).expect("parameter file");
                for p in model_description::ssv::read(&text).expect("ssv") {
                    set(&mut m, &p.name, &p.value);
                }
            }
            for (name, value) in case.set {
                set(&mut m, name, value);
            }
            set(&mut m, "solver.method", method);
            let params = m.drive_params().expect("parameters");
            let mut d = Drive::new(&params, 0.0).expect("a valid drive");
            let mut h = Fnv(0xcbf2_9ce4_8422_2325);
            let n = (horizon / 1e-3).round() as usize;
            let mut failed = None;
            for k in 1..=n {
                if let Err(e) = d.advance(k as f64 * 1e-3) {
                    failed = Some(format!("step failure at {} ms: {e:?}", k));
                    break;
                }
                for v in d.state() {
                    h.bytes(&v.to_bits().to_le_bytes());
                }
                h.bytes(format!("{:?}", d.outputs()).as_bytes());
            }
            let s = d.stats();
            println!(
                "{:<22} method {method} n {:>4}: hash {:016x} steps {} rejected {}{}",
                case.name,
                d.state().len(),
                h.0,
                s.steps,
                s.rejected,
                failed.map(|f| format!(" ({f})")).unwrap_or_default()
            );
        }
    }
}
