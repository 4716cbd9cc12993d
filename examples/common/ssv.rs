//! A drive from a parameter file of parameters/ (.ssv), set through the FMU's
//! own variables: shared by examples/mesh_study.rs, examples/stiff_energy.rs and
//! examples/wrap_profile.rs (included with `#[path]`, one definition).

use std::path::Path;

use belt_drive::fmi::FmuModel;
use belt_drive::fmu::variables::{by_name, VarType};
use belt_drive::fmu::BeltDrive;
use belt_drive::DriveParams;

/// The parameters of `parameters/<file>` set through the FMU's own variables.
pub fn from_ssv(file: &str) -> DriveParams {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("parameters")
        .join(file);
    let text = std::fs::read_to_string(&path).expect("parameter file");
    let mut m = BeltDrive::new();
    for p in model_description::ssv::read(&text).expect("ssv") {
        let v = by_name(&p.name).expect("variable");
        match v.ty {
            VarType::Real => m.set_real(v, p.value.parse().unwrap()),
            VarType::Integer => m.set_integer(v, p.value.parse().unwrap()),
            VarType::Boolean => m.set_boolean(v, p.value == "true" || p.value == "1"),
            _ => panic!("{}", p.name),
        }
        .expect("set");
    }
    m.drive_params().expect("parameters")
}
