//! Build script: turns `modelDescription/modelDescription.xml` into Rust with
//! the `model_description` crate (the crate in `modelDescription/`, tested on
//! its own). The file is generated from that crate's registry
//! (`modelDescription/src/registry/table.rs`, `cargo xtask model-description`);
//! the build refuses a file that is not the registry's. It parses and checks
//! the description (a violation fails the build with a message naming the
//! line), hashes its GUID, and writes
//!
//! * `$OUT_DIR/variables.rs`, included by `src/fmu/variables.rs`: the variable
//!   table, `Var` (one variant per base name), `lookup`, `by_name`;
//! * `$OUT_DIR/modelDescription.xml`, the description with its GUID;
//! * `$OUT_DIR/param_ranges.rs`, included by `src/model/param_id.rs`: each
//!   parameter id's declared range and unit (`Param::declared`), and
//!   `$OUT_DIR/param_starts.rs`, included by `src/model/params.rs`: each id's
//!   start value (`Param::start`, the core's defaults), and
//!   `$OUT_DIR/param_variables.rs`, included by `src/fmu/names.rs`: each
//!   id's variable (`var_of`) and the decoding of the coded Integers, and
//!   `$OUT_DIR/param_list.rs`, included by `src/model/param_id.rs`: the
//!   parameter ids with their engineering names, all from the registry.

use std::path::PathBuf;
use std::{env, fs, process};

const XML_PATH: &str = "modelDescription/modelDescription.xml";

fn main() {
    println!("cargo:rerun-if-changed={XML_PATH}");
    println!("cargo:rerun-if-changed=build.rs");

    if let Err(e) = run() {
        // A panic would print a backtrace hint; a plain message reads better.
        eprintln!("error: {XML_PATH}: {e}");
        println!("cargo:warning={XML_PATH}: {e}");
        process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let manifest_dir = PathBuf::from(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
    let out_dir = PathBuf::from(env::var("OUT_DIR").map_err(|e| e.to_string())?);
    let source = fs::read_to_string(manifest_dir.join(XML_PATH))
        .map_err(|e| format!("cannot read the file: {e}"))?;
    let registry = model_description::registry::model_description();
    if source != registry {
        return Err(
            "the file is not the registry's (modelDescription/src/registry/table.rs): \
                    edit the registry, then run `cargo xtask model-description`"
                .into(),
        );
    }
    let compiled = model_description::compile(&source)?;
    let table = model_description::rust_table(&compiled.description, &compiled.guid, "crate::fmi")?;
    let ids = model_description::registry::param_ids();
    let codes = model_description::registry::param_codes();
    let params = model_description::param_tables(
        &compiled.description,
        &ids,
        &codes,
        "Param",
        "DeclaredRange",
    )
    .map_err(|e| format!("{e} (the registry)"))?;
    write(&out_dir.join("modelDescription.xml"), &compiled.xml)?;
    write(&out_dir.join("param_ranges.rs"), &params.ranges)?;
    write(&out_dir.join("param_variables.rs"), &params.variables)?;
    write(&out_dir.join("param_starts.rs"), &params.starts)?;
    write(
        &out_dir.join("param_list.rs"),
        &model_description::registry::param_list(),
    )?;
    write(&out_dir.join("variables.rs"), &table)
}

fn write(path: &PathBuf, text: &str) -> Result<(), String> {
    fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
