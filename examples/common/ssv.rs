//! A drive from a parameter file of parameters/ (.ssv), set through the FMU's
//! own variables: shared by examples/mesh_study.rs, examples/stiff_energy.rs and
//! examples/wrap_profile.rs (included with `#[path]`, one definition).

use std::path::Path;

use belt_drive::fmi::FmuModel;
use belt_drive::fmu::variables::{by_name, VarType};
use belt_drive::fmu::BeltDrive;
use belt_drive::DriveParams;

/// The parameters of `parameters/<file>` set through the FMU's own variables.
#[allow(dead_code)] // not every including crate reads a plain file
pub fn from_ssv(file: &str) -> DriveParams {
    from_ssv_with(file, &[])
}

/// The same, then each `(name, value)` of `overrides` set by its variable
/// name (e.g. `("belt.nBodies", "320")`).
#[allow(dead_code)] // not every including crate overrides
pub fn from_ssv_with(file: &str, overrides: &[(String, String)]) -> DriveParams {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("parameters")
        .join(file);
    let text = std::fs::read_to_string(&path).expect("parameter file");
    let mut m = BeltDrive::new();
    let file_values = model_description::ssv::read(&text)
        .expect("ssv")
        .into_iter()
        .map(|p| (p.name, p.value));
    for (name, value) in file_values.chain(overrides.iter().cloned()) {
        let v = by_name(&name).unwrap_or_else(|| panic!("variable {name}"));
        match v.ty {
            VarType::Real => m.set_real(v, value.parse().unwrap()),
            VarType::Integer => m.set_integer(v, value.parse().unwrap()),
            VarType::Boolean => m.set_boolean(v, value == "true" || value == "1"),
            _ => panic!("{name}"),
        }
        .expect("set");
    }
    m.drive_params().expect("parameters")
}
