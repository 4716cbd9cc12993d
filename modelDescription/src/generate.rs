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
    let _ = writeln!(
        w,
        "#[allow(clippy::approx_constant)] // bounds as the XML writes them (pi as digits)"
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

/// The Rust source that ties a model's parameter ids to the model
/// description (see [`param_tables`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamTables {
    /// `impl {id_type} { pub const fn declared(self) -> {range_type} }`: each
    /// id's declared range (`min`, `max`, exclusive ends) and unit. Numbers
    /// only: the core that includes it learns no variable names.
    pub ranges: String,
    /// `fn var_of(p: {id_type}) -> (Var, usize)`: each id's variable in the
    /// table of [`rust_table`] and its array index; `pub fn param_of(var:
    /// Var, j: usize) -> Option<{id_type}>`, the other way; and for each coded id
    /// (`codes` of [`param_tables`], e.g. `FrictionLaw`)
    /// `pub fn decode_friction_law(code: i32) -> Option<T>` and
    /// `pub fn encode_friction_law(value: T) -> i32`, `T` the type of its values.
    pub variables: String,
    /// `impl {id_type} { pub const fn start(self) -> f64 }`: each id's start
    /// value as a number (an array id's of each element, by its 0-based
    /// index; a Boolean 0 or 1; a coded Integer its code); and for each
    /// coded id `pub const START_FRICTION_LAW: T`, its start value decoded.
    /// Numbers and the core's own values only: no variable names, no codes
    /// to interpret.
    pub starts: String,
}

/// A start attribute as a number: a Real's value, an Integer's, a Boolean's
/// 0 or 1.
fn start_number(v: &Variable) -> Result<f64, String> {
    let s = v
        .start
        .as_deref()
        .ok_or_else(|| format!("{} has no start value (line {})", v.name, v.line))?;
    let bad = || {
        format!(
            "{}: start=\"{s}\" is not a {} (line {})",
            v.name, v.ty, v.line
        )
    };
    Ok(match v.ty.as_str() {
        "Real" => s.trim().parse::<f64>().map_err(|_| bad())?,
        "Integer" => s.trim().parse::<i64>().map_err(|_| bad())? as f64,
        "Boolean" => match s.trim() {
            "true" | "1" => 1.0,
            "false" | "0" => 0.0,
            _ => return Err(bad()),
        },
        _ => return Err(bad()),
    })
}

/// `FrictionLaw` -> `FRICTION_LAW` (`upper`) or `friction_law`.
fn snake(id: &str, upper: bool) -> String {
    let mut out = String::new();
    for (i, ch) in id.chars().enumerate() {
        if ch.is_ascii_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(if upper {
            ch.to_ascii_uppercase()
        } else {
            ch.to_ascii_lowercase()
        });
    }
    out
}

/// One declared range as a Rust expression of the `Range` struct `ty`.
fn range_literal(md: &ModelDescription, v: &Variable, ty: &str) -> Result<String, String> {
    Ok(format!(
        "{ty} {{ min: {}, max: {}, min_exclusive: {}, max_exclusive: {}, unit: {:?} }}",
        bound_literal(&v.min)?,
        bound_literal(&v.max)?,
        v.min_exclusive,
        v.max_exclusive,
        md.unit_of(v).unwrap_or_default(),
    ))
}

/// The Rust source of [`ParamTables`] for a checked description `md`.
///
/// `ids` lists each parameter id of the core (a variant of the enum
/// `id_type`) with its variable's name; `#` in the name stands for the
/// 1-based array index and makes the id a one-field variant carrying the
/// 0-based index (`("PulleyRadius", "pulley[#].radius")` is
/// `PulleyRadius(j)` for `pulley[j + 1].radius`). Every element of such an
/// array must declare the same range and unit. `range_type` is the path of
/// the struct with the fields `min`, `max` (`Option<f64>`),
/// `min_exclusive`, `max_exclusive` (`bool`) and `unit` (`&'static str`).
/// The generated `match`es list every id without a wildcard, so the
/// compiler refuses an enum variant that `ids` lacks.
///
/// `codes` lists the Integer parameters whose values are codes: the id and
/// each code with the value it stands for, as a Rust path of the including
/// module (`("FrictionLaw", &[(1, "FrictionLaw::Kubas2014"), ...])`; the
/// type is the path less its last segment).
pub fn param_tables(
    md: &ModelDescription,
    ids: &[(&str, &str)],
    codes: &[(&str, &[(i32, &str)])],
    id_type: &str,
    range_type: &str,
) -> Result<ParamTables, String> {
    let mut ranges = String::new();
    let mut vars = String::new();
    let mut starts = String::new();
    let mut decoded = String::new();
    let mut coded_fns = String::new();
    let mut inverse = String::new();
    for (id, values) in codes {
        let (_, pattern) = ids
            .iter()
            .find(|(other, _)| other == id)
            .ok_or_else(|| format!("coded parameter {id} is not a parameter id"))?;
        let v = md
            .variable(pattern)
            .filter(|v| v.ty == "Integer")
            .ok_or_else(|| format!("coded parameter {id}: {pattern} is not an Integer"))?;
        let start = start_number(v)? as i32;
        let (_, value) = values.iter().find(|(c, _)| *c == start).ok_or_else(|| {
            format!("coded parameter {id}: start value {start} of {pattern} is no code")
        })?;
        // each code inside the declared range and explained by the
        // variable's description (`1 = kubas2014`), which the FMU shows
        // when it refuses a value that is no code
        let bound = |b: &Option<String>| b.as_deref().and_then(|s| s.trim().parse::<i32>().ok());
        for (c, _) in *values {
            if bound(&v.min).is_some_and(|lo| *c < lo) || bound(&v.max).is_some_and(|hi| *c > hi) {
                return Err(format!(
                    "coded parameter {id}: code {c} is outside the declared range of {pattern} (line {})",
                    v.line
                ));
            }
            if !v.description.contains(&format!("{c} = ")) {
                return Err(format!(
                    "coded parameter {id}: the description of {pattern} does not explain code {c} \
                     as \"{c} = ...\" (line {})",
                    v.line
                ));
            }
        }
        let ty = value
            .rsplit_once("::")
            .map(|(ty, _)| ty)
            .ok_or_else(|| format!("coded parameter {id}: {value} is not a path"))?;
        let (upper, lower) = (snake(id, true), snake(id, false));
        let _ = writeln!(
            decoded,
            "\n/// `{pattern}`'s start value ({start}), decoded.\npub const START_{upper}: {ty} = {value};"
        );
        let arms: String = values
            .iter()
            .map(|(c, v)| format!("        {c} => Some({v}),\n"))
            .collect();
        let back: String = values
            .iter()
            .map(|(c, v)| format!("        {v} => {c},\n"))
            .collect();
        let _ = write!(
            coded_fns,
            "\n/// The value `{pattern}`'s code stands for.\n\
             pub fn decode_{lower}(code: i32) -> Option<{ty}> {{\n    match code {{\n{arms}        _ => None,\n    }}\n}}\n\
             \n/// `{pattern}`'s code of a value.\n\
             pub fn encode_{lower}(value: {ty}) -> i32 {{\n    match value {{\n{back}    }}\n}}\n"
        );
    }
    for (i, (id, pattern)) in ids.iter().enumerate() {
        if ids[..i].iter().any(|(other, _)| other == id) {
            return Err(format!("parameter id {id} is listed twice"));
        }
        let array = pattern.contains("[#]");
        let elements: Vec<&Variable> = if array {
            (1..)
                .map_while(|k| md.variable(&pattern.replace('#', &k.to_string())))
                .collect()
        } else {
            md.variable(pattern).into_iter().collect()
        };
        let first = *elements
            .first()
            .ok_or_else(|| format!("parameter id {id}: no variable {pattern}"))?;
        let range = range_literal(md, first, range_type)?;
        for v in &elements[1..] {
            if range_literal(md, v, range_type)? != range {
                return Err(format!(
                    "parameter id {id}: {} declares another range or unit than {} (line {})",
                    v.name, first.name, v.line
                ));
            }
        }
        let (variant, _) = variant_and_index(&first.name)?;
        let values = elements
            .iter()
            .map(|v| start_number(v).map(|x| format!("{x:?}")))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| format!("parameter id {id}: {e}"))?;
        if array {
            let _ = writeln!(ranges, "            Self::{id}(_) => {range},");
            let _ = writeln!(vars, "        {id_type}::{id}(j) => (Var::{variant}, j),");
            let _ = writeln!(
                inverse,
                "        Var::{variant} => Some({id_type}::{id}(j)),"
            );
            let _ = writeln!(
                starts,
                "            Self::{id}(j) => [{}][j],",
                values.join(", ")
            );
        } else {
            let _ = writeln!(ranges, "            Self::{id} => {range},");
            let _ = writeln!(vars, "        {id_type}::{id} => (Var::{variant}, 0),");
            let _ = writeln!(inverse, "        Var::{variant} => Some({id_type}::{id}),");
            let _ = writeln!(starts, "            Self::{id} => {},", values[0]);
        }
    }
    Ok(ParamTables {
        ranges: format!(
            "// @generated by the model_description crate from modelDescription.xml. Do not edit.\n\n\
             impl {id_type} {{\n    \
             /// The declared range (`min`, `max`, exclusive ends) and unit of this\n    \
             /// parameter, as the model description states them.\n    \
             #[allow(clippy::approx_constant)] // bounds as the XML writes them (pi as digits)\n    \
             pub const fn declared(self) -> {range_type} {{\n        \
             match self {{\n{ranges}        }}\n    }}\n}}\n"
        ),
        variables: format!(
            "// @generated by the model_description crate from modelDescription.xml. Do not edit.\n\n\
             /// The variable behind a parameter id, and its 0-based array index.\n\
             fn var_of(p: {id_type}) -> (Var, usize) {{\n    \
             match p {{\n{vars}    }}\n}}\n\n\
             /// The parameter id behind a variable and its 0-based array index.\n\
             pub fn param_of(var: Var, j: usize) -> Option<{id_type}> {{\n    \
             match var {{\n{inverse}        _ => None,\n    }}\n}}\n{coded_fns}"
        ),
        starts: format!(
            "// @generated by the model_description crate from modelDescription.xml. Do not edit.\n\n\
             impl {id_type} {{\n    \
             /// The start value of this parameter as the model description states it\n    \
             /// (a pulley parameter's in its slot; a Boolean 0 or 1; a coded Integer\n    \
             /// its code, decoded in the `START_*` constants).\n    \
             pub const fn start(self) -> f64 {{\n        \
             match self {{\n{starts}        }}\n    }}\n}}\n{decoded}"
        ),
    })
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

    const TWO_SLOTS: &str = r#"<fmiModelDescription fmiVersion="2.0" modelName="M" guid="@GUID@">
  <UnitDefinitions><Unit name="m"/></UnitDefinitions>
  <TypeDefinitions><SimpleType name="L"><Real unit="m"/></SimpleType></TypeDefinitions>
  <VendorAnnotations><Tool name="BeltDrive"><ExclusiveBounds>
    <Range variable="p[1].r" min="exclusive"/><Range variable="p[2].r" min="exclusive"/>
  </ExclusiveBounds></Tool></VendorAnnotations>
  <ModelVariables>
    <ScalarVariable name="n" valueReference="1" description="2 = two, 3 = three" causality="parameter" variability="fixed">
      <Integer start="2" min="2" max="6"/></ScalarVariable>
    <ScalarVariable name="p[1].r" valueReference="2" causality="parameter" variability="fixed">
      <Real declaredType="L" start="1" min="0"/></ScalarVariable>
    <ScalarVariable name="p[2].r" valueReference="3" causality="parameter" variability="fixed">
      <Real declaredType="L" start="2" min="0"/></ScalarVariable>
  </ModelVariables>
</fmiModelDescription>"#;

    #[test]
    fn param_tables_follow_the_description() {
        let md = crate::parse(TWO_SLOTS).unwrap();
        let ids = [("Count", "n"), ("Radius", "p[#].r")];
        let t = param_tables(&md, &ids, &[], "Id", "R").unwrap();
        assert!(t.ranges.contains(
            "Self::Count => R { min: Some(2.0), max: Some(6.0), min_exclusive: false, max_exclusive: false, unit: \"\" },"
        ), "{}", t.ranges);
        assert!(t.ranges.contains(
            "Self::Radius(_) => R { min: Some(0.0), max: None, min_exclusive: true, max_exclusive: false, unit: \"m\" },"
        ), "{}", t.ranges);
        assert!(
            t.variables.contains("Id::Count => (Var::N, 0),"),
            "{}",
            t.variables
        );
        assert!(
            t.variables.contains("Id::Radius(j) => (Var::PR, j),"),
            "{}",
            t.variables
        );
        // refusals: an unknown variable, an id twice, slots that disagree
        let e = param_tables(&md, &[("X", "q[#].r")], &[], "Id", "R").unwrap_err();
        assert!(e.contains("X: no variable q[#].r"), "{e}");
        let e = param_tables(&md, &[("Count", "n"), ("Count", "n")], &[], "Id", "R").unwrap_err();
        assert!(e.contains("Count is listed twice"), "{e}");
        let md =
            crate::parse(&TWO_SLOTS.replacen("start=\"2\" min=\"0\"", "start=\"2\" min=\"1\"", 1))
                .unwrap();
        let e = param_tables(&md, &ids, &[], "Id", "R").unwrap_err();
        assert!(e.contains("p[2].r declares another range"), "{e}");
    }

    /// Start values per id and slot, and a coded Integer decoded: its start
    /// as the value it stands for, the decoding both ways.
    #[test]
    fn param_starts_and_codes_follow_the_description() {
        let md = crate::parse(TWO_SLOTS).unwrap();
        let ids = [("Count", "n"), ("Radius", "p[#].r")];
        let codes: &[(&str, &[(i32, &str)])] = &[("Count", &[(2, "K::Two"), (3, "K::Three")])];
        let t = param_tables(&md, &ids, codes, "Id", "R").unwrap();
        assert!(t.starts.contains("Self::Count => 2.0,"), "{}", t.starts);
        assert!(
            t.starts.contains("Self::Radius(j) => [1.0, 2.0][j],"),
            "{}",
            t.starts
        );
        assert!(
            t.starts.contains("pub const START_COUNT: K = K::Two;"),
            "{}",
            t.starts
        );
        for needle in [
            "pub fn decode_count(code: i32) -> Option<K> {",
            "        3 => Some(K::Three),",
            "pub fn encode_count(value: K) -> i32 {",
            "        K::Two => 2,",
        ] {
            assert!(t.variables.contains(needle), "{needle}: {}", t.variables);
        }
        // refusals: a start that is no code, a coded id that is not an id
        let codes: &[(&str, &[(i32, &str)])] = &[("Count", &[(1, "K::One")])];
        let e = param_tables(&md, &ids, codes, "Id", "R").unwrap_err();
        assert!(e.contains("start value 2 of n is no code"), "{e}");
        let codes: &[(&str, &[(i32, &str)])] = &[("Other", &[(2, "K::Two")])];
        let e = param_tables(&md, &ids, codes, "Id", "R").unwrap_err();
        assert!(e.contains("Other is not a parameter id"), "{e}");
        // a code outside the declared range, a code the description does not
        // explain
        let codes: &[(&str, &[(i32, &str)])] = &[("Count", &[(2, "K::Two"), (7, "K::Seven")])];
        let e = param_tables(&md, &ids, codes, "Id", "R").unwrap_err();
        assert!(
            e.contains("code 7 is outside the declared range of n"),
            "{e}"
        );
        let codes: &[(&str, &[(i32, &str)])] = &[("Count", &[(2, "K::Two"), (4, "K::Four")])];
        let e = param_tables(&md, &ids, codes, "Id", "R").unwrap_err();
        assert!(e.contains("does not explain code 4"), "{e}");
        // a parameter without a start value
        let md = crate::parse(&TWO_SLOTS.replacen("start=\"2\" min=\"0\"", "min=\"0\"", 1));
        let e = param_tables(&md.unwrap(), &ids, &[], "Id", "R").unwrap_err();
        assert!(e.contains("p[2].r has no start value"), "{e}");
    }
}
