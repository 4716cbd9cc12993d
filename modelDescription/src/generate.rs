//! The Rust variable table generated from a checked model description.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;

use crate::parse::{ModelDescription, Variable};

/// `pulley[3].hubForce.x` -> ("PulleyHubForceX", 2); scalars get index 0.
pub fn variant_and_index(name: &str) -> Result<(String, usize), String> {
    let mut variant = String::new();
    let mut index = None;
    for part in name.split('.') {
        let (base, idx) = match part.find('[') {
            Some(open) => {
                let digits = part[open + 1..]
                    .strip_suffix(']')
                    .ok_or_else(|| format!("cannot parse array index in \"{part}\""))?;
                let i: usize = digits.parse().map_err(|_| {
                    format!("only single, 1-based array indices are supported (\"{part}\")")
                })?;
                (&part[..open], Some(i))
            }
            None => (part, None),
        };
        let mut chars = base.chars();
        match chars.next() {
            Some(first) if first.is_ascii_alphabetic() || first == '_' => {
                if !chars
                    .clone()
                    .all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
                {
                    return Err(format!("name part \"{base}\" is not a plain identifier"));
                }
                variant.push(first.to_ascii_uppercase());
                variant.extend(chars);
            }
            _ => return Err(format!("name part \"{base}\" is not a plain identifier")),
        }
        if let Some(i) = idx {
            if i == 0 {
                return Err(format!("array indices are 1-based (\"{part}\")"));
            }
            if index.replace(i - 1).is_some() {
                return Err("at most one array index per name is supported".into());
            }
        }
    }
    Ok((variant, index.unwrap_or(0)))
}

/// The Rust `Start` expression for a start attribute of type `ty`.
pub fn start_literal(ty: &str, s: &str) -> Result<String, String> {
    let bad = || format!("start=\"{s}\" is not a valid {ty}");
    Ok(match ty {
        "Real" => {
            let x: f64 = s.trim().parse().map_err(|_| bad())?;
            if !x.is_finite() {
                return Err(bad());
            }
            format!("Start::Real({x:?})")
        }
        "Integer" => format!(
            "Start::Integer({})",
            s.trim().parse::<i32>().map_err(|_| bad())?
        ),
        "Boolean" => match s.trim() {
            "true" | "1" => "Start::Boolean(true)".into(),
            "false" | "0" => "Start::Boolean(false)".into(),
            _ => return Err(bad()),
        },
        _ => format!("Start::String({s:?})"),
    })
}

/// A `min`/`max` attribute as a Rust `Option<f64>` expression.
fn bound_literal(text: &Option<String>) -> Result<String, String> {
    Ok(match text {
        None => "None".into(),
        Some(s) => {
            let x: f64 = s
                .trim()
                .parse()
                .map_err(|_| format!("bound \"{s}\" is not a number"))?;
            if x.is_infinite() {
                "None".into()
            } else {
                format!("Some({x:?})")
            }
        }
    })
}

fn camel(s: &str) -> String {
    let mut out = String::new();
    let mut up = true;
    for ch in s.chars() {
        if ch == '_' || ch == ' ' {
            up = true;
        } else if up {
            out.push(ch.to_ascii_uppercase());
            up = false;
        } else {
            out.push(ch);
        }
    }
    out
}

/// Rust source of the variable table of a checked description `md` whose
/// GUID is `guid`. `fmi` is the path of the module that defines the table's
/// types (`VarInfo`, `ModelDescription`, `Start`, `VarType`, `Causality`,
/// `Variability`), e.g. `crate::fmi`. The source defines:
///
/// * `MODEL_IDENTIFIER`, `GUID`, `LOG_CATEGORIES`;
/// * `Var`, one variant per base name (`pulley[3].hubForce.x` is
///   `Var::PulleyHubForceX` with `VarInfo::index == 2`), and `VarInfo`
///   (`{fmi}::VarInfo<Var>`);
/// * `VARIABLES` in XML order and `MODEL_DESCRIPTION`, the table with its
///   look-ups, plus `lookup(ty, vr)` and `by_name(name)`;
/// * re-exports of `Start`, `VarType`, `Causality` and `Variability`.
pub fn rust_table(md: &ModelDescription, guid: &str, fmi: &str) -> Result<String, String> {
    let mut o = String::new();
    let w = &mut o;
    let model_identifier = md.model_identifier.as_deref().unwrap_or_default();
    let categories: Vec<&str> = md.log_categories.iter().map(|c| c.name.as_str()).collect();

    // Variants in order of first appearance, with their element count.
    let mut variants: Vec<(String, usize, &Variable)> = Vec::new();
    let mut position: HashMap<String, usize> = HashMap::new();
    for v in &md.variables {
        let (variant, _) = variant_and_index(&v.name)?;
        match position.get(&variant) {
            Some(&p) => variants[p].1 += 1,
            None => {
                position.insert(variant.clone(), variants.len());
                variants.push((variant, 1, v));
            }
        }
    }

    let _ = writeln!(
        w,
        "// @generated by the model_description crate from modelDescription.xml. Do not edit.\n"
    );
    let _ = writeln!(
        w,
        "pub use {fmi}::{{Causality, Start, VarType, Variability}};\n"
    );
    let _ = writeln!(
        w,
        "/// `modelIdentifier` of the `<CoSimulation>` element (name of the binary)."
    );
    let _ = writeln!(
        w,
        "pub const MODEL_IDENTIFIER: &str = {model_identifier:?};"
    );
    let _ = writeln!(
        w,
        "/// GUID of this build's model description (a hash of the XML)."
    );
    let _ = writeln!(w, "pub const GUID: &str = {guid:?};");
    let _ = writeln!(w, "/// Names of the `<LogCategories>`, in XML order.");
    let _ = writeln!(w, "pub static LOG_CATEGORIES: &[&str] = &{categories:?};\n");

    let _ = writeln!(
        w,
        "/// One variant per variable base name: the name with its array index"
    );
    let _ = writeln!(
        w,
        "/// dropped, split on `.` and camel-cased (`pulley[3].hubForce.x` is"
    );
    let _ = writeln!(w, "/// `PulleyHubForceX` with `VarInfo::index` 2).");
    let _ = writeln!(
        w,
        "#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]\npub enum Var {{"
    );
    for (variant, count, first) in &variants {
        let doc = if *count > 1 {
            format!(
                "`{}` ({} elements, index 0..{}): {}",
                first.name,
                count,
                count - 1,
                first.description
            )
        } else {
            format!("`{}`: {}", first.name, first.description)
        };
        let _ = writeln!(w, "    #[doc = {doc:?}]\n    {variant},");
    }
    let _ = writeln!(w, "}}\n");
    let _ = writeln!(w, "/// One ScalarVariable of this model.");
    let _ = writeln!(w, "pub type VarInfo = {fmi}::VarInfo<Var>;\n");

    let _ = writeln!(
        w,
        "/// Every ScalarVariable, in XML order (`VARIABLES[i]` has ModelStructure index `i + 1`)."
    );
    let _ = writeln!(w, "pub static VARIABLES: &[VarInfo] = &[");
    for v in &md.variables {
        let (variant, index) = variant_and_index(&v.name)?;
        let start = match &v.start {
            Some(s) => start_literal(&v.ty, s)?,
            None => "Start::None".into(),
        };
        let unit = md.unit_of(v).unwrap_or_default();
        let _ = writeln!(
            w,
            "    {fmi}::VarInfo {{ vr: {}, name: {:?}, var: Var::{variant}, index: {index}, ty: VarType::{}, causality: Causality::{}, variability: Variability::{}, start: {start}, min: {}, max: {}, description: {:?}, unit: {unit:?} }},",
            v.vr,
            v.name,
            v.ty,
            camel(&v.causality),
            camel(&v.variability),
            bound_literal(&v.min)?,
            bound_literal(&v.max)?,
            v.description,
        );
    }
    let _ = writeln!(w, "];\n");

    let by_vr: BTreeMap<u32, usize> = md
        .variables
        .iter()
        .enumerate()
        .map(|(i, v)| (v.vr, i))
        .collect();
    let _ = writeln!(
        w,
        "/// (value reference, position in `VARIABLES`), sorted by value reference."
    );
    let _ = writeln!(w, "static BY_VR: &[(u32, u32)] = &[");
    for (vr, i) in &by_vr {
        let _ = writeln!(w, "    ({vr}, {i}),");
    }
    let _ = writeln!(w, "];\n");

    let by_name: BTreeMap<&str, usize> = md
        .variables
        .iter()
        .enumerate()
        .map(|(i, v)| (v.name.as_str(), i))
        .collect();
    let _ = writeln!(
        w,
        "/// (name, position in `VARIABLES`), sorted by name (byte order)."
    );
    let _ = writeln!(w, "static BY_NAME: &[(&str, u32)] = &[");
    for (name, i) in &by_name {
        let _ = writeln!(w, "    ({name:?}, {i}),");
    }
    let _ = writeln!(w, "];\n");

    let _ = writeln!(
        w,
        r#"/// The model's identity and variables, as the FMI plumbing takes them.
pub static MODEL_DESCRIPTION: {fmi}::ModelDescription<Var> = {fmi}::ModelDescription {{
    model_identifier: MODEL_IDENTIFIER,
    guid: GUID,
    log_categories: LOG_CATEGORIES,
    variables: VARIABLES,
    by_vr: BY_VR,
    by_name: BY_NAME,
}};

/// The variable of type `ty` with value reference `vr`.
pub fn lookup(ty: VarType, vr: u32) -> Option<&'static VarInfo> {{
    MODEL_DESCRIPTION.lookup(ty, vr)
}}

/// The variable with this exact name.
pub fn by_name(name: &str) -> Option<&'static VarInfo> {{
    MODEL_DESCRIPTION.by_name(name)
}}"#
    );
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variant_names() {
        assert_eq!(
            variant_and_index("pulley[3].hubForce.x").unwrap(),
            ("PulleyHubForceX".into(), 2)
        );
        assert_eq!(variant_and_index("belt.EA").unwrap(), ("BeltEA".into(), 0));
        assert_eq!(
            variant_and_index("span[12].slip").unwrap(),
            ("SpanSlip".into(), 11)
        );
        for bad in ["a.", "1a", "a-b", "a[x]", "a[0]", "a[1].b[1]", "a[1"] {
            assert!(variant_and_index(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn literals() {
        assert_eq!(start_literal("Real", "1e3").unwrap(), "Start::Real(1000.0)");
        assert_eq!(start_literal("Real", " 0.5 ").unwrap(), "Start::Real(0.5)");
        assert!(start_literal("Real", "NaN").is_err());
        assert_eq!(
            start_literal("Integer", "-3").unwrap(),
            "Start::Integer(-3)"
        );
        assert!(start_literal("Integer", "3000000000").is_err());
        assert_eq!(
            start_literal("Boolean", "1").unwrap(),
            "Start::Boolean(true)"
        );
        assert!(start_literal("Boolean", "yes").is_err());
        assert_eq!(
            start_literal("String", "a\"b").unwrap(),
            "Start::String(\"a\\\"b\")"
        );
        assert_eq!(bound_literal(&Some("2".into())).unwrap(), "Some(2.0)");
        assert_eq!(bound_literal(&Some("-INF".into())).unwrap(), "None");
        assert_eq!(bound_literal(&None).unwrap(), "None");
        assert_eq!(camel("calculatedParameter"), "CalculatedParameter");
    }
}
