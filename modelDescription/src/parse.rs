//! Reading `modelDescription.xml` into [`ModelDescription`] (no checks
//! beyond well-formedness and the attributes every element must have; see
//! [`crate::check`] for the rules of FMI 2.0).

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

/// What the project uses of an FMI 2.0 model description, in document order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelDescription {
    /// `fmiVersion`.
    pub fmi_version: String,
    /// `modelName`.
    pub model_name: String,
    /// The `guid` attribute as written (the `@GUID@` placeholder in the
    /// source file, see [`crate::guid`]).
    pub guid_attr: String,
    /// `description` (empty if absent).
    pub description: String,
    /// `version` (empty if absent).
    pub version: String,
    /// `license` (empty if absent).
    pub license: String,
    /// `modelIdentifier` of `<CoSimulation>`; `None` if there is no such element.
    pub model_identifier: Option<String>,
    /// Every attribute of `<CoSimulation>` (capability flags), in document order.
    pub co_simulation: Vec<(String, String)>,
    /// `<UnitDefinitions>`.
    pub units: Vec<Unit>,
    /// `<TypeDefinitions>`.
    pub types: Vec<SimpleType>,
    /// `<LogCategories>`.
    pub log_categories: Vec<LogCategory>,
    /// Every attribute of `<DefaultExperiment>`, in document order.
    pub default_experiment: Vec<(String, String)>,
    /// `<ModelVariables>`.
    pub variables: Vec<Variable>,
    /// `<ModelStructure><Outputs>`.
    pub outputs: Vec<Unknown>,
    /// `<ModelStructure><InitialUnknowns>`.
    pub initial_unknowns: Vec<Unknown>,
}

/// A `<Unit>` of `<UnitDefinitions>`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Unit {
    /// Line of the element (1-based).
    pub line: usize,
    /// `name`.
    pub name: String,
    /// `<DisplayUnit>`s as (name, factor).
    pub display_units: Vec<(String, f64)>,
}

/// A `<SimpleType>` of `<TypeDefinitions>`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimpleType {
    /// Line of the element (1-based).
    pub line: usize,
    /// `name`.
    pub name: String,
    /// Element inside it: `Real`, `Integer`, `Boolean`, `String`, `Enumeration`.
    pub ty: String,
    /// `quantity`.
    pub quantity: Option<String>,
    /// `unit`.
    pub unit: Option<String>,
    /// `displayUnit`.
    pub display_unit: Option<String>,
}

/// A `<Category>` of `<LogCategories>`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LogCategory {
    /// Line of the element (1-based).
    pub line: usize,
    /// `name`.
    pub name: String,
    /// `description` (empty if absent).
    pub description: String,
}

/// A `<ScalarVariable>` with its type element.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Variable {
    /// Line of the element (1-based).
    pub line: usize,
    /// `name`.
    pub name: String,
    /// `valueReference`.
    pub vr: u32,
    /// `description` (empty if absent).
    pub description: String,
    /// As written, or the default `local`.
    pub causality: String,
    /// As written, or the default `continuous`.
    pub variability: String,
    /// `initial`, if written.
    pub initial: Option<String>,
    /// `Real`, `Integer`, `Boolean`, `String` (or whatever element was found).
    pub ty: String,
    /// `declaredType`.
    pub declared_type: Option<String>,
    /// The variable's own `unit` attribute (see [`ModelDescription::unit_of`]).
    pub unit: Option<String>,
    /// `start`, as written.
    pub start: Option<String>,
    /// `min`, as written.
    pub min: Option<String>,
    /// `max`, as written.
    pub max: Option<String>,
    /// The range excludes `min` (FMI's `min` is inclusive; see
    /// [`RANGE_TOOL`]).
    pub min_exclusive: bool,
    /// The range excludes `max`.
    pub max_exclusive: bool,
}

/// The `name` of the `<Tool>` in `<VendorAnnotations>` that says which ends
/// of declared ranges are exclusive, e.g. `pulley[1].radius` must be > 0:
///
/// ```xml
/// <VendorAnnotations>
///   <Tool name="BeltDrive">
///     <ExclusiveBounds>
///       <Range variable="pulley[1].radius" min="exclusive"/>
///     </ExclusiveBounds>
///   </Tool>
/// </VendorAnnotations>
/// ```
///
/// FMI 2.0 has no exclusive bounds; importers read `min`/`max` (inclusive)
/// and ignore the annotation, the model refuses a value on the excluded end.
/// (A ScalarVariable's own `<Annotations>` would be the natural place, but
/// rust-fmi's reader refuses them.)
pub const RANGE_TOOL: &str = "BeltDrive";

/// An `<Unknown>` of the model structure.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Unknown {
    /// Line of the element (1-based).
    pub line: usize,
    /// 1-based position of the variable in `<ModelVariables>`.
    pub index: usize,
    /// `dependencies` (1-based positions); `None` if the attribute is absent
    /// (the unknown may depend on every known).
    pub dependencies: Option<Vec<usize>>,
    /// `dependenciesKind`, one per dependency; `None` if absent.
    pub dependencies_kind: Option<Vec<String>>,
}

impl ModelDescription {
    /// The unit of `v`: its own, else that of its declared type.
    pub fn unit_of<'a>(&'a self, v: &'a Variable) -> Option<&'a str> {
        v.unit.as_deref().or_else(|| {
            let t = self.simple_type(v.declared_type.as_deref()?)?;
            t.unit.as_deref()
        })
    }

    /// The `<SimpleType>` called `name`.
    pub fn simple_type(&self, name: &str) -> Option<&SimpleType> {
        self.types.iter().find(|t| t.name == name)
    }

    /// The `<Unit>` called `name`.
    pub fn unit(&self, name: &str) -> Option<&Unit> {
        self.units.iter().find(|u| u.name == name)
    }

    /// The variable called `name`.
    pub fn variable(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }
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

/// Line numbers of increasing byte offsets, counted incrementally.
struct Lines<'a> {
    xml: &'a str,
    pos: usize,
    line: usize,
}

impl Lines<'_> {
    /// Line of `pos` (not before the previous call's).
    fn at(&mut self, pos: usize) -> usize {
        let pos = pos.clamp(self.pos, self.xml.len());
        self.line += self.xml.as_bytes()[self.pos..pos]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = pos;
        self.line
    }
}

/// The attributes of one element, with the line for messages.
struct Attrs {
    line: usize,
    elem: String,
    list: Vec<(String, String)>,
}

impl Attrs {
    fn read(e: &BytesStart, elem: &str, line: usize) -> Result<Attrs, String> {
        let mut list = Vec::new();
        for a in e.attributes() {
            let a = a.map_err(|err| format!("line {line}: malformed attribute: {err}"))?;
            let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
            let value = a
                .unescape_value()
                .map_err(|err| format!("line {line}: malformed value of attribute {key}: {err}"))?
                .into_owned();
            list.push((key, value));
        }
        Ok(Attrs {
            line,
            elem: elem.to_string(),
            list,
        })
    }

    fn get(&self, key: &str) -> Option<String> {
        self.list
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
    }

    fn required(&self, key: &str) -> Result<String, String> {
        self.get(key).ok_or_else(|| {
            format!(
                "line {}: <{}> lacks the required attribute {key}",
                self.line, self.elem
            )
        })
    }

    fn number<T: std::str::FromStr>(&self, key: &str, what: &str) -> Result<T, String> {
        let text = self.required(key)?;
        text.trim()
            .parse()
            .map_err(|_| format!("line {}: {key} \"{text}\" is not {what}", self.line))
    }
}

const TYPE_ELEMENTS: [&str; 5] = ["Real", "Integer", "Boolean", "String", "Enumeration"];

/// Parse a model description. Errors name the line.
pub fn parse(xml: &str) -> Result<ModelDescription, String> {
    let mut reader = Reader::from_str(xml);
    reader.config_mut().trim_text(true);
    let mut md = ModelDescription::default();
    let mut stack: Vec<String> = Vec::new();
    let mut current: Option<Variable> = None;
    // `name` of the `<Tool>` of `<VendorAnnotations>` being read
    let mut tool: Option<String> = None;
    // (line, variable, min exclusive, max exclusive) of the range annotation
    let mut exclusive: Vec<(usize, String, bool, bool)> = Vec::new();
    let mut root_seen = false;
    let mut lines = Lines {
        xml,
        pos: 0,
        line: 1,
    };

    loop {
        let pos = reader.buffer_position();
        let event = reader.read_event().map_err(|e| {
            format!(
                "line {}: malformed XML: {e}",
                line_of(xml, reader.error_position())
            )
        })?;
        // `pos` is where the reader stood before the event: skip the
        // whitespace that trim_text dropped to reach the element's `<`.
        let start = usize::try_from(pos).unwrap_or(usize::MAX).min(xml.len());
        let skipped = xml[start..].len() - xml[start..].trim_start().len();
        let line = lines.at(start + skipped);
        let (elem, is_empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                if stack.pop().as_deref() == Some("ScalarVariable") {
                    let v = current
                        .take()
                        .ok_or("internal: unbalanced ScalarVariable")?;
                    if v.ty.is_empty() {
                        return Err(format!(
                            "line {}: ScalarVariable \"{}\" has no type element",
                            v.line, v.name
                        ));
                    }
                    md.variables.push(v);
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = String::from_utf8_lossy(elem.name().as_ref()).into_owned();
        let a = Attrs::read(elem, &name, line)?;
        let parent = stack.last().map(String::as_str);

        match (parent, name.as_str()) {
            (None, "fmiModelDescription") => {
                root_seen = true;
                md.fmi_version = a.required("fmiVersion")?;
                md.model_name = a.required("modelName")?;
                md.guid_attr = a.required("guid")?;
                md.description = a.get("description").unwrap_or_default();
                md.version = a.get("version").unwrap_or_default();
                md.license = a.get("license").unwrap_or_default();
            }
            (None, other) => {
                return Err(format!(
                    "line {line}: root element must be <fmiModelDescription>, found <{other}>"
                ))
            }
            (Some("fmiModelDescription"), "CoSimulation") => {
                md.model_identifier = Some(a.required("modelIdentifier")?);
                md.co_simulation = a.list.clone();
            }
            (Some("fmiModelDescription"), "DefaultExperiment") => {
                md.default_experiment = a.list.clone();
            }
            (Some("UnitDefinitions"), "Unit") => md.units.push(Unit {
                line,
                name: a.required("name")?,
                display_units: Vec::new(),
            }),
            (Some("Unit"), "DisplayUnit") => {
                let factor = match a.get("factor") {
                    Some(_) => a.number("factor", "a number")?,
                    None => 1.0,
                };
                let unit = md
                    .units
                    .last_mut()
                    .ok_or("internal: DisplayUnit outside Unit")?;
                unit.display_units.push((a.required("name")?, factor));
            }
            (Some("TypeDefinitions"), "SimpleType") => md.types.push(SimpleType {
                line,
                name: a.required("name")?,
                ..SimpleType::default()
            }),
            (Some("SimpleType"), ty) if TYPE_ELEMENTS.contains(&ty) => {
                let t = md
                    .types
                    .last_mut()
                    .ok_or("internal: type outside SimpleType")?;
                t.ty = ty.to_string();
                t.quantity = a.get("quantity");
                t.unit = a.get("unit");
                t.display_unit = a.get("displayUnit");
            }
            (Some("LogCategories"), "Category") => md.log_categories.push(LogCategory {
                line,
                name: a.required("name")?,
                description: a.get("description").unwrap_or_default(),
            }),
            (Some("ModelVariables"), "ScalarVariable") => {
                let v = Variable {
                    line,
                    name: a.required("name")?,
                    vr: a.number("valueReference", "an unsigned 32-bit integer")?,
                    description: a.get("description").unwrap_or_default(),
                    causality: a.get("causality").unwrap_or_else(|| "local".into()),
                    variability: a.get("variability").unwrap_or_else(|| "continuous".into()),
                    initial: a.get("initial"),
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
            (Some("ScalarVariable"), ty) if TYPE_ELEMENTS.contains(&ty) => {
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
                v.declared_type = a.get("declaredType");
                v.unit = a.get("unit");
                v.start = a.get("start");
                v.min = a.get("min");
                v.max = a.get("max");
            }
            (Some("VendorAnnotations"), "Tool") => tool = a.get("name"),
            (Some("ExclusiveBounds"), "Range") if tool.as_deref() == Some(RANGE_TOOL) => {
                let end = |key: &str| -> Result<bool, String> {
                    match a.get(key).as_deref() {
                        None | Some("inclusive") => Ok(false),
                        Some("exclusive") => Ok(true),
                        Some(other) => Err(format!(
                            "line {line}: <Range {key}=\"{other}\">: use \"exclusive\" or \"inclusive\""
                        )),
                    }
                };
                exclusive.push((line, a.required("variable")?, end("min")?, end("max")?));
            }
            (Some(list @ ("Outputs" | "InitialUnknowns" | "Derivatives")), "Unknown") => {
                let numbers = |key: &str| -> Result<Option<Vec<usize>>, String> {
                    a.get(key)
                        .map(|text| {
                            text.split_whitespace()
                                .map(|x| {
                                    x.parse().map_err(|_| {
                                        format!("line {line}: {key} entry \"{x}\" is not a number")
                                    })
                                })
                                .collect()
                        })
                        .transpose()
                };
                let u = Unknown {
                    line,
                    index: a.number("index", "a number")?,
                    dependencies: numbers("dependencies")?,
                    dependencies_kind: a
                        .get("dependenciesKind")
                        .map(|s| s.split_whitespace().map(String::from).collect()),
                };
                match list {
                    "Outputs" => md.outputs.push(u),
                    "InitialUnknowns" => md.initial_unknowns.push(u),
                    _ => {
                        return Err(format!(
                            "line {line}: <Derivatives> has no place in a Co-Simulation FMU without states"
                        ))
                    }
                }
            }
            _ => {}
        }
        if !is_empty {
            stack.push(name);
        }
    }
    if !root_seen {
        return Err("no <fmiModelDescription> element".into());
    }
    for (line, name, lo, hi) in exclusive {
        let v = md
            .variables
            .iter_mut()
            .find(|v| v.name == name)
            .ok_or_else(|| format!("line {line}: <Range variable=\"{name}\">: no such variable"))?;
        if v.min_exclusive || v.max_exclusive {
            return Err(format!(
                "line {line}: <Range variable=\"{name}\"> is given twice"
            ));
        }
        (v.min_exclusive, v.max_exclusive) = (lo, hi);
    }
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) const SMALL: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="@GUID@" description="A &amp; B" version="1.2">
  <CoSimulation modelIdentifier="Mid" canHandleVariableCommunicationStepSize="true"/>
  <UnitDefinitions>
    <Unit name="m"><BaseUnit m="1"/><DisplayUnit name="mm" factor="1000"/></Unit>
  </UnitDefinitions>
  <TypeDefinitions>
    <SimpleType name="Length"><Real quantity="Length" unit="m"/></SimpleType>
  </TypeDefinitions>
  <LogCategories><Category name="logEvents" description="events"/></LogCategories>
  <DefaultExperiment startTime="0" stopTime="2"/>
  <ModelVariables>
    <ScalarVariable name="n" valueReference="1" description="count" causality="parameter" variability="fixed">
      <Integer start="2" min="1" max="6"/>
    </ScalarVariable>
    <ScalarVariable name="p[2].x" valueReference="7" description="position" causality="output">
      <Real declaredType="Length"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="2" dependencies="" dependenciesKind=""/></Outputs>
    <InitialUnknowns><Unknown index="2" dependencies="1" dependenciesKind="dependent"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"#;

    #[test]
    fn reads_every_part() {
        let md = parse(SMALL).unwrap();
        assert_eq!(
            (
                md.fmi_version.as_str(),
                md.model_name.as_str(),
                md.description.as_str()
            ),
            ("2.0", "M", "A & B")
        );
        assert_eq!(md.model_identifier.as_deref(), Some("Mid"));
        assert_eq!(md.co_simulation.len(), 2);
        assert_eq!(md.units[0].display_units, vec![("mm".into(), 1000.0)]);
        assert_eq!(md.types[0].unit.as_deref(), Some("m"));
        assert_eq!(md.log_categories[0].name, "logEvents");
        assert_eq!(md.default_experiment[1], ("stopTime".into(), "2".into()));
        let n = &md.variables[0];
        assert_eq!((n.vr, n.ty.as_str(), n.line), (1, "Integer", 13));
        assert_eq!((n.min.as_deref(), n.max.as_deref()), (Some("1"), Some("6")));
        let x = &md.variables[1];
        assert_eq!(
            (x.causality.as_str(), x.variability.as_str()),
            ("output", "continuous")
        );
        assert_eq!(md.unit_of(x), Some("m"));
        assert_eq!(md.outputs[0].dependencies, Some(vec![]));
        assert_eq!(md.initial_unknowns[0].dependencies, Some(vec![1]));
        assert_eq!(
            md.initial_unknowns[0].dependencies_kind,
            Some(vec!["dependent".to_string()])
        );
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse(&SMALL.replace("valueReference=\"7\"", "valueReference=\"x\"")).unwrap_err();
        assert!(e.starts_with("line 16: valueReference \"x\""), "{e}");
        let e =
            parse(&SMALL.replace("<Integer start=\"2\" min=\"1\" max=\"6\"/>", "")).unwrap_err();
        assert!(
            e.contains("line 13") && e.contains("has no type element"),
            "{e}"
        );
        let e = parse(&SMALL.replace(" modelName=\"M\"", "")).unwrap_err();
        assert!(e.contains("lacks the required attribute modelName"), "{e}");
        let e = parse("<a/>").unwrap_err();
        assert!(
            e.contains("root element must be <fmiModelDescription>"),
            "{e}"
        );
        let e = parse(&SMALL.replace("</ModelVariables>", "")).unwrap_err();
        assert!(e.contains("malformed XML"), "{e}");
        assert!(parse("").unwrap_err().contains("no <fmiModelDescription>"));
        let annotate = |ranges: &str| {
            SMALL.replace(
                "  <ModelVariables>",
                &format!(
                    "  <VendorAnnotations><Tool name=\"BeltDrive\"><ExclusiveBounds>\n{ranges}\n\
                     </ExclusiveBounds></Tool></VendorAnnotations>\n  <ModelVariables>"
                ),
            )
        };
        let e = parse(&annotate("<Range variable=\"n\" min=\"open\"/>")).unwrap_err();
        assert!(e.contains("line 13: <Range min=\"open\">"), "{e}");
        let e = parse(&annotate("<Range variable=\"m\" min=\"exclusive\"/>")).unwrap_err();
        assert!(
            e.contains("line 13: <Range variable=\"m\">: no such variable"),
            "{e}"
        );
        let twice =
            "<Range variable=\"n\" min=\"exclusive\"/><Range variable=\"n\" max=\"exclusive\"/>";
        let e = parse(&annotate(twice)).unwrap_err();
        assert!(e.contains("is given twice"), "{e}");
        let e = parse(&annotate("<Range min=\"exclusive\"/>")).unwrap_err();
        assert!(e.contains("lacks the required attribute variable"), "{e}");
    }

    #[test]
    fn reads_exclusive_ends() {
        let annotated = |tool: &str| {
            SMALL.replace(
                "  <ModelVariables>",
                &format!(
                    "  <VendorAnnotations><Tool name=\"{tool}\"><ExclusiveBounds>\
                     <Range variable=\"n\" min=\"exclusive\" max=\"inclusive\"/>\
                     </ExclusiveBounds></Tool></VendorAnnotations>\n  <ModelVariables>"
                ),
            )
        };
        let md = parse(&annotated("BeltDrive")).unwrap();
        let n = &md.variables[0];
        assert!(n.min_exclusive && !n.max_exclusive);
        assert!(!md.variables[1].min_exclusive);
        // another tool's annotation is not ours
        let md = parse(&annotated("SomeTool")).unwrap();
        assert!(!md.variables[0].min_exclusive);
        assert!(!parse(SMALL).unwrap().variables[0].min_exclusive);
    }
}
