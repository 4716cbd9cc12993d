//! `documentation/index.html` of the FMU: the variables of the model
//! description as tables, followed by `docs/model.md` (equations, the
//! paper's cases, verification) rendered from a small Markdown subset.

use crate::Result;

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One `<ScalarVariable>` of the model description, as the documentation
/// shows it.
#[derive(Default)]
struct Variable {
    name: String,
    causality: String,
    description: String,
    /// `Real`, `Integer`, `Boolean` or `String`.
    ty: String,
    start: String,
    /// The variable's own unit, else that of its declared type.
    unit: String,
    declared_type: String,
}

/// What the documentation needs from the model description.
#[derive(Default)]
struct ModelInfo {
    description: String,
    /// DefaultExperiment attributes in document order.
    default_experiment: Vec<(String, String)>,
    variables: Vec<Variable>,
}

fn attrs(e: &quick_xml::events::BytesStart) -> Result<Vec<(String, String)>> {
    e.attributes()
        .map(|a| {
            let a = a.map_err(|e| format!("model description: {e}"))?;
            let value = a
                .unescape_value()
                .map_err(|e| format!("model description: {e}"))?;
            Ok((
                String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                value.into_owned(),
            ))
        })
        .collect()
}

fn get(attrs: &[(String, String)], key: &str) -> String {
    attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.clone())
        .unwrap_or_default()
}

/// Read the parts of the model description the documentation shows.
fn parse_model_description(xml: &str) -> Result<ModelInfo> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut info = ModelInfo::default();
    // SimpleType name -> unit of its type element.
    let mut type_units: Vec<(String, String)> = Vec::new();
    let mut simple_type: Option<String> = None;
    let mut current: Option<Variable> = None;
    loop {
        let event = reader
            .read_event()
            .map_err(|e| format!("model description: {e}"))?;
        let (e, empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(e) => {
                match e.name().as_ref() {
                    b"ScalarVariable" => info.variables.extend(current.take()),
                    b"SimpleType" => simple_type = None,
                    _ => {}
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let a = attrs(e)?;
        match e.name().as_ref() {
            b"fmiModelDescription" => info.description = get(&a, "description"),
            b"DefaultExperiment" => info.default_experiment = a,
            b"SimpleType" if !empty => simple_type = Some(get(&a, "name")),
            b"ScalarVariable" => {
                let v = Variable {
                    name: get(&a, "name"),
                    causality: get(&a, "causality"),
                    description: get(&a, "description"),
                    ..Variable::default()
                };
                if empty {
                    info.variables.push(v);
                } else {
                    current = Some(v);
                }
            }
            tag @ (b"Real" | b"Integer" | b"Boolean" | b"String" | b"Enumeration") => {
                if let Some(name) = &simple_type {
                    type_units.push((name.clone(), get(&a, "unit")));
                } else if let Some(v) = current.as_mut() {
                    v.ty = String::from_utf8_lossy(tag).into_owned();
                    v.start = get(&a, "start");
                    v.unit = get(&a, "unit");
                    v.declared_type = get(&a, "declaredType");
                }
            }
            _ => {}
        }
    }
    for v in &mut info.variables {
        if v.unit.is_empty() {
            v.unit = get(&type_units, &v.declared_type);
        }
    }
    Ok(info)
}

/// `code` and **bold** spans of one line of Markdown, HTML-escaped.
fn inline_markdown(text: &str) -> String {
    let mut out = String::new();
    for (i, piece) in text.split('`').enumerate() {
        if i % 2 == 1 {
            out.push_str(&format!("<code>{}</code>", escape_html(piece)));
        } else {
            for (j, part) in escape_html(piece).split("**").enumerate() {
                if j % 2 == 1 {
                    out.push_str(&format!("<b>{part}</b>"));
                } else {
                    out.push_str(part);
                }
            }
        }
    }
    out
}

/// A deliberately small Markdown subset (headings, paragraphs, bullet
/// lists, pipe tables, code fences) rendered to HTML; anything else comes
/// out as escaped paragraph text.
fn markdown_to_html(md: &str) -> String {
    #[derive(PartialEq)]
    enum Block {
        None,
        Para,
        List,
        Table,
        Code,
    }
    /// The open block, and the text of the paragraph or list item being
    /// collected (inline markup may span lines).
    struct Writer {
        out: String,
        block: Block,
        text: String,
    }
    impl Writer {
        fn flush_text(&mut self) {
            self.out.push_str(&inline_markdown(self.text.trim()));
            self.text.clear();
        }
        fn close(&mut self) {
            self.flush_text();
            self.out.push_str(match self.block {
                Block::None => "",
                Block::Para => "</p>\n",
                Block::List => "</li></ul>\n",
                Block::Table => "</table>\n",
                Block::Code => "</pre>\n",
            });
            self.block = Block::None;
        }
        fn open(&mut self, block: Block, html: &str) {
            self.close();
            self.out.push_str(html);
            self.block = block;
        }
    }
    let mut w = Writer {
        out: String::new(),
        block: Block::None,
        text: String::new(),
    };
    for line in md.lines() {
        let trimmed = line.trim();
        if w.block == Block::Code {
            if trimmed.starts_with("```") {
                w.close();
            } else {
                w.out.push_str(&escape_html(line));
                w.out.push('\n');
            }
        } else if trimmed.starts_with("```") {
            w.open(Block::Code, "<pre>");
        } else if trimmed.is_empty() {
            w.close();
        } else if let Some(level) = line
            .find(|c| c != '#')
            .filter(|&n| (1..=4).contains(&n) && line[n..].starts_with(' '))
        {
            w.close();
            // The page has its own h1/h2: Markdown levels move one down.
            let h = (level + 1).min(6);
            let title = inline_markdown(line[level..].trim());
            w.out.push_str(&format!("<h{h}>{title}</h{h}>\n"));
        } else if trimmed.starts_with('|') {
            if w.block != Block::Table {
                w.open(Block::Table, "<table>\n");
            }
            let cells: Vec<&str> = trimmed.trim_matches('|').split('|').collect();
            let separator = cells
                .iter()
                .all(|c| c.trim().chars().all(|ch| matches!(ch, '-' | ':')));
            if !separator {
                w.out.push_str("<tr>");
                for c in cells {
                    w.out
                        .push_str(&format!("<td>{}</td>", inline_markdown(c.trim())));
                }
                w.out.push_str("</tr>\n");
            }
        } else if let Some(item) = trimmed
            .strip_prefix("* ")
            .or_else(|| trimmed.strip_prefix("- "))
            .filter(|_| !line.starts_with("  ") || w.block != Block::List)
        {
            if w.block == Block::List {
                w.flush_text();
                w.out.push_str("</li>\n<li>");
            } else {
                w.open(Block::List, "<ul>\n<li>");
            }
            w.text.push_str(item);
        } else {
            if !matches!(w.block, Block::Para | Block::List) {
                w.open(Block::Para, "<p>");
            }
            w.text.push('\n');
            w.text.push_str(trimmed);
        }
    }
    w.close();
    w.out
}

/// An HTML table of the variables selected by `keep`.
fn variable_table(info: &ModelInfo, keep: impl Fn(&Variable) -> bool, with_start: bool) -> String {
    let mut html = String::from("<table>\n<tr><th>name</th><th>type</th>");
    if with_start {
        html.push_str("<th>start</th>");
    }
    html.push_str("<th>unit</th><th>description</th></tr>\n");
    for v in info.variables.iter().filter(|v| keep(v)) {
        html.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td>",
            escape_html(&v.name),
            escape_html(&v.ty)
        ));
        if with_start {
            html.push_str(&format!("<td>{}</td>", escape_html(&v.start)));
        }
        html.push_str(&format!(
            "<td>{}</td><td>{}</td></tr>\n",
            escape_html(&v.unit),
            escape_html(&v.description)
        ));
    }
    html.push_str("</table>\n");
    html
}

/// `documentation/index.html`: parameters, inputs and outputs from the model
/// description, then docs/model.md (equations, verification, the paper's
/// cases) if present.
pub fn index_html(xml: &str, model_md: Option<&str>) -> Result<String> {
    let info = parse_model_description(xml)?;
    let experiment = info
        .default_experiment
        .iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ");
    let parameters = variable_table(&info, |v| v.causality == "parameter", true);
    let inputs = variable_table(&info, |v| v.causality == "input", true);
    let outputs = variable_table(&info, |v| v.causality == "output", false);
    let model_md = model_md
        .map(markdown_to_html)
        .unwrap_or_else(|| "<p>(docs/model.md was not present at packaging time.)</p>".into());
    Ok(format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>BeltDrive</title>\n\
         <style>body{{font-family:sans-serif;max-width:75em;margin:auto;padding:0 1em}}\
         td,th{{border:1px solid #ccc;padding:2px 6px;vertical-align:top}}\
         table{{border-collapse:collapse;margin:0.5em 0}}pre{{white-space:pre-wrap}}</style></head><body>\n\
         <h1>BeltDrive</h1>\n<p>{}</p>\n\
         <p>FMI 2.0 Co-Simulation. The default start values are the paper's section-4 5PK drive, so an importer \
         that sets nothing simulates it. Default experiment: {}.</p>\n\
         <h2>Parameters</h2>\n{parameters}<h2>Inputs</h2>\n{inputs}<h2>Outputs</h2>\n{outputs}\
         <h2>Model notes (docs/model.md)</h2>\n{model_md}</body></html>\n",
        escape_html(&info.description),
        escape_html(&experiment),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{x}" description="A &amp; B">
  <TypeDefinitions>
    <SimpleType name="Force"><Real quantity="Force" unit="N"/></SimpleType>
  </TypeDefinitions>
  <DefaultExperiment startTime="0" stopTime="2"/>
  <ModelVariables>
    <ScalarVariable name="p" valueReference="1" description="a &lt;force&gt;" causality="parameter" variability="fixed">
      <Real declaredType="Force" start="550"/>
    </ScalarVariable>
    <ScalarVariable name="n" valueReference="2" description="count" causality="parameter" variability="fixed">
      <Integer start="150"/>
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
        let v: Vec<_> = info
            .variables
            .iter()
            .map(|v| {
                (
                    v.name.as_str(),
                    v.ty.as_str(),
                    v.start.as_str(),
                    v.unit.as_str(),
                )
            })
            .collect();
        assert_eq!(
            v,
            [
                ("p", "Real", "550", "N"),
                ("n", "Integer", "150", ""),
                ("y", "Real", "", "m")
            ]
        );
        let html = index_html(XML, None).unwrap();
        assert!(html.contains("a &lt;force&gt;"));
        assert!(html.contains("startTime = 0, stopTime = 2"));
    }

    #[test]
    fn markdown_subset() {
        let md = "# Title\n\nText with **bold\nacross** lines and `a<b`.\n\n\
                  | a | b |\n|---|:-:|\n| 1 | 2 |\n\n* one\n  more\n* two\n\n```\nx < y\n```\n";
        let html = markdown_to_html(md);
        assert!(html.contains("<h2>Title</h2>"));
        assert!(html.contains("<b>bold\nacross</b>"));
        assert!(html.contains("<code>a&lt;b</code>"));
        assert!(html.contains("<tr><td>1</td><td>2</td></tr>"));
        assert!(!html.contains("---"));
        assert!(html.contains("<li>one\nmore</li>\n<li>two</li></ul>"));
        assert!(html.contains("<pre>x &lt; y\n</pre>"));
    }
}
