//! Reads, checks and compiles an FMI 2.0 Co-Simulation `modelDescription.xml`.
//!
//! The one piece of code that reads the project's XML: `build.rs` turns the
//! model description into the Rust variable table, `cargo xtask fmu` packages
//! it with the GUID and binary path taken from here, and the tests read the
//! SSP parameter sets with [`ssv`].
//!
//! * [`parse`]: the XML into [`ModelDescription`] (line numbers kept);
//! * [`check`]: the rules of FMI 2.0 section 2.2 and of the generated table;
//! * [`rust_table`]: the Rust source of the variable table;
//! * [`param_tables`]: the Rust source that gives a model's parameter ids
//!   their declared ranges and variables;
//! * [`guid`]: the GUID, a hash of the file's text;
//! * [`compile`]: all of the above for one file;
//! * [`platform`]: where the binary goes in the FMU archive;
//! * [`ssv`]: SSP parameter sets.

#![warn(missing_docs)]

mod check;
mod generate;
pub mod guid;
mod parse;
pub mod platform;
pub mod registry;
pub mod ssv;

pub use check::{check, effective_initial};
pub use generate::{param_tables, rust_table, variant_and_index, ParamTables};
pub use parse::{
    parse, LogCategory, ModelDescription, SimpleType, Unit, Unknown, Variable, RANGE_TOOL,
};

/// A checked model description ready to be packaged.
#[derive(Clone, Debug)]
pub struct Compiled {
    /// The parsed and checked description.
    pub description: ModelDescription,
    /// The GUID hashed from the source text.
    pub guid: String,
    /// The source text with the GUID in place of the placeholder: the
    /// `modelDescription.xml` that goes into the FMU.
    pub xml: String,
}

impl Compiled {
    /// `modelIdentifier` of `<CoSimulation>` (present: [`check`] requires it).
    pub fn model_identifier(&self) -> &str {
        self.description
            .model_identifier
            .as_deref()
            .unwrap_or_default()
    }
}

/// Parse and check the source text of a model description, hash its GUID
/// and put the GUID in place of the `@GUID@` placeholder.
pub fn compile(source: &str) -> Result<Compiled, String> {
    let description = parse(source)?;
    check(&description)?;
    let guid = guid::guid_for_xml(source);
    let xml = guid::substitute_guid(source, &guid)
        .ok_or("the placeholder @GUID@ must occur exactly once (in the guid attribute)")?;
    Ok(Compiled {
        description,
        guid,
        xml,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The project's model description compiles, and the packaged text
    /// parses back with the GUID in it.
    #[test]
    fn project_model_description() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription.xml");
        let source = std::fs::read_to_string(path).unwrap();
        let c = compile(&source).unwrap();
        assert!(!c.xml.contains(guid::GUID_PLACEHOLDER));
        let back = parse(&c.xml).unwrap();
        assert_eq!(back.guid_attr, c.guid);
        assert_eq!(back.variables, c.description.variables);
        let table = rust_table(&c.description, &c.guid, "crate::fmi").unwrap();
        assert!(table.contains(&format!("pub const GUID: &str = {:?};", c.guid)));
        assert!(platform::host_binary_path(c.model_identifier())
            .unwrap()
            .starts_with("binaries/"));
    }

    #[test]
    fn compile_needs_one_placeholder() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription.xml");
        let source = std::fs::read_to_string(path).unwrap();
        let twice = source.replacen("<!--", "<!-- @GUID@", 1);
        assert!(compile(&twice).unwrap_err().contains("exactly once"));
    }

    /// Damaged copies of the project's description (bytes cut out,
    /// duplicated or flipped; deterministic pseudo-random positions) are
    /// refused or accepted, never a panic.
    #[test]
    fn damaged_descriptions_never_panic() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription.xml");
        let source = std::fs::read(path).unwrap();
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        let (mut refused, mut accepted) = (0, 0);
        for round in 0..300 {
            let mut bytes = source.clone();
            let at = next(bytes.len());
            let len = 1 + next(40);
            match round % 3 {
                0 => drop(bytes.drain(at..(at + len).min(bytes.len()))),
                1 => {
                    let piece = bytes[at..(at + len).min(bytes.len())].to_vec();
                    bytes.splice(at..at, piece);
                }
                _ => bytes[at] ^= 1 << next(7),
            }
            let text = String::from_utf8_lossy(&bytes);
            let result = std::panic::catch_unwind(|| compile(&text).map(|_| ()));
            match result.expect("compile panicked") {
                Ok(()) => accepted += 1,
                Err(e) => {
                    assert!(!e.is_empty());
                    refused += 1;
                }
            }
        }
        // Most damage must be caught (a cut inside a description or a
        // comment is harmless, so not all of it).
        assert!(refused > 150, "refused {refused}, accepted {accepted}");
    }
}
