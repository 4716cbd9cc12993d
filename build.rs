//! Build script: turns `modelDescription/modelDescription.xml` into Rust.
//!
//! * computes the GUID from the XML text (`modelDescription/guid.rs`, shared
//!   with xtask) and writes `$OUT_DIR/modelDescription.xml` with the
//!   `@GUID@` placeholder replaced;
//! * checks the description (unique names and value references, start values,
//!   declared types and units, ModelStructure) and fails the build with a
//!   message naming the line if something is wrong;
//! * writes `$OUT_DIR/variables.rs`, included by `src/variables.rs`: the
//!   variable table, `Var` (one variant per base name), `lookup`, `by_name`.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::{env, fs, process};

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

#[path = "modelDescription/guid.rs"]
mod guid;

const XML_PATH: &str = "modelDescription/modelDescription.xml";

fn main() {
    println!("cargo:rerun-if-changed={XML_PATH}");
    println!("cargo:rerun-if-changed=modelDescription/guid.rs");
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
    let xml = fs::read_to_string(manifest_dir.join(XML_PATH))
        .map_err(|e| format!("cannot read the file: {e}"))?;

    let md = parse(&xml)?;
    check(&md)?;

    let guid = guid::guid_for_xml(&xml);
    let packaged = guid::substitute_guid(&xml, &guid)
        .ok_or("the placeholder @GUID@ must occur exactly once (in the guid attribute)")?;
    write(&out_dir.join("modelDescription.xml"), &packaged)?;
    write(&out_dir.join("variables.rs"), &generate(&md, &guid)?)?;
    Ok(())
}

fn write(path: &PathBuf, text: &str) -> Result<(), String> {
    fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

// ---------------------------------------------------------------------------
// Parsing
// ---------------------------------------------------------------------------

#[derive(Default)]
struct ModelDescription {
    fmi_version: String,
    guid_attr: String,
    model_identifier: Option<String>,
    /// Unit name -> line.
    units: HashMap<String, usize>,
    /// SimpleType name -> (element type, unit).
    types: HashMap<String, (String, Option<String>)>,
    log_categories: Vec<(String, usize)>,
    variables: Vec<Variable>,
    /// (index attribute, line).
    outputs: Vec<(usize, usize)>,
    initial_unknowns: Vec<(usize, usize)>,
}

#[derive(Default)]
struct Variable {
    line: usize,
    name: String,
    vr: u32,
    description: String,
    causality: String,
    variability: String,
    initial: Option<String>,
    /// "Real", "Integer", "Boolean", "String" (or whatever element was found).
    ty: String,
    declared_type: Option<String>,
    unit: Option<String>,
    start: Option<String>,
}

/// Line (1-based) of a byte offset.
fn line_of(xml: &str, pos: u64) -> usize {
    let end = usize::try_from(pos).unwrap_or(usize::MAX).min(xml.len());
    xml.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// All attributes of an element as (name, unescaped value).
fn attributes(e: &BytesStart, line: usize) -> Result<HashMap<String, String>, String> {
    let mut map = HashMap::new();
    for a in e.attributes() {
        let a = a.map_err(|err| format!("line {line}: malformed attribute: {err}"))?;
        let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
        let value = a
            .unescape_value()
            .map_err(|err| format!("line {line}: malformed value of attribute {key}: {err}"))?
            .into_owned();
        map.insert(key, value);
    }
    Ok(map)
}

fn required(
    attrs: &HashMap<String, String>,
    key: &str,
    elem: &str,
    line: usize,
) -> Result<String, String> {
    attrs
        .get(key)
        .cloned()
        .ok_or_else(|| format!("line {line}: <{elem}> lacks the required attribute {key}"))
}

fn parse(xml: &str) -> Result<ModelDescription, String> {
    let mut reader = Reader::from_str(xml);
    reader.config_mut().trim_text(true);
    let mut md = ModelDescription::default();
    let mut stack: Vec<String> = Vec::new();
    let mut current: Option<Variable> = None;
    let mut current_type: Option<String> = None;

    loop {
        let pos = reader.buffer_position();
        let event = reader.read_event().map_err(|e| {
            format!(
                "line {}: malformed XML: {e}",
                line_of(xml, reader.error_position())
            )
        })?;
        let line = line_of(xml, pos);
        let (elem, is_empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                match stack.pop().as_deref() {
                    Some("ScalarVariable") => {
                        let v = current
                            .take()
                            .ok_or("internal: unbalanced ScalarVariable")?;
                        finish_variable(&mut md, v)?;
                    }
                    Some("SimpleType") => current_type = None,
                    _ => {}
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = String::from_utf8_lossy(elem.name().as_ref()).into_owned();
        let attrs = attributes(elem, line)?;
        let parent = stack.last().map(String::as_str);

        match (parent, name.as_str()) {
            (None, "fmiModelDescription") => {
                md.fmi_version = required(&attrs, "fmiVersion", &name, line)?;
                md.guid_attr = required(&attrs, "guid", &name, line)?;
            }
            (None, other) => {
                return Err(format!(
                    "line {line}: root element must be <fmiModelDescription>, found <{other}>"
                ))
            }
            (Some("fmiModelDescription"), "CoSimulation") => {
                md.model_identifier = Some(required(&attrs, "modelIdentifier", &name, line)?);
            }
            (Some("UnitDefinitions"), "Unit") => {
                let unit = required(&attrs, "name", &name, line)?;
                if md.units.insert(unit.clone(), line).is_some() {
                    return Err(format!("line {line}: unit \"{unit}\" is defined twice"));
                }
            }
            (Some("TypeDefinitions"), "SimpleType") => {
                let t = required(&attrs, "name", &name, line)?;
                if md.types.contains_key(&t) {
                    return Err(format!("line {line}: SimpleType \"{t}\" is defined twice"));
                }
                current_type = Some(t);
            }
            (
                Some("SimpleType"),
                ty @ ("Real" | "Integer" | "Boolean" | "String" | "Enumeration"),
            ) => {
                let t = current_type
                    .clone()
                    .ok_or("internal: type outside SimpleType")?;
                md.types
                    .insert(t, (ty.to_string(), attrs.get("unit").cloned()));
            }
            (Some("LogCategories"), "Category") => {
                md.log_categories
                    .push((required(&attrs, "name", &name, line)?, line));
            }
            (Some("ModelVariables"), "ScalarVariable") => {
                let vr_text = required(&attrs, "valueReference", &name, line)?;
                let v = Variable {
                    line,
                    name: required(&attrs, "name", &name, line)?,
                    vr: vr_text.trim().parse().map_err(|_| {
                        format!("line {line}: valueReference \"{vr_text}\" is not an unsigned 32-bit integer")
                    })?,
                    description: attrs.get("description").cloned().unwrap_or_default(),
                    causality: attrs.get("causality").cloned().unwrap_or_else(|| "local".into()),
                    variability: attrs.get("variability").cloned().unwrap_or_else(|| "continuous".into()),
                    initial: attrs.get("initial").cloned(),
                    ..Variable::default()
                };
                if is_empty {
                    return Err(format!(
                        "line {line}: ScalarVariable \"{}\" has no type element",
                        v.name
                    ));
                }
                current = Some(v);
            }
            (
                Some("ScalarVariable"),
                ty @ ("Real" | "Integer" | "Boolean" | "String" | "Enumeration"),
            ) => {
                let v = current
                    .as_mut()
                    .ok_or("internal: type outside ScalarVariable")?;
                if !v.ty.is_empty() {
                    return Err(format!(
                        "line {line}: ScalarVariable \"{}\" has more than one type element",
                        v.name
                    ));
                }
                v.ty = ty.to_string();
                v.declared_type = attrs.get("declaredType").cloned();
                v.unit = attrs.get("unit").cloned();
                v.start = attrs.get("start").cloned();
            }
            (Some("Outputs"), "Unknown") | (Some("InitialUnknowns"), "Unknown") => {
                let text = required(&attrs, "index", &name, line)?;
                let index = text.trim().parse().map_err(|_| {
                    format!("line {line}: Unknown index \"{text}\" is not a number")
                })?;
                if parent == Some("Outputs") {
                    md.outputs.push((index, line));
                } else {
                    md.initial_unknowns.push((index, line));
                }
            }
            _ => {}
        }
        if !is_empty {
            stack.push(name);
        }
    }
    if md.fmi_version.is_empty() {
        return Err("no <fmiModelDescription> element".into());
    }
    Ok(md)
}

fn finish_variable(md: &mut ModelDescription, v: Variable) -> Result<(), String> {
    if v.ty.is_empty() {
        return Err(format!(
            "line {}: ScalarVariable \"{}\" has no type element",
            v.line, v.name
        ));
    }
    md.variables.push(v);
    Ok(())
}

// ---------------------------------------------------------------------------
// Checks (FMI 2.0 section 2.2.7 and what the plumbing relies on)
// ---------------------------------------------------------------------------

/// `initial` as defined or defaulted (FMI 2.0 table in section 2.2.7);
/// `None` where the attribute is not allowed (input, independent).
fn effective_initial(v: &Variable) -> Option<&str> {
    if let Some(i) = v.initial.as_deref() {
        return Some(i);
    }
    match (v.causality.as_str(), v.variability.as_str()) {
        ("input", _) | ("independent", _) => None,
        (_, "constant") | ("parameter", _) => Some("exact"),
        _ => Some("calculated"),
    }
}

fn check(md: &ModelDescription) -> Result<(), String> {
    if md.fmi_version != "2.0" {
        return Err(format!(
            "fmiVersion must be \"2.0\", found \"{}\"",
            md.fmi_version
        ));
    }
    if md.guid_attr != guid::GUID_PLACEHOLDER {
        return Err(format!(
            "the guid attribute must be the placeholder {} (the GUID is computed at build time), found \"{}\"",
            guid::GUID_PLACEHOLDER,
            md.guid_attr
        ));
    }
    if md.model_identifier.is_none() {
        return Err("no <CoSimulation modelIdentifier=...> element".into());
    }
    let mut seen = HashSet::new();
    for (c, line) in &md.log_categories {
        if !seen.insert(c) {
            return Err(format!("line {line}: log category \"{c}\" is listed twice"));
        }
    }
    for (t, (_, unit)) in &md.types {
        if let Some(u) = unit {
            if !md.units.contains_key(u) {
                return Err(format!(
                    "SimpleType \"{t}\" uses unit \"{u}\" which is not in <UnitDefinitions>"
                ));
            }
        }
    }

    let mut names = HashMap::new();
    let mut vrs = HashMap::new();
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

    // ModelStructure: Outputs lists every output once, in index order;
    // InitialUnknowns lists the outputs with initial approx/calculated and the
    // calculated parameters (this is a Co-Simulation FMU: no states).
    let position = |list: &[(usize, usize)], what: &str| -> Result<Vec<usize>, String> {
        let mut last = 0;
        for &(i, line) in list {
            if i == 0 || i > md.variables.len() {
                return Err(format!(
                    "line {line}: {what} index {i} is outside 1..={}",
                    md.variables.len()
                ));
            }
            if i <= last {
                return Err(format!(
                    "line {line}: {what} indices must be strictly ascending ({i} after {last})"
                ));
            }
            last = i;
        }
        Ok(list.iter().map(|&(i, _)| i).collect())
    };
    let outputs = position(&md.outputs, "ModelStructure/Outputs")?;
    let expected: Vec<usize> = (1..=md.variables.len())
        .filter(|&i| md.variables[i - 1].causality == "output")
        .collect();
    if outputs != expected {
        return Err(format!(
            "ModelStructure/Outputs must list exactly the outputs by their 1-based position in ModelVariables: expected {expected:?}, found {outputs:?}"
        ));
    }
    let initial = position(&md.initial_unknowns, "ModelStructure/InitialUnknowns")?;
    let expected: Vec<usize> = (1..=md.variables.len())
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
            start_literal(&v.ty, s)?;
        }
        (None, false) => {}
    }
    // Declared type and unit: every Real uses a declaredType (project rule).
    if let Some(dt) = &v.declared_type {
        let (ty, _) = md
            .types
            .get(dt)
            .ok_or_else(|| format!("declaredType \"{dt}\" is not in <TypeDefinitions>"))?;
        if *ty != v.ty {
            return Err(format!(
                "declaredType \"{dt}\" is a {ty} type, the variable is {}",
                v.ty
            ));
        }
    } else if v.ty == "Real" {
        return Err("Real variables must use a declaredType from <TypeDefinitions>".into());
    }
    if let Some(u) = &v.unit {
        if !md.units.contains_key(u) {
            return Err(format!("unit \"{u}\" is not in <UnitDefinitions>"));
        }
    }
    Ok(())
}

/// `pulley[3].hubForce.x` -> ("PulleyHubForceX", 2); scalars get index 0.
fn variant_and_index(name: &str) -> Result<(String, usize), String> {
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

/// The Rust `Start` expression for a start attribute.
fn start_literal(ty: &str, s: &str) -> Result<String, String> {
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

// ---------------------------------------------------------------------------
// Code generation
// ---------------------------------------------------------------------------

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

fn generate(md: &ModelDescription, guid: &str) -> Result<String, String> {
    let mut o = String::new();
    let w = &mut o;
    let model_identifier = md.model_identifier.as_deref().unwrap_or_default();
    let categories: Vec<&str> = md.log_categories.iter().map(|(c, _)| c.as_str()).collect();

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
        "// @generated by build.rs from {XML_PATH}. Do not edit.\n"
    );
    let _ = writeln!(
        w,
        "/// `modelIdentifier` of the `<CoSimulation>` element (name of the binary)."
    );
    let _ = writeln!(
        w,
        "pub const MODEL_IDENTIFIER: &str = {model_identifier:?};"
    );
    let _ = writeln!(w, "/// GUID of this build's model description (hash of the XML, see `modelDescription/guid.rs`).");
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

    let _ = writeln!(w, "{}", STATIC_TYPES);

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
        let unit = v
            .unit
            .clone()
            .or_else(|| {
                v.declared_type
                    .as_ref()
                    .and_then(|t| md.types.get(t))
                    .and_then(|(_, u)| u.clone())
            })
            .unwrap_or_default();
        let _ = writeln!(
            w,
            "    VarInfo {{ vr: {}, name: {:?}, var: Var::{variant}, index: {index}, ty: VarType::{}, causality: Causality::{}, variability: Variability::{}, start: {start}, description: {:?}, unit: {unit:?} }},",
            v.vr,
            v.name,
            v.ty,
            camel(&v.causality),
            camel(&v.variability),
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
    let _ = writeln!(w, "static BY_VR: &[(u32, usize)] = &[");
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
    let _ = writeln!(w, "static BY_NAME: &[(&str, usize)] = &[");
    for (name, i) in &by_name {
        let _ = writeln!(w, "    ({name:?}, {i}),");
    }
    let _ = writeln!(w, "];\n");
    let _ = writeln!(w, "{}", LOOKUPS);
    Ok(o)
}

/// Fixed part of the generated file: the types of the table.
const STATIC_TYPES: &str = r#"/// FMI 2.0 base type of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
    String,
}

/// FMI 2.0 `causality`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

/// FMI 2.0 `variability`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

/// The `start` attribute (`None` for calculated variables).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    None,
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(&'static str),
}

/// One ScalarVariable of the model description.
#[derive(Clone, Copy, Debug)]
pub struct VarInfo {
    /// Value reference (unique across all types).
    pub vr: u32,
    /// Full name, e.g. `pulley[2].hubForce.x`.
    pub name: &'static str,
    /// Base name, e.g. `Var::PulleyHubForceX`.
    pub var: Var,
    /// 0-based array index (`pulley[2]` -> 1); 0 for scalars.
    pub index: usize,
    pub ty: VarType,
    pub causality: Causality,
    pub variability: Variability,
    pub start: Start,
    pub description: &'static str,
    /// Unit (own or from the declared type); empty if dimensionless.
    pub unit: &'static str,
}
"#;

/// Fixed part of the generated file: the look-up functions.
const LOOKUPS: &str = r#"/// The variable of type `ty` with value reference `vr` (binary search).
pub fn lookup(ty: VarType, vr: u32) -> Option<&'static VarInfo> {
    let i = BY_VR.binary_search_by_key(&vr, |&(r, _)| r).ok()?;
    let v = &VARIABLES[BY_VR[i].1];
    (v.ty == ty).then_some(v)
}

/// The variable with this exact name (binary search).
pub fn by_name(name: &str) -> Option<&'static VarInfo> {
    let i = BY_NAME.binary_search_by(|&(n, _)| n.cmp(name)).ok()?;
    Some(&VARIABLES[BY_NAME[i].1])
}
"#;
