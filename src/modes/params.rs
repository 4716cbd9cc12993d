//! Drive parameters for the analysis: the FMU's start values, an SSP
//! parameter set (.ssv) and `NAME=VALUE` overrides, all applied through the
//! FMU's own setters, so every name and check is the one an importer meets.

use crate::belt::DriveParams;
use crate::fmi::FmuModel;
use crate::fmu_model::BeltDrive;
use crate::variables::{by_name, Causality, VarType};
use quick_xml::events::Event;
use quick_xml::Reader;
use std::path::Path;

/// (name, element, value) of every `ssv:Parameter` in an .ssv file, the
/// element being `Real`, `Integer` or `Boolean`.
pub fn read_ssv(path: &Path) -> Result<Vec<(String, String, String)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut reader = Reader::from_str(&text);
    let mut out = Vec::new();
    let mut name = None;
    let bad = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    loop {
        match reader.read_event().map_err(|e| bad(&e))? {
            Event::Start(e) | Event::Empty(e) => {
                let attr = |key: &str| -> Result<Option<String>, String> {
                    match e.try_get_attribute(key).map_err(|e| bad(&e))? {
                        Some(a) => Ok(Some(a.unescape_value().map_err(|e| bad(&e))?.into_owned())),
                        None => Ok(None),
                    }
                };
                match e.name().as_ref() {
                    b"ssv:Parameter" => name = attr("name")?,
                    tag @ (b"ssv:Real" | b"ssv:Integer" | b"ssv:Boolean") => {
                        let kind = String::from_utf8_lossy(&tag[4..]).into_owned();
                        let n = name
                            .take()
                            .ok_or_else(|| bad(&"a value outside ssv:Parameter"))?;
                        let v = attr("value")?.ok_or_else(|| bad(&format!("{n}: no value")))?;
                        out.push((n, kind, v));
                    }
                    _ => {}
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    Ok(out)
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
