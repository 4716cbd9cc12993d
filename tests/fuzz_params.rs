//! Parameter fuzzing through the C ABI: random and adversarial parameter
//! sets on the fast 40-body drive (zero, negative, NaN, infinite, huge and
//! tiny values, scaled values, out-of-range integers, overlapping pulleys,
//! coarse belts, 2 and 100000 bodies, nPulleys out of range, back-side
//! flags). Each set is either simulated (a few communication steps that
//! return fmi2OK with finite outputs, or fmi2Discard with the last good time
//! kept) or refused at fmi2ExitInitializationMode with fmi2Error and a
//! message naming a parameter and what it must be. No call may take longer
//! than `CALL_LIMIT`.
//!
//! Bounded run in CI (fixed seed); long runs: `BELT_FUZZ_PARAMS=<sets>`
//! (and `BELT_FUZZ_SEED=<seed>`).
#![cfg(unix)]

mod abi;

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::ffi::c_int;
use std::time::{Duration, Instant};

use abi::*;
use belt_drive::fmu::variables::{Causality, Start, VarInfo, VARIABLES};

const CI_SETS: usize = 150;
const CI_SEED: u64 = 0x7061_7261_6d73;
/// Longest single FMI call accepted (generous: the machine may be busy).
const CALL_LIMIT: Duration = Duration::from_secs(30);
const STEP: f64 = 1e-4;
const STEPS: usize = 3;

const OUTPUTS: &[&str] = &[
    "pulley[1].omega",
    "pulley[2].omega",
    "span[1].tension",
    "span[2].tension",
    "belt.minTension",
    "belt.maxTension",
    "probe.sdeForce",
];

fn parameters() -> Vec<&'static VarInfo> {
    VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
        .collect()
}

/// One parameter assignment.
#[derive(Clone, Debug)]
enum Value {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

fn adversarial(rng: &mut Rng, v: &VarInfo) -> Value {
    match v.start {
        Start::Real(x) => Value::Real(match rng.below(14) {
            0 => 0.0,
            1 => -1.0,
            2 => -x,
            3 => f64::NAN,
            4 => f64::INFINITY,
            5 => -f64::INFINITY,
            6 => 1e300,
            7 => 1e-300,
            8 => x * 1e3,
            9 => x * 1e-3,
            10 => f64::MAX,
            11 => f64::MIN_POSITIVE / 4.0, // subnormal
            _ => x * 10f64.powf(2.0 * rng.unit() - 1.0),
        }),
        Start::Integer(x) => Value::Integer(match rng.below(10) {
            0 => 0,
            1 => -1,
            2 => i32::MIN,
            3 => i32::MAX,
            4 => 2,
            5 => 7,
            6 => 100_000,
            7 => x + 1,
            _ => 1 + rng.below(60) as i32,
        }),
        Start::Boolean(b) => Value::Boolean(!b),
        _ => unreachable!("parameters have start values"),
    }
}

/// Named adversarial scenarios (the list) on top of the fast drive.
fn scenarios() -> Vec<(&'static str, Vec<(&'static str, Value)>)> {
    use Value::*;
    vec![
        ("overlapping pulleys", vec![("pulley[2].x", Real(0.06))]),
        ("coincident pulleys", vec![("pulley[2].x", Real(0.0))]),
        ("2 bodies", vec![("belt.nBodies", Integer(2))]),
        (
            "3 bodies (belt too coarse)",
            vec![("belt.nBodies", Integer(3))],
        ),
        ("5 bodies", vec![("belt.nBodies", Integer(5))]),
        ("100000 bodies", vec![("belt.nBodies", Integer(100_000))]),
        ("nPulleys = 0", vec![("nPulleys", Integer(0))]),
        ("nPulleys = 1", vec![("nPulleys", Integer(1))]),
        ("nPulleys = 7", vec![("nPulleys", Integer(7))]),
        ("nPulleys = 3, slot 3 unset", vec![("nPulleys", Integer(3))]),
        (
            "pulley inside the other",
            vec![("pulley[2].radius", Real(0.5))],
        ),
        ("zero radius", vec![("pulley[1].radius", Real(0.0))]),
        ("negative preload", vec![("belt.preload", Real(-10.0))]),
        ("preload above EA/2", vec![("belt.preload", Real(1e6))]),
        ("NaN EA", vec![("belt.EA", Real(f64::NAN))]),
        ("zero mass", vec![("belt.massPerLength", Real(0.0))]),
        ("infinite gravity", vec![("gravity", Real(f64::INFINITY))]),
        (
            "muKinetic > muStatic",
            vec![("pulley[1].muKinetic", Real(2.0))],
        ),
        ("relTol = 0", vec![("solver.relTol", Real(0.0))]),
        ("relTol = 1e-300", vec![("solver.relTol", Real(1e-300))]),
        ("maxSteps = 1", vec![("solver.maxSteps", Integer(1))]),
        (
            "probe.body beyond the belt",
            vec![("probe.body", Integer(41))],
        ),
        ("friction.law = 3", vec![("friction.law", Integer(3))]),
        ("solver.method = 2", vec![("solver.method", Integer(2))]),
        (
            "back-side pulley 2",
            vec![("pulley[2].backSide", Boolean(true))],
        ),
        (
            "huge drive torque ramp",
            vec![("pulley[1].torqueRamp", Real(1e300))],
        ),
        (
            "huge load damping",
            vec![("pulley[2].loadDamping", Real(1e300))],
        ),
        ("huge EA", vec![("belt.EA", Real(1e300))]),
        ("huge contact stiffness", vec![("contact.c1", Real(1e300))]),
        ("tiny mass", vec![("belt.massPerLength", Real(1e-300))]),
        // Found by this fuzzer: was "belt.nBodies: no body length fits".
        ("pulley 1e300 m away", vec![("pulley[2].y", Real(1e300))]),
        ("huge pulley", vec![("pulley[2].radius", Real(1e300))]),
        // a 1 deg groove would multiply mu by 115
        (
            "groove of 1 deg",
            vec![("pulley[1].grooveAngle", Real(0.0175))],
        ),
        (
            "groove of 180 deg",
            vec![("pulley[1].grooveAngle", Real(PI))],
        ),
        (
            "40 deg grooves on both pulleys",
            vec![
                ("pulley[1].grooveAngle", Real(0.698)),
                ("pulley[2].grooveAngle", Real(0.698)),
            ],
        ),
        // tensioner arms: pulley 2 at (0.25, 0) on an arm from (0.25, 0.08)
        ("tensioner arm", tensioner(vec![])),
        (
            "tensioner pivot at the pulley centre",
            tensioner(vec![("pulley[2].arm.pivot.y", Real(0.0))]),
        ),
        (
            "tensioner with its pivot 1e300 m away",
            tensioner(vec![("pulley[2].arm.pivot.x", Real(1e300))]),
        ),
        (
            "tensioner pivot at the default (0, 0): a 0.25 m arm",
            vec![("pulley[2].tensioner", Boolean(true))],
        ),
        (
            "tensioner on pulley 1 at its default pivot (its centre)",
            vec![("pulley[1].tensioner", Boolean(true))],
        ),
        (
            "tensioner without inertia",
            tensioner(vec![("pulley[2].arm.inertia", Real(0.0))]),
        ),
        (
            "tensioner of tiny inertia",
            tensioner(vec![("pulley[2].arm.inertia", Real(1e-300))]),
        ),
        (
            "tensioner with a NaN spring",
            tensioner(vec![("pulley[2].arm.stiffness", Real(f64::NAN))]),
        ),
        (
            "tensioner with a huge spring",
            tensioner(vec![("pulley[2].arm.stiffness", Real(1e300))]),
        ),
        (
            "tensioner with huge pivot friction",
            tensioner(vec![("pulley[2].arm.friction", Real(1e300))]),
        ),
        (
            "tensioner with negative damping",
            tensioner(vec![("pulley[2].arm.damping", Real(-1.0))]),
        ),
        (
            "tensioners on both pulleys and the stiff method",
            tensioner(vec![
                ("pulley[1].tensioner", Boolean(true)),
                ("pulley[1].arm.pivot.y", Real(-0.08)),
                ("solver.method", Integer(2)),
            ]),
        ),
    ]
}

/// Pulley 2 of the fast drive on a tensioner arm (pivot 80 mm above its
/// centre, pivot friction 0.5 N m), then `more`.
fn tensioner(more: Vec<(&'static str, Value)>) -> Vec<(&'static str, Value)> {
    use Value::*;
    let mut v = vec![
        ("pulley[2].tensioner", Boolean(true)),
        ("pulley[2].arm.pivot.x", Real(0.25)),
        ("pulley[2].arm.pivot.y", Real(0.08)),
        ("pulley[2].arm.friction", Real(0.5)),
    ];
    v.extend(more);
    v
}

struct Outcome {
    /// "simulated", "discarded", or "refused".
    kind: &'static str,
    /// The refusal or discard message.
    message: String,
    slowest: Duration,
    slowest_call: &'static str,
}

/// Set `assignments` on the fast drive, initialize, take `STEPS` steps.
fn try_set(fmi: &Fmi, assignments: &[(&str, Value)]) -> Outcome {
    let i = Instance::new(fmi);
    i.log_categories(&["logStatusDiscard"]);
    let set_all = |list: &[(&str, Value)]| {
        for (name, value) in list {
            let s = match value {
                Value::Real(x) => i.set_real(name, *x),
                Value::Integer(x) => i.set_integer(name, *x),
                Value::Boolean(x) => i.set_boolean(name, *x),
            };
            assert_eq!(
                s, OK,
                "parameters are checked at initialization: {name} = {value:?}"
            );
        }
    };
    let ints: Vec<(&str, Value)> = FAST_INTS
        .iter()
        .map(|(n, x)| (*n, Value::Integer(*x)))
        .collect();
    let reals: Vec<(&str, Value)> = FAST_REALS
        .iter()
        .map(|(n, x)| (*n, Value::Real(*x)))
        .collect();
    set_all(&ints);
    set_all(&reals);
    set_all(assignments);
    let mut slowest = (Duration::ZERO, "");
    let mut timed = |what: &'static str, f: &mut dyn FnMut() -> c_int| {
        let t = Instant::now();
        let s = f();
        let dt = t.elapsed();
        assert!(dt < CALL_LIMIT, "{what} took {dt:?} for {assignments:?}");
        if dt > slowest.0 {
            slowest = (dt, what);
        }
        s
    };
    unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
    }
    let s = timed("fmi2ExitInitializationMode", &mut || unsafe {
        (fmi.exit_init)(i.c)
    });
    let log = |i: &Instance| format!("{:?}", i.log.borrow());
    if s == ERROR {
        let (_, _, m) = i.log.borrow().last().cloned().expect("a log line");
        assert!(m.starts_with("fmi2ExitInitializationMode: "), "{m}");
        // The message names a parameter of the model description and says
        // what it must be ("<name> must be ...", "<name>: ... must ..." or
        // "<name>: ... are needed: use <name> >= n", or a geometric rule
        // with what to check).
        let body = m.trim_start_matches("fmi2ExitInitializationMode: ");
        let names_parameter = parameters().iter().any(|v| {
            body.starts_with(&format!("{} must", v.name))
                || body.starts_with(&format!("{}: ", v.name))
        });
        assert!(
            names_parameter && ["must", "needed", "check"].iter().any(|w| body.contains(w)),
            "refusal does not name a parameter and its range: {m} ({assignments:?})"
        );
        return Outcome {
            kind: "refused",
            message: m,
            slowest: slowest.0,
            slowest_call: slowest.1,
        };
    }
    assert_eq!(s, OK, "{}", log(&i));
    let mut t = 0.0;
    for _ in 0..STEPS {
        let s = timed("fmi2DoStep", &mut || i.step(t, STEP));
        match s {
            OK => {
                t += STEP;
                let y = i.get(OUTPUTS);
                assert!(
                    y.iter().all(|x| x.is_finite()),
                    "fmi2OK with non-finite outputs {y:?} for {assignments:?}"
                );
            }
            DISCARD => {
                assert_eq!(i.last_successful_time(), (OK, t), "{}", log(&i));
                let m = i
                    .log
                    .borrow()
                    .iter()
                    .rev()
                    .find(|(s, _, _)| *s == DISCARD)
                    .map(|(_, _, m)| m.clone())
                    .expect("a discard log line");
                return Outcome {
                    kind: "discarded",
                    message: m,
                    slowest: slowest.0,
                    slowest_call: slowest.1,
                };
            }
            other => panic!("fmi2DoStep returned {other}: {}", log(&i)),
        }
    }
    Outcome {
        kind: "simulated",
        message: String::new(),
        slowest: slowest.0,
        slowest_call: slowest.1,
    }
}

/// The message without numbers, to group refusals by rule.
fn rule(message: &str) -> String {
    let m = message.trim_start_matches("fmi2ExitInitializationMode: ");
    let m = m.split(" (got").next().unwrap_or(m);
    let m: String = m.chars().take(90).collect();
    m.chars()
        .map(|c| if c.is_ascii_digit() { '#' } else { c })
        .collect()
}

#[test]
fn adversarial_parameter_sets() {
    let fmi = Fmi::load();
    let started = Instant::now();
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    let mut rules: BTreeMap<String, usize> = BTreeMap::new();
    let mut slowest = (Duration::ZERO, "", String::new());
    let mut record = |what: String, o: Outcome| {
        *counts.entry(o.kind).or_default() += 1;
        if o.kind != "simulated" {
            *rules
                .entry(format!("{}: {}", o.kind, rule(&o.message)))
                .or_default() += 1;
        }
        if o.slowest > slowest.0 {
            slowest = (o.slowest, o.slowest_call, what);
        }
    };
    for (name, assignments) in scenarios() {
        eprintln!("scenario {name} ...");
        let o = try_set(&fmi, &assignments);
        eprintln!("scenario {name:32} {:9} {}", o.kind, o.message);
        record(name.to_string(), o);
    }
    let params = parameters();
    let sets = iterations("BELT_FUZZ_PARAMS", CI_SETS);
    let seed = seed(CI_SEED);
    let mut rng = Rng::new(seed);
    for _ in 0..sets {
        let n = 1 + rng.below(3);
        let mut assignments: Vec<(&str, Value)> = (0..n)
            .map(|_| {
                let v = *rng.pick(&params);
                (v.name, adversarial(&mut rng, v))
            })
            .collect();
        // a tensioner arm's parameters act only with the arm on: switch it
        // on (pulley 2, pivot 80 mm above its centre, before them)
        if assignments.iter().any(|(name, _)| name.contains(".arm.")) {
            let mut arm = tensioner(vec![]);
            arm.truncate(3);
            assignments.splice(0..0, arm);
        }
        let o = try_set(&fmi, &assignments);
        record(format!("{assignments:?}"), o);
    }
    println!(
        "fuzz_params: seed {seed}, {} scenarios + {sets} random sets in {:.1} s: {counts:?}",
        scenarios().len(),
        started.elapsed().as_secs_f64()
    );
    println!(
        "slowest call: {} {:?} for {}",
        slowest.1, slowest.0, slowest.2
    );
    for (r, n) in &rules {
        println!("{n:6}  {r}");
    }
}
