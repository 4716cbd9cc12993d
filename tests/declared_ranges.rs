//! Every declared range of a Real parameter is enforced through the C ABI,
//! exactly at the bound the model description states: on the fast 40-body
//! drive, each bounded parameter (every pulley slot, used or not) is set
//!
//! * to the next floating-point number outside a bound: fmi2ExitInitializationMode
//!   returns fmi2Error and logs `<name> must be finite and ... (got ...)`;
//! * to the bound itself: refused the same way if the model description's
//!   range annotation marks that end exclusive (`min="exclusive"`, e.g. a
//!   radius > 0), else not refused by its range (the drive may still be
//!   refused by a rule that involves other parameters, e.g. a pulley at
//!   x = 1000 m for the belt's body count; such a message does not state
//!   this parameter's range).
//!
//! The ranges are read from `modelDescription/modelDescription.xml` with the
//! project's reader, not from the generated table the model uses.
#![cfg(unix)]

mod abi;

use abi::*;
use model_description::Variable;

/// The model description's Real parameters that declare a bound.
fn bounded_reals() -> Vec<Variable> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/modelDescription/modelDescription.xml"
    );
    let text = std::fs::read_to_string(path).expect("model description");
    let md = model_description::parse(&text).expect("valid model description");
    md.variables
        .into_iter()
        .filter(|v| v.causality == "parameter" && v.ty == "Real")
        .filter(|v| v.min.is_some() || v.max.is_some())
        .collect()
}

/// fmi2ExitInitializationMode's status and its error messages, for the fast
/// drive with `name` = `x`.
fn initialize_with(fmi: &Fmi, name: &str, x: f64) -> (i32, Vec<String>) {
    let i = Instance::new(fmi);
    for (n, v) in FAST_INTS {
        assert_eq!(i.set_integer(n, *v), OK);
    }
    for (n, v) in FAST_REALS {
        assert_eq!(i.set_real(n, *v), OK);
    }
    assert_eq!(
        i.set_real(name, x),
        OK,
        "parameters are checked at initialization"
    );
    let s = unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        (fmi.exit_init)(i.c)
    };
    let errors = i
        .log
        .borrow()
        .iter()
        .filter(|(s, _, _)| *s == ERROR)
        .map(|(_, _, m)| m.clone())
        .collect();
    (s, errors)
}

#[test]
fn every_real_bound_is_enforced_where_declared() {
    let fmi = Fmi::load();
    let vars = bounded_reals();
    // 18 drive parameters and 22 per pulley slot declare ranges
    assert!(vars.len() >= 100, "{} bounded Real parameters", vars.len());
    let mut checked = 0;
    for v in &vars {
        let range_refusal = format!("fmi2ExitInitializationMode: {} must be finite and ", v.name);
        let ends = [
            (&v.min, v.min_exclusive, f64::next_down as fn(f64) -> f64),
            (&v.max, v.max_exclusive, f64::next_up),
        ];
        for (bound, exclusive, outward) in ends {
            let Some(text) = bound else { continue };
            let b: f64 = text.parse().expect("a number");
            // just outside: refused, naming the parameter and its range
            let (s, errors) = initialize_with(&fmi, &v.name, outward(b));
            assert_eq!(s, ERROR, "{} = {:e} accepted", v.name, outward(b));
            assert!(
                errors.iter().any(|m| m.starts_with(&range_refusal)),
                "{} = {:e}: {errors:?}",
                v.name,
                outward(b)
            );
            // at the bound: refused by its range only if that end is exclusive
            let (s, errors) = initialize_with(&fmi, &v.name, b);
            let refused_by_range = errors.iter().any(|m| m.starts_with(&range_refusal));
            assert_eq!(
                refused_by_range,
                exclusive,
                "{} = {b} ({} end): status {s}, {errors:?}",
                v.name,
                if exclusive { "exclusive" } else { "inclusive" }
            );
            assert_eq!(s == ERROR, exclusive || !errors.is_empty());
            checked += 1;
        }
    }
    println!(
        "{checked} declared bounds of {} Real parameters enforced",
        vars.len()
    );
}

/// The refusal states the value, the range in the variable's unit and,
/// for an exclusive end, the strict comparison.
#[test]
fn refusals_state_value_range_and_unit() {
    let fmi = Fmi::load();
    let cases = [
        (
            "pulley[1].radius",
            0.0,
            "pulley[1].radius must be finite and > 0 m (got 0)",
        ),
        (
            "pulley[4].rampTime",
            -1.0,
            "pulley[4].rampTime must be finite and > 0 s (got -1)",
        ),
        (
            "solver.relTol",
            1.0,
            "solver.relTol must be finite and in (0, 1) (got 1)",
        ),
        (
            "friction.creepDampingTime",
            2.0,
            "friction.creepDampingTime must be finite and in [0, 1] s (got 2)",
        ),
        (
            "pulley[2].grooveAngle",
            std::f64::consts::PI,
            "pulley[2].grooveAngle must be finite and in [0, 3.141592653589793) rad",
        ),
        (
            "belt.EA",
            f64::NAN,
            "belt.EA must be finite and > 0 N (got NaN)",
        ),
        (
            "pulley[6].arm.pivot.y",
            -1e300,
            "pulley[6].arm.pivot.y must be finite and in [-1000, 1000] m (got -1e300)",
        ),
        (
            "pulley[1].torqueRamp",
            f64::INFINITY,
            "pulley[1].torqueRamp must be finite (got inf)",
        ),
    ];
    for (name, x, expected) in cases {
        let (s, errors) = initialize_with(&fmi, name, x);
        assert_eq!(s, ERROR);
        assert!(
            errors
                .iter()
                .any(|m| m.starts_with(&format!("fmi2ExitInitializationMode: {expected}"))),
            "{name} = {x}: {errors:?}"
        );
    }
}
