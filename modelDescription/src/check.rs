//! The rules a model description must follow: FMI 2.0 (section 2.2) and
//! what the generated variable table and the FMI plumbing rely on. Every
//! message names the line and, for a variable, its name.

use std::collections::{HashMap, HashSet};

use crate::generate::variant_and_index;
use crate::guid::GUID_PLACEHOLDER;
use crate::parse::{ModelDescription, Unknown, Variable};

/// `initial` as written or defaulted (FMI 2.0 table in section 2.2.7);
/// `None` where the attribute is not allowed (input, independent).
pub fn effective_initial(v: &Variable) -> Option<&str> {
    if let Some(i) = v.initial.as_deref() {
        return Some(i);
    }
    match (v.causality.as_str(), v.variability.as_str()) {
        ("input", _) | ("independent", _) => None,
        (_, "constant") | ("parameter", _) => Some("exact"),
        _ => Some("calculated"),
    }
}

/// Check `md`; the first violation found is the error.
pub fn check(md: &ModelDescription) -> Result<(), String> {
    if md.fmi_version != "2.0" {
        return Err(format!(
            "fmiVersion must be \"2.0\", found \"{}\"",
            md.fmi_version
        ));
    }
    if md.guid_attr != GUID_PLACEHOLDER {
        return Err(format!(
            "the guid attribute must be the placeholder {GUID_PLACEHOLDER} (the GUID is computed at build time), found \"{}\"",
            md.guid_attr
        ));
    }
    match md.model_identifier.as_deref() {
        None => return Err("no <CoSimulation modelIdentifier=...> element".into()),
        Some(id) if !is_c_identifier(id) => {
            return Err(format!(
                "modelIdentifier \"{id}\" must be a valid C identifier (it names the binary and prefixes its functions)"
            ))
        }
        Some(_) => {}
    }
    let mut seen = HashSet::new();
    for u in &md.units {
        if !seen.insert(u.name.as_str()) {
            return Err(format!(
                "line {}: unit \"{}\" is defined twice",
                u.line, u.name
            ));
        }
    }
    let mut seen = HashSet::new();
    for t in &md.types {
        if !seen.insert(t.name.as_str()) {
            return Err(format!(
                "line {}: SimpleType \"{}\" is defined twice",
                t.line, t.name
            ));
        }
        if let Some(u) = &t.unit {
            if md.unit(u).is_none() {
                return Err(format!(
                    "line {}: SimpleType \"{}\" uses unit \"{u}\" which is not in <UnitDefinitions>",
                    t.line, t.name
                ));
            }
        }
    }
    let mut seen = HashSet::new();
    for c in &md.log_categories {
        if !seen.insert(c.name.as_str()) {
            return Err(format!(
                "line {}: log category \"{}\" is listed twice",
                c.line, c.name
            ));
        }
    }

    let mut names = HashMap::new();
    let mut vrs: HashMap<u32, &Variable> = HashMap::new();
    let mut keys = HashMap::new();
    for v in &md.variables {
        let at = |msg: String| format!("line {}: variable \"{}\": {msg}", v.line, v.name);
        if let Some(prev) = names.insert(v.name.as_str(), v.line) {
            return Err(at(format!("duplicate name (first defined on line {prev})")));
        }
        if let Some(prev) = vrs.insert(v.vr, v) {
            return Err(at(format!(
                "duplicate valueReference {} (also used by \"{}\" on line {}); value references must be unique across all types",
                v.vr, prev.name, prev.line
            )));
        }
        let (variant, index) = variant_and_index(&v.name).map_err(at)?;
        if let Some(prev) = keys.insert((variant.clone(), index), v) {
            return Err(at(format!(
                "maps to Var::{variant} index {index} like \"{}\" on line {}",
                prev.name, prev.line
            )));
        }
        if v.description.trim().is_empty() {
            return Err(at("has no description".into()));
        }
        check_variable(md, v).map_err(at)?;
    }
    check_structure(md)
}

/// ModelStructure: Outputs lists every output once, in index order;
/// InitialUnknowns lists the outputs with initial approx/calculated and the
/// calculated parameters (a Co-Simulation FMU without states); dependencies
/// point at variables an unknown can depend on.
fn check_structure(md: &ModelDescription) -> Result<(), String> {
    let n = md.variables.len();
    let positions = |list: &[Unknown], what: &str| -> Result<Vec<usize>, String> {
        let mut last = 0;
        for u in list {
            let line = u.line;
            if u.index == 0 || u.index > n {
                return Err(format!(
                    "line {line}: {what} index {} is outside 1..={n}",
                    u.index
                ));
            }
            if u.index <= last {
                return Err(format!(
                    "line {line}: {what} indices must be strictly ascending ({} after {last})",
                    u.index
                ));
            }
            last = u.index;
            check_dependencies(md, u, what)?;
        }
        Ok(list.iter().map(|u| u.index).collect())
    };
    let outputs = positions(&md.outputs, "ModelStructure/Outputs")?;
    let expected: Vec<usize> = (1..=n)
        .filter(|&i| md.variables[i - 1].causality == "output")
        .collect();
    if outputs != expected {
        return Err(format!(
            "ModelStructure/Outputs must list exactly the outputs by their 1-based position in ModelVariables: expected {expected:?}, found {outputs:?}"
        ));
    }
    let initial = positions(&md.initial_unknowns, "ModelStructure/InitialUnknowns")?;
    let expected: Vec<usize> = (1..=n)
        .filter(|&i| {
            let v = &md.variables[i - 1];
            (v.causality == "output"
                && matches!(effective_initial(v), Some("approx" | "calculated")))
                || v.causality == "calculatedParameter"
        })
        .collect();
    if initial != expected {
        return Err(format!(
            "ModelStructure/InitialUnknowns must list the outputs with initial=approx/calculated and the calculated parameters: expected {expected:?}, found {initial:?}"
        ));
    }
    Ok(())
}

/// `dependencies` of one unknown: positions of inputs, parameters or other
/// knowns (FMI 2.0 section 2.2.8), never the unknown itself;
/// `dependenciesKind` (if given) has one valid entry per dependency.
fn check_dependencies(md: &ModelDescription, u: &Unknown, what: &str) -> Result<(), String> {
    let line = u.line;
    let Some(deps) = &u.dependencies else {
        if u.dependencies_kind.is_some() {
            return Err(format!(
                "line {line}: {what} index {}: dependenciesKind without dependencies",
                u.index
            ));
        }
        return Ok(());
    };
    for &d in deps {
        if d == 0 || d > md.variables.len() {
            return Err(format!(
                "line {line}: {what} index {}: dependency {d} is outside 1..={}",
                u.index,
                md.variables.len()
            ));
        }
        if d == u.index {
            return Err(format!(
                "line {line}: {what} index {}: an unknown cannot depend on itself",
                u.index
            ));
        }
        let v = &md.variables[d - 1];
        if v.causality == "output" || v.causality == "local" {
            return Err(format!(
                "line {line}: {what} index {}: dependency {d} is \"{}\", a{} {} variable, not an input or parameter",
                u.index,
                v.name,
                if v.causality == "output" { "n" } else { "" },
                v.causality
            ));
        }
    }
    if let Some(kinds) = &u.dependencies_kind {
        if kinds.len() != deps.len() {
            return Err(format!(
                "line {line}: {what} index {}: {} dependenciesKind entries for {} dependencies",
                u.index,
                kinds.len(),
                deps.len()
            ));
        }
        if let Some(k) = kinds.iter().find(|k| {
            !matches!(
                k.as_str(),
                "dependent" | "constant" | "fixed" | "tunable" | "discrete"
            )
        }) {
            return Err(format!(
                "line {line}: {what} index {}: unknown dependenciesKind \"{k}\"",
                u.index
            ));
        }
    }
    Ok(())
}

fn is_c_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn check_variable(md: &ModelDescription, v: &Variable) -> Result<(), String> {
    let (c, var) = (v.causality.as_str(), v.variability.as_str());
    if !matches!(
        c,
        "parameter" | "calculatedParameter" | "input" | "output" | "local" | "independent"
    ) {
        return Err(format!("unknown causality \"{c}\""));
    }
    if !matches!(
        var,
        "constant" | "fixed" | "tunable" | "discrete" | "continuous"
    ) {
        return Err(format!("unknown variability \"{var}\""));
    }
    let legal = match c {
        "parameter" | "calculatedParameter" => matches!(var, "fixed" | "tunable"),
        "input" => matches!(var, "discrete" | "continuous"),
        "independent" => var == "continuous",
        _ => true,
    };
    if !legal {
        return Err(format!(
            "causality=\"{c}\" with variability=\"{var}\" is not allowed (FMI 2.0 section 2.2.7)"
        ));
    }
    if !matches!(v.ty.as_str(), "Real" | "Integer" | "Boolean" | "String") {
        return Err(format!(
            "type <{}> is not supported (Real, Integer, Boolean, String)",
            v.ty
        ));
    }
    if var == "continuous" && v.ty != "Real" {
        return Err("only Real variables can be continuous".into());
    }
    match (c, v.initial.as_deref()) {
        (_, None) => {}
        ("input" | "independent", Some(_)) => {
            return Err(format!(
                "causality=\"{c}\" must not have an initial attribute"
            ))
        }
        (_, Some(i)) if !matches!(i, "exact" | "approx" | "calculated") => {
            return Err(format!("unknown initial \"{i}\""))
        }
        ("parameter", Some(i)) if i != "exact" => {
            return Err("a parameter must have initial=\"exact\"".into())
        }
        _ => {}
    }
    let needs_start = c == "input" || matches!(effective_initial(v), Some("exact" | "approx"));
    match (&v.start, needs_start) {
        (None, true) => return Err("needs a start value (input, or initial exact/approx)".into()),
        (Some(_), false) => {
            return Err(
                "must not have a start value (initial=\"calculated\" or independent)".into(),
            )
        }
        (Some(s), true) => {
            crate::generate::start_literal(&v.ty, s)?;
        }
        (None, false) => {}
    }
    check_range(v)?;
    // Declared type and unit: every Real uses a declaredType (project rule).
    if let Some(dt) = &v.declared_type {
        let t = md
            .simple_type(dt)
            .ok_or_else(|| format!("declaredType \"{dt}\" is not in <TypeDefinitions>"))?;
        if t.ty != v.ty {
            return Err(format!(
                "declaredType \"{dt}\" is a {} type, the variable is {}",
                t.ty, v.ty
            ));
        }
    } else if v.ty == "Real" {
        return Err("Real variables must use a declaredType from <TypeDefinitions>".into());
    }
    if let Some(u) = &v.unit {
        if md.unit(u).is_none() {
            return Err(format!("unit \"{u}\" is not in <UnitDefinitions>"));
        }
    }
    Ok(())
}

/// `min`/`max`: only on Real and Integer, numbers of the variable's type,
/// `min <= max`, and a start value inside them.
pub(crate) fn check_range(v: &Variable) -> Result<(), String> {
    let bound = |key: &str, text: &Option<String>| -> Result<Option<f64>, String> {
        let Some(s) = text else { return Ok(None) };
        let x = match v.ty.as_str() {
            "Real" => s.trim().parse::<f64>().ok().filter(|x| !x.is_nan()),
            "Integer" => s.trim().parse::<i32>().ok().map(f64::from),
            other => return Err(format!("{key} is not allowed on a {other} variable")),
        };
        x.map(Some)
            .ok_or_else(|| format!("{key}=\"{s}\" is not a valid {}", v.ty))
    };
    let (min, max) = (bound("min", &v.min)?, bound("max", &v.max)?);
    for (open, bound, key) in [(v.min_exclusive, min, "min"), (v.max_exclusive, max, "max")] {
        if open && bound.is_none() {
            return Err(format!(
                "the {} annotation makes {key} exclusive, but no {key} is declared",
                crate::parse::RANGE_TOOL
            ));
        }
    }
    if let (Some(lo), Some(hi)) = (min, max) {
        if lo > hi {
            return Err(format!("min = {lo} is greater than max = {hi}"));
        }
        if lo == hi && (v.min_exclusive || v.max_exclusive) {
            return Err(format!(
                "min = max = {lo} with an exclusive end leaves no value"
            ));
        }
    }
    if let Some(x) = v
        .start
        .as_deref()
        .and_then(|s| s.trim().parse::<f64>().ok())
    {
        let below = min.is_some_and(|lo| x < lo || (v.min_exclusive && x == lo));
        let above = max.is_some_and(|hi| x > hi || (v.max_exclusive && x == hi));
        if below || above {
            return Err(format!(
                "start = {x} is outside {}{}, {}{}",
                if v.min_exclusive { "(" } else { "[" },
                v.min.as_deref().unwrap_or("-inf"),
                v.max.as_deref().unwrap_or("inf"),
                if v.max_exclusive { ")" } else { "]" },
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::parse;

    /// A valid description with one parameter, one input and two outputs.
    const OK: &str = r#"<fmiModelDescription fmiVersion="2.0" modelName="M" guid="@GUID@">
  <CoSimulation modelIdentifier="M"/>
  <UnitDefinitions><Unit name="m"/></UnitDefinitions>
  <TypeDefinitions><SimpleType name="L"><Real unit="m"/></SimpleType></TypeDefinitions>
  <LogCategories><Category name="logEvents"/></LogCategories>
  <ModelVariables>
    <ScalarVariable name="n" valueReference="1" description="d" causality="parameter" variability="fixed">
      <Integer start="2" min="1" max="6"/></ScalarVariable>
    <ScalarVariable name="u" valueReference="2" description="d" causality="input">
      <Real declaredType="L" start="0"/></ScalarVariable>
    <ScalarVariable name="p[1].y" valueReference="3" description="d" causality="output">
      <Real declaredType="L"/></ScalarVariable>
    <ScalarVariable name="p[2].y" valueReference="4" description="d" causality="output" initial="exact">
      <Real declaredType="L" start="1"/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="3" dependencies="2" dependenciesKind="dependent"/><Unknown index="4"/></Outputs>
    <InitialUnknowns><Unknown index="3"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>"#;

    fn err(from: &str, to: &str) -> String {
        assert!(OK.contains(from), "test pattern {from:?} not in the sample");
        let md = parse(&OK.replacen(from, to, 1)).unwrap();
        check(&md).expect_err(to)
    }

    #[test]
    fn valid_sample_passes() {
        check(&parse(OK).unwrap()).unwrap();
    }

    #[test]
    fn header_rules() {
        assert!(err("fmiVersion=\"2.0\"", "fmiVersion=\"3.0\"").contains("fmiVersion must be"));
        assert!(err("guid=\"@GUID@\"", "guid=\"{x}\"").contains("placeholder @GUID@"));
        assert!(err("<CoSimulation modelIdentifier=\"M\"/>", "")
            .contains("no <CoSimulation modelIdentifier"));
        assert!(
            err("modelIdentifier=\"M\"", "modelIdentifier=\"a b\"").contains("valid C identifier")
        );
        assert!(
            err("<Unit name=\"m\"/>", "<Unit name=\"m\"/><Unit name=\"m\"/>")
                .contains("unit \"m\" is defined twice")
        );
        assert!(err("<Real unit=\"m\"/>", "<Real unit=\"s\"/>")
            .contains("uses unit \"s\" which is not in <UnitDefinitions>"));
        assert!(err(
            "<Category name=\"logEvents\"/>",
            "<Category name=\"logEvents\"/><Category name=\"logEvents\"/>"
        )
        .contains("listed twice"));
    }

    #[test]
    fn variable_rules() {
        let cases = [
            ("valueReference=\"2\"", "valueReference=\"1\"", "line 9: variable \"u\": duplicate valueReference 1"),
            ("name=\"u\"", "name=\"n\"", "duplicate name (first defined on line 7)"),
            ("name=\"p[2].y\"", "name=\"p[1].y\"", "duplicate name"),
            ("name=\"u\"", "name=\"p[3]y\"", "cannot parse array index"),
            ("name=\"u\"", "name=\"p[0].y\"", "array indices are 1-based"),
            ("name=\"u\"", "name=\"a[1].b[2]\"", "at most one array index"),
            ("name=\"u\"", "name=\"p_3.y\"", ""), // a valid name: checked below
            ("causality=\"input\"", "causality=\"sideways\"", "unknown causality"),
            ("variability=\"fixed\"", "variability=\"continuous\"", "is not allowed (FMI 2.0 section 2.2.7)"),
            ("<Integer start=\"2\" min=\"1\" max=\"6\"/>", "<Enumeration start=\"2\"/>", "type <Enumeration> is not supported"),
            ("causality=\"input\"", "causality=\"input\" initial=\"exact\"", "must not have an initial attribute"),
            ("causality=\"output\" initial=\"exact\"", "causality=\"output\" initial=\"maybe\"", "unknown initial"),
            ("variability=\"fixed\"", "variability=\"fixed\" initial=\"approx\"", "a parameter must have initial=\"exact\""),
            ("<Real declaredType=\"L\" start=\"0\"/>", "<Real declaredType=\"L\"/>", "needs a start value"),
            ("<Real declaredType=\"L\"/></ScalarVariable>\n    <ScalarVariable name=\"p[2]", "<Real declaredType=\"L\" start=\"1\"/></ScalarVariable>\n    <ScalarVariable name=\"p[2]", "must not have a start value"),
            ("start=\"2\"", "start=\"2.5\"", "start=\"2.5\" is not a valid Integer"),
            ("start=\"0\"", "start=\"inf\"", "is not a valid Real"),
            ("min=\"1\"", "min=\"7\"", "min = 7 is greater than max = 6"),
            ("start=\"2\"", "start=\"9\"", "start = 9 is outside [1, 6]"),
            ("min=\"1\"", "min=\"x\"", "min=\"x\" is not a valid Integer"),
            ("<Real declaredType=\"L\" start=\"0\"/>", "<Real start=\"0\"/>", "must use a declaredType"),
            ("<Real declaredType=\"L\" start=\"0\"/>", "<Real declaredType=\"X\" start=\"0\"/>", "declaredType \"X\" is not in <TypeDefinitions>"),
            ("<Real declaredType=\"L\" start=\"0\"/>", "<Real declaredType=\"L\" unit=\"ft\" start=\"0\"/>", "unit \"ft\" is not in <UnitDefinitions>"),
            ("description=\"d\" causality=\"input\"", "description=\" \" causality=\"input\"", "has no description"),
        ];
        for (from, to, needle) in cases {
            let md = parse(&OK.replacen(from, to, 1)).unwrap();
            match check(&md) {
                Ok(()) => assert!(needle.is_empty(), "{to}: accepted, expected {needle:?}"),
                Err(e) => assert!(!needle.is_empty() && e.contains(needle), "{to}: {e}"),
            }
        }
    }

    /// Exclusive ends (the `BeltDrive` range annotation) need their bound
    /// and a start value strictly inside.
    #[test]
    fn exclusive_end_rules() {
        let with = |real: &str, range: &str| {
            let xml = OK
                .replacen("<Real declaredType=\"L\" start=\"0\"/>", real, 1)
                .replacen(
                    "  <ModelVariables>",
                    &format!(
                        "  <VendorAnnotations><Tool name=\"BeltDrive\"><ExclusiveBounds>\
                         <Range variable=\"u\" {range}/></ExclusiveBounds></Tool>\
                         </VendorAnnotations>\n  <ModelVariables>"
                    ),
                    1,
                );
            check(&parse(&xml).unwrap())
        };
        let cases = [
            (
                "<Real declaredType=\"L\" start=\"0\" min=\"0\"/>",
                "min=\"exclusive\"",
                "start = 0 is outside (0, inf]",
            ),
            (
                "<Real declaredType=\"L\" start=\"1\" min=\"0\" max=\"1\"/>",
                "max=\"exclusive\"",
                "start = 1 is outside [0, 1)",
            ),
            (
                "<Real declaredType=\"L\" start=\"0\"/>",
                "max=\"exclusive\"",
                "makes max exclusive, but no max is declared",
            ),
            (
                "<Real declaredType=\"L\" start=\"1\" min=\"1\" max=\"1\"/>",
                "min=\"exclusive\"",
                "leaves no value",
            ),
            (
                "<Real declaredType=\"L\" start=\"0.5\" min=\"0\" max=\"1\"/>",
                "min=\"exclusive\" max=\"exclusive\"",
                "",
            ),
            (
                "<Real declaredType=\"L\" start=\"0\" min=\"0\"/>",
                "min=\"inclusive\"",
                "",
            ),
        ];
        for (real, range, needle) in cases {
            match with(real, range) {
                Ok(()) => assert!(
                    needle.is_empty(),
                    "{real} {range}: accepted, expected {needle:?}"
                ),
                Err(e) => assert!(
                    !needle.is_empty() && e.contains(needle),
                    "{real} {range}: {e}"
                ),
            }
        }
    }

    #[test]
    fn structure_rules() {
        assert!(err("<Unknown index=\"4\"/></Outputs>", "</Outputs>")
            .contains("must list exactly the outputs"));
        assert!(err(
            "<Unknown index=\"3\" dependencies",
            "<Unknown index=\"9\" dependencies"
        )
        .contains("index 9 is outside 1..=4"));
        assert!(err(
            "<InitialUnknowns><Unknown index=\"3\"/>",
            "<InitialUnknowns><Unknown index=\"3\"/><Unknown index=\"4\"/>"
        )
        .contains("initial=approx/calculated"));
        assert!(err(
            "<Unknown index=\"4\"/></Outputs>",
            "<Unknown index=\"4\"/><Unknown index=\"3\"/></Outputs>"
        )
        .contains("strictly ascending"));
        assert!(err("dependencies=\"2\"", "dependencies=\"5\"").contains("dependency 5 is outside"));
        assert!(err("dependencies=\"2\"", "dependencies=\"3\"").contains("cannot depend on itself"));
        assert!(err("dependencies=\"2\"", "dependencies=\"4\"")
            .contains("\"p[2].y\", an output variable, not an input or parameter"));
        assert!(
            err("dependenciesKind=\"dependent\"", "dependenciesKind=\"\"")
                .contains("0 dependenciesKind entries for 1 dependencies")
        );
        assert!(
            err("dependenciesKind=\"dependent\"", "dependenciesKind=\"odd\"")
                .contains("unknown dependenciesKind \"odd\"")
        );
        assert!(err("dependencies=\"2\" ", "").contains("dependenciesKind without dependencies"));
    }
}
