//! `documentation/` of the FMU: `index.html`, the user manual
//! `docs/fmu-manual.md` rendered with pulldown-cmark (CommonMark with tables),
//! its `<!-- fmu:... -->` placeholders replaced by what the model description
//! holds (version and licence, the parameter, input and output tables), the
//! drawing of the default drive (`docs/layout/default-drive.svg`, made by
//! `cargo xtask layout`, with pulley, span and body numbering), and the
//! images the manual shows, copied from `docs/`.
//!
//! The build fails on a placeholder it does not know, a link or image that
//! points to a file the FMU does not contain, or a comment left in the page.

use std::path::Path;

use crate::Result;

/// The drawing of the default drive, relative to `docs/`.
const DEFAULT_DRAWING: &str = "layout/default-drive.svg";

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One `<ScalarVariable>` of the model description, as the documentation
/// shows it.
#[derive(Clone, Default)]
struct Variable {
    name: String,
    causality: String,
    description: String,
    /// `Real`, `Integer`, `Boolean` or `String`.
    ty: String,
    start: String,
    /// The variable's own unit, else that of its declared type.
    unit: String,
    /// The variable's declared `min` and `max` (empty: none declared).
    min: String,
    max: String,
    /// The model description's range annotation excludes `min` / `max`.
    min_exclusive: bool,
    max_exclusive: bool,
}

/// What the documentation needs from the model description.
#[derive(Default)]
struct ModelInfo {
    /// The model's description (the pages do not show it; the reader's
    /// test checks it).
    #[cfg_attr(not(test), allow(dead_code))]
    description: String,
    version: String,
    license: String,
    fmi_version: String,
    /// DefaultExperiment attributes in document order.
    default_experiment: Vec<(String, String)>,
    variables: Vec<Variable>,
}

/// Read the parts of the model description the documentation shows (with
/// the project's one reader, `model_description::parse`).
fn parse_model_description(xml: &str) -> Result<ModelInfo> {
    let md = model_description::parse(xml).map_err(|e| format!("model description: {e}"))?;
    let variables = md
        .variables
        .iter()
        .map(|v| Variable {
            name: v.name.clone(),
            causality: v.causality.clone(),
            description: v.description.clone(),
            ty: v.ty.clone(),
            start: v.start.clone().unwrap_or_default(),
            unit: md.unit_of(v).unwrap_or_default().to_owned(),
            min: v.min.clone().unwrap_or_default(),
            max: v.max.clone().unwrap_or_default(),
            min_exclusive: v.min_exclusive,
            max_exclusive: v.max_exclusive,
        })
        .collect();
    Ok(ModelInfo {
        description: md.description.clone(),
        version: md.version.clone(),
        license: md.license.clone(),
        fmi_version: md.fmi_version.clone(),
        default_experiment: md.default_experiment.clone(),
        variables,
    })
}

/// An HTML table of the variables selected by `keep`.
fn variable_table(info: &ModelInfo, keep: impl Fn(&Variable) -> bool, with_start: bool) -> String {
    let mut html = String::from("<table>\n<tr><th>name</th><th>type</th>");
    if with_start {
        html.push_str("<th>start</th>");
    }
    html.push_str("<th>unit</th><th>range</th><th>description</th></tr>\n");
    for v in info.variables.iter().filter(|v| keep(v)) {
        html.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td>",
            escape_html(&v.name),
            escape_html(&v.ty)
        ));
        if with_start {
            html.push_str(&format!("<td>{}</td>", escape_html(&v.start)));
        }
        let unit = if v.unit.is_empty() && v.ty == "Real" {
            "see description".to_string()
        } else {
            v.unit.clone()
        };
        html.push_str(&format!(
            "<td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape_html(&unit),
            escape_html(&range(v)),
            escape_html(&v.description)
        ));
    }
    html.push_str("</table>\n");
    html
}

/// The declared range as the tables show it: `min … max`, `≥ min`, `≤ max`,
/// with `>` / `<` for an end the range annotation excludes (`> 0`,
/// `> 0, < 1`), or a dash when the model description declares none.
fn range(v: &Variable) -> String {
    let lower = if v.min_exclusive { ">" } else { "≥" };
    let upper = if v.max_exclusive { "<" } else { "≤" };
    match (v.min.as_str(), v.max.as_str()) {
        ("", "") => "–".into(),
        (min, "") => format!("{lower} {min}"),
        ("", max) => format!("{upper} {max}"),
        (min, max) if !(v.min_exclusive || v.max_exclusive) => format!("{min} … {max}"),
        (min, max) => format!("{lower} {min}, {upper} {max}"),
    }
}

/// Relative targets of the links and images of rendered HTML.
fn relative_targets(html: &str) -> Vec<String> {
    let mut out = Vec::new();
    for attr in ["href=\"", "src=\""] {
        let mut rest = html;
        while let Some(i) = rest.find(attr) {
            rest = &rest[i + attr.len()..];
            let end = rest.find('"').unwrap_or(rest.len());
            let target = &rest[..end];
            if !(target.starts_with("http://")
                || target.starts_with("https://")
                || target.starts_with('#'))
            {
                out.push(target.to_string());
            }
        }
    }
    out
}

/// Markdown (CommonMark with tables) to HTML.
fn markdown_to_html(md: &str) -> String {
    use pulldown_cmark::{Options, Parser};
    let mut html = String::new();
    pulldown_cmark::html::push_html(&mut html, Parser::new_ext(md, Options::ENABLE_TABLES));
    html
}

/// The files of `documentation/`: `index.html` (the manual with the model
/// description's data) and the images it shows, as (path in the FMU, bytes).
/// `manual` is docs/fmu-manual.md; images are read relative to `docs`.
pub fn documentation(xml: &str, manual: &str, docs: &Path) -> Result<Vec<(String, Vec<u8>)>> {
    let info = parse_model_description(xml)?;
    let experiment = info
        .default_experiment
        .iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ");
    let about = format!(
        "<table>\n<tr><th>version</th><td>{}</td></tr>\n<tr><th>licence</th><td>{}</td></tr>\n\
         <tr><th>standard</th><td>FMI {} Co-Simulation, binaries for linux64</td></tr>\n\
         <tr><th>default experiment</th><td>{}</td></tr>\n</table>\n",
        escape_html(&info.version),
        escape_html(&info.license),
        escape_html(&info.fmi_version),
        escape_html(&experiment)
    );
    let mut md = String::new();
    for line in manual.lines() {
        let t = line.trim();
        let block = match t {
            "<!-- fmu:about -->" => Some(about.clone()),
            // The drawing of the default drive, `cargo xtask layout` on the
            // physics core's layout (docs/layout.md; tests/drawing.rs checks
            // it is current).
            "<!-- fmu:drawing -->" => Some(
                std::fs::read_to_string(docs.join(DEFAULT_DRAWING))
                    .map_err(|e| format!("docs/{DEFAULT_DRAWING}: {e}"))?,
            ),
            "<!-- fmu:parameters -->" => {
                Some(variable_table(&info, |v| v.causality == "parameter", true))
            }
            "<!-- fmu:inputs -->" => Some(variable_table(&info, |v| v.causality == "input", true)),
            // outputs and the values the FMU calculates at initialization
            // (calculated parameters, e.g. a tensioner spring's free angle)
            "<!-- fmu:outputs -->" => Some(variable_table(
                &info,
                |v| v.causality == "output" || v.causality == "calculatedParameter",
                false,
            )),
            _ if t.starts_with("<!-- fmu:") => {
                return Err(format!("docs/fmu-manual.md: unknown placeholder {t}"))
            }
            _ => None,
        };
        match block {
            // An HTML block ends at a blank line: keep the generated one whole.
            Some(b) => md.push_str(&b.replace("\n\n", "\n")),
            None => md.push_str(line),
        }
        md.push('\n');
    }
    // Comments in the manual's source are notes for its editors.
    while let Some(i) = md.find("<!--") {
        let end = md[i..]
            .find("-->")
            .ok_or("docs/fmu-manual.md: unterminated comment")?;
        md.replace_range(i..i + end + 3, "");
    }
    let body = markdown_to_html(&md);
    let mut files = Vec::new();
    for target in relative_targets(&body) {
        let path = docs.join(&target);
        let bytes = std::fs::read(&path).map_err(|e| {
            format!(
                "docs/fmu-manual.md links to {target}, which the FMU cannot contain ({}: {e})",
                path.display()
            )
        })?;
        if !files.iter().any(|(n, _): &(String, Vec<u8>)| *n == target) {
            files.push((target, bytes));
        }
    }
    let html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>BeltDrive</title>\n<style>\n\
         body{{font-family:system-ui,sans-serif;max-width:60em;margin:auto;padding:0 1em 3em;line-height:1.45;color:#222}}\n\
         td,th{{border:1px solid #ccc;padding:2px 6px;vertical-align:top;text-align:left}}\n\
         table{{border-collapse:collapse;margin:0.5em 0;font-size:0.92em}}\n\
         pre{{background:#f5f5f5;padding:0.6em;overflow-x:auto}}code{{font-size:0.92em}}\n\
         img{{max-width:100%}}h1{{margin-top:0.6em}}\n</style></head><body>\n{body}</body></html>\n"
    );
    if html.contains("<!--") {
        return Err("documentation/index.html would contain a comment".into());
    }
    files.insert(0, ("index.html".into(), html.into_bytes()));
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{x}" description="A &amp; B" version="1.2" license="MIT">
  <TypeDefinitions>
    <SimpleType name="Force"><Real quantity="Force" unit="N"/></SimpleType>
  </TypeDefinitions>
  <DefaultExperiment startTime="0" stopTime="2"/>
  <ModelVariables>
    <ScalarVariable name="p" valueReference="1" description="a &lt;force&gt;" causality="parameter" variability="fixed">
      <Real declaredType="Force" start="550"/>
    </ScalarVariable>
    <ScalarVariable name="n" valueReference="2" description="count" causality="parameter" variability="fixed">
      <Integer start="150" min="3" max="2000"/>
    </ScalarVariable>
    <ScalarVariable name="m" valueReference="4" description="mass" causality="parameter" variability="fixed">
      <Real declaredType="Force" start="1" min="0"/>
    </ScalarVariable>
    <ScalarVariable name="y" valueReference="3" description="out" causality="output">
      <Real unit="m"/>
    </ScalarVariable>
  </ModelVariables>
</fmiModelDescription>"#;

    #[test]
    fn variables_with_units_resolved_through_declared_types() {
        let info = parse_model_description(XML).unwrap();
        assert_eq!(info.description, "A & B");
        assert_eq!(
            (info.version.as_str(), info.license.as_str()),
            ("1.2", "MIT")
        );
        let v: Vec<_> = info
            .variables
            .iter()
            .map(|v| {
                (
                    v.name.as_str(),
                    v.ty.as_str(),
                    v.start.as_str(),
                    v.unit.as_str(),
                    range(v),
                )
            })
            .collect();
        assert_eq!(
            v,
            [
                ("p", "Real", "550", "N", "–".to_string()),
                ("n", "Integer", "150", "", "3 … 2000".to_string()),
                ("m", "Real", "1", "N", "≥ 0".to_string()),
                ("y", "Real", "", "m", "–".to_string())
            ]
        );
    }

    #[test]
    fn exclusive_ends_are_shown() {
        let xml = XML.replacen(
            "  <ModelVariables>",
            "  <VendorAnnotations><Tool name=\"BeltDrive\"><ExclusiveBounds>\
             <Range variable=\"m\" min=\"exclusive\"/></ExclusiveBounds></Tool></VendorAnnotations>\n  <ModelVariables>",
            1,
        );
        let info = parse_model_description(&xml).unwrap();
        let m = &info.variables[2];
        assert_eq!((m.name.as_str(), range(m).as_str()), ("m", "> 0"));
        let mut v = info.variables[2].clone();
        for (min, max, lo, hi, shown) in [
            ("0", "", true, false, "> 0"),
            ("0", "1", true, true, "> 0, < 1"),
            ("0", "3.14", false, true, "≥ 0, < 3.14"),
            ("0", "1", false, false, "0 … 1"),
            ("", "5", false, true, "< 5"),
        ] {
            (v.min, v.max) = (min.into(), max.into());
            (v.min_exclusive, v.max_exclusive) = (lo, hi);
            assert_eq!(range(&v), shown);
        }
    }

    #[test]
    fn placeholders_comments_and_links() {
        let dir = std::env::temp_dir().join(format!("beltdrive-docs-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("img")).unwrap();
        std::fs::write(dir.join("img/a.png"), b"png").unwrap();
        let manual = "# T\n\n<!-- a note -->\n\n<!-- fmu:about -->\n\n<!-- fmu:parameters -->\n\n\
                      ![a](img/a.png) [web](https://example.org) [here](#t)\n";
        let files = documentation(XML, manual, &dir).unwrap();
        let names: Vec<_> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["index.html", "img/a.png"]);
        let html = String::from_utf8(files[0].1.clone()).unwrap();
        assert!(html.contains("<h1>T</h1>"));
        assert!(html.contains("a &lt;force&gt;"));
        assert!(html.contains("<th>unit</th><th>range</th>"));
        assert!(html.contains("<td>3 … 2000</td>"));
        assert!(html.contains("<td>1.2</td>"));
        assert!(html.contains("startTime = 0, stopTime = 2"));
        assert!(!html.contains("<!--") && !html.contains("fmu:"));
        // A dead link, an unknown placeholder: refused.
        assert!(documentation(XML, "[x](missing.md)\n", &dir).is_err());
        assert!(documentation(XML, "<!-- fmu:nothing -->\n", &dir).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
