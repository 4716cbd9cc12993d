//! `documentation/` of the FMU: `index.html`, the user manual
//! `docs/fmu-manual.md` rendered with pulldown-cmark (CommonMark with tables),
//! its `<!-- fmu:... -->` placeholders replaced by what the model description
//! holds (version and licence, a drawing of the default drive with pulley,
//! span and body numbering, the parameter, input and output tables), and the
//! images the manual shows, copied from `docs/`.
//!
//! The build fails on a placeholder it does not know, a link or image that
//! points to a file the FMU does not contain, or a comment left in the page.

use std::f64::consts::PI;
use std::path::Path;

use crate::Result;

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

/// Start value of a Real, Integer or Boolean variable as a number.
fn start_of(info: &ModelInfo, name: &str) -> Result<f64> {
    let v = info
        .variables
        .iter()
        .find(|v| v.name == name)
        .ok_or_else(|| format!("documentation: variable {name} missing"))?;
    match v.start.as_str() {
        "true" => Ok(1.0),
        "false" => Ok(0.0),
        s => s
            .parse()
            .map_err(|_| format!("documentation: start of {name} is not a number")),
    }
}

/// SVG drawing of the default drive (the start values): pulleys with their
/// numbers, the belt on the common tangents, span numbers, body 1, the axes
/// and the direction the belt runs. Pulleys are taken as inside the loop
/// (as in the default drive), listed counter-clockwise around it.
fn drive_svg(info: &ModelInfo) -> Result<String> {
    let np = start_of(info, "nPulleys")? as usize;
    let mut p = Vec::new();
    for j in 1..=np {
        p.push((
            start_of(info, &format!("pulley[{j}].x"))?,
            start_of(info, &format!("pulley[{j}].y"))?,
            start_of(info, &format!("pulley[{j}].radius"))?,
        ));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y, r) in &p {
        x0 = x0.min(x - r);
        x1 = x1.max(x + r);
        y0 = y0.min(y - r);
        y1 = y1.max(y + r);
    }
    let w = 760.0;
    let scale = ((w - 200.0) / (x1 - x0)).min(300.0 / (y1 - y0));
    let h = scale * (y1 - y0) + 190.0;
    let ox = 110.0 - scale * x0;
    let oy = 60.0 + scale * y1;
    let sx = |x: f64| ox + scale * x;
    let sy = |y: f64| oy - scale * y;
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" \
         font-family=\"sans-serif\" font-size=\"13\" role=\"img\" aria-label=\"The default drive\">\n\
         <defs><marker id=\"arr\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" \
         markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#333\"/></marker></defs>\n"
    );
    // Tangent points: the belt leaves pulley a and reaches pulley b on the
    // right of the direction a -> b (a counter-clockwise loop).
    let mut spans = Vec::new();
    for k in 0..np {
        let (a, b) = (p[k], p[(k + 1) % np]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let d = dx.hypot(dy);
        let (ux, uy) = (dx / d, dy / d);
        let (nx, ny) = (uy, -ux);
        let s = (a.2 - b.2) / d;
        let c = (1.0 - s * s).sqrt();
        let (mx, my) = (nx * c + ux * s, ny * c + uy * s);
        spans.push((
            (a.0 + a.2 * mx, a.1 + a.2 * my),
            (b.0 + b.2 * mx, b.1 + b.2 * my),
            (mx, my),
        ));
    }
    for (j, &(x, y, r)) in p.iter().enumerate() {
        svg.push_str(&format!(
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"{:.1}\" fill=\"#e8e8e8\" stroke=\"#777\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">pulley {}</text>\n",
            sx(x),
            sy(y),
            scale * r,
            sx(x),
            sy(y) + 4.0,
            j + 1
        ));
        // the belt on the wrap: from the end of the previous span to the
        // start of the next, counter-clockwise
        let (from, to) = (spans[(j + np - 1) % np].1, spans[j].0);
        let a0 = (from.1 - y).atan2(from.0 - x);
        let mut a1 = (to.1 - y).atan2(to.0 - x);
        while a1 <= a0 {
            a1 += 2.0 * PI;
        }
        let large = if a1 - a0 > PI { 1 } else { 0 };
        svg.push_str(&format!(
            "<path d=\"M{:.1},{:.1} A{:.1},{:.1} 0 {large} 0 {:.1},{:.1}\" fill=\"none\" stroke=\"#2a5599\" stroke-width=\"4\"/>\n",
            sx(from.0),
            sy(from.1),
            scale * r,
            scale * r,
            sx(to.0),
            sy(to.1)
        ));
    }
    // The belt runs clockwise when pulley 1's drive torque is negative.
    let clockwise = start_of(info, "pulley[1].torqueRamp")? < 0.0
        || start_of(info, "pulley[1].omegaRamp")? < 0.0;
    for (k, &(a, b, (mx, my))) in spans.iter().enumerate() {
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#2a5599\" stroke-width=\"4\"/>\n",
            sx(a.0),
            sy(a.1),
            sx(b.0),
            sy(b.1)
        ));
        let (cx, cy) = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
        let (lx, ly) = (sx(cx) + 28.0 * mx, sy(cy) - 28.0 * my);
        // travel arrow along the span, outside the loop
        let (tx, ty) = if clockwise {
            (a.0 - b.0, a.1 - b.1)
        } else {
            (b.0 - a.0, b.1 - a.1)
        };
        let t = tx.hypot(ty);
        let (tx, ty) = (tx / t * 50.0, -ty / t * 50.0);
        let (ax, ay) = (sx(cx) + 12.0 * mx, sy(cy) - 12.0 * my);
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#333\" marker-end=\"url(#arr)\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">span {}</text>\n",
            ax - tx / 2.0,
            ay - ty / 2.0,
            ax + tx / 2.0,
            ay + ty / 2.0,
            lx + tx.signum() * 0.0,
            ly + 5.0 + 6.0 * my.signum().abs() * if my < 0.0 { 1.0 } else { -0.3 },
            k + 1
        ));
    }
    // Body 1 starts span 1 at pulley 1.
    let b1 = spans[0].0;
    svg.push_str(&format!(
        "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"5\" fill=\"#c00\"/>\
         <text x=\"{:.1}\" y=\"{:.1}\" fill=\"#c00\">body 1</text>\n",
        sx(b1.0),
        sy(b1.1),
        sx(b1.0) - 70.0,
        sy(b1.1) + 18.0
    ));
    // Axes at pulley 1's centre, and the sign convention.
    let (ax, ay) = (30.0, h - 25.0);
    svg.push_str(&format!(
        "<line x1=\"{ax}\" y1=\"{ay}\" x2=\"{}\" y2=\"{ay}\" stroke=\"#333\" marker-end=\"url(#arr)\"/>\
         <text x=\"{}\" y=\"{}\">x</text>\
         <line x1=\"{ax}\" y1=\"{ay}\" x2=\"{ax}\" y2=\"{}\" stroke=\"#333\" marker-end=\"url(#arr)\"/>\
         <text x=\"{}\" y=\"{}\">y</text>\
         <path d=\"M{},{} A14,14 0 1 0 {},{}\" fill=\"none\" stroke=\"#333\" marker-end=\"url(#arr)\"/>\
         <text x=\"{}\" y=\"{}\">+ angle, speed, torque: counter-clockwise</text>\
         <text x=\"{}\" y=\"{}\">arrows on the spans: direction of belt travel ({})</text>\n",
        ax + 40.0,
        ax + 44.0,
        ay + 4.0,
        ay - 40.0,
        ax - 4.0,
        ay - 44.0,
        ax + 80.0,
        ay - 10.0,
        ax + 70.0,
        ay - 24.0,
        ax + 100.0,
        ay - 18.0,
        ax + 100.0,
        ay + 2.0,
        if clockwise { "clockwise" } else { "counter-clockwise" }
    ));
    svg.push_str("</svg>\n");
    Ok(svg)
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
            "<!-- fmu:drawing -->" => Some(drive_svg(&info)?),
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
