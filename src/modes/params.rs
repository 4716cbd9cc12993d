//! Drive parameters for the analysis: the FMU's start values, an SSP
//! parameter set (.ssv) and `NAME=VALUE` overrides, all applied through the
//! FMU's own setters, so every name and check is the one an importer meets.

use crate::fmi::FmuModel;
use crate::fmu::variables::{by_name, Causality, VarType};
use crate::fmu::BeltDrive;
use crate::DriveParams;
use std::path::Path;

/// (name, element, value) of every `ssv:Parameter` in an .ssv file, the
/// element being `Real`, `Integer` or `Boolean`.
pub fn read_ssv(path: &Path) -> Result<Vec<(String, String, String)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let params =
        model_description::ssv::read(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(params
        .into_iter()
        .map(|p| (p.name, p.ty, p.value))
        .collect())
}

/// Sets parameter `name` from its text `value` (the variable's own type).
pub fn set(m: &mut BeltDrive, name: &str, value: &str) -> Result<(), String> {
    let v = by_name(name).ok_or_else(|| format!("{name}: no such variable"))?;
    if !matches!(v.causality, Causality::Parameter) {
        return Err(format!("{name} is not a parameter"));
    }
    let parse_err = |e: &dyn std::fmt::Display| format!("{name} = {value}: {e}");
    match v.ty {
        VarType::Real => m.set_real(v, value.trim().parse().map_err(|e| parse_err(&e))?),
        VarType::Integer => m.set_integer(v, value.trim().parse().map_err(|e| parse_err(&e))?),
        VarType::Boolean => m.set_boolean(v, matches!(value.trim(), "true" | "1")),
        VarType::String => Err(format!("{name} is a string")),
    }
    .map_err(|e| format!("{name} = {value}: {e}"))
}

/// The FMU's start values, then the .ssv's parameters, then `sets`
/// (`NAME=VALUE`).
pub fn drive_params(ssv: Option<&Path>, sets: &[String]) -> Result<DriveParams, String> {
    let mut m = BeltDrive::new();
    if let Some(path) = ssv {
        for (name, _, value) in read_ssv(path)? {
            set(&mut m, &name, &value).map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    for s in sets {
        let (name, value) = s
            .split_once('=')
            .ok_or_else(|| format!("--set {s}: expected NAME=VALUE"))?;
        set(&mut m, name.trim(), value)?;
    }
    m.drive_params()
}

/// `p` set to run its crank (pulley 1, which must be speed-driven) at
/// `omega` [rad/s] in the set's own direction of rotation; with
/// `idle_loads`, every speed-proportional load keeps the torque it takes at
/// the set's own crank speed (its `loadDamping` scaled by that speed over
/// `omega`: the sets' loads otherwise grow with the speed squared). Returns
/// the time the analysis of steady running starts from: 0.3 s after the
/// crank's ramp.
pub fn at_crank_speed(p: &mut DriveParams, omega: f64, idle_loads: bool) -> Result<f64, String> {
    let crank = &mut p.pulleys[0];
    if !crank.speed_driven {
        return Err(
            "the analysis' speed is the crank's, pulley 1's: it must be speed-driven \
             (--set pulley[1].speedDriven=true)"
                .into(),
        );
    }
    let own = crank.omega_ramp.abs();
    crank.omega_ramp = omega.copysign(crank.omega_ramp);
    let at = crank.ramp_time + 0.3;
    if idle_loads && own > 0.0 && omega > 0.0 {
        for q in &mut p.pulleys[1..] {
            q.load_damping *= own / omega;
        }
    }
    Ok(at)
}
