//! SSP parameter sets (`.ssv` files, SSP 1.0 `ssv:ParameterSet`): the
//! parameters a file sets, with their type and value as written.

use quick_xml::events::Event;
use quick_xml::Reader;

/// One `<ssv:Parameter>` of a parameter set.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// The parameter's (variable's) name.
    pub name: String,
    /// `Real`, `Integer`, `Boolean`, `String` or `Enumeration` (the element
    /// inside `<ssv:Parameter>`, without its namespace prefix).
    pub ty: String,
    /// The `value` attribute as written.
    pub value: String,
}

/// Every parameter of an `.ssv` file, in document order.
pub fn read(text: &str) -> Result<Vec<Parameter>, String> {
    let mut reader = Reader::from_str(text);
    let mut out = Vec::new();
    let mut name: Option<String> = None;
    loop {
        let event = reader
            .read_event()
            .map_err(|e| format!("malformed XML at byte {}: {e}", reader.error_position()))?;
        let (Event::Start(e) | Event::Empty(e)) = event else {
            if matches!(event, Event::Eof) {
                break;
            }
            continue;
        };
        let attr = |key: &str| -> Result<Option<String>, String> {
            e.try_get_attribute(key)
                .map_err(|err| err.to_string())?
                .map(|a| a.unescape_value().map(|v| v.into_owned()))
                .transpose()
                .map_err(|err| err.to_string())
        };
        let tag = String::from_utf8_lossy(e.local_name().as_ref()).into_owned();
        match tag.as_str() {
            "Parameter" => {
                name = Some(attr("name")?.ok_or("<ssv:Parameter> without a name")?);
            }
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration" => {
                let Some(n) = name.take() else {
                    return Err(format!("<ssv:{tag}> outside an <ssv:Parameter>"));
                };
                let value = attr("value")?.ok_or_else(|| format!("{n}: no value attribute"))?;
                out.push(Parameter {
                    name: n,
                    ty: tag,
                    value,
                });
            }
            _ => {}
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_parameters() {
        let text = r#"<?xml version="1.0"?>
<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="x">
  <ssv:Parameters>
    <ssv:Parameter name="belt.preload"><ssv:Real value="500" unit="N"/></ssv:Parameter>
    <ssv:Parameter name="nPulleys"><ssv:Integer value="3"/></ssv:Parameter>
    <ssv:Parameter name="a&amp;b"><ssv:Boolean value="true"/></ssv:Parameter>
  </ssv:Parameters>
</ssv:ParameterSet>"#;
        let p = read(text).unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!(
            p[0],
            Parameter {
                name: "belt.preload".into(),
                ty: "Real".into(),
                value: "500".into()
            }
        );
        assert_eq!((p[1].ty.as_str(), p[1].value.as_str()), ("Integer", "3"));
        assert_eq!(p[2].name, "a&b");
        assert!(read("<ssv:Real value=\"1\"/>")
            .unwrap_err()
            .contains("outside"));
        assert!(
            read("<ssv:Parameter name=\"x\"><ssv:Real/></ssv:Parameter>")
                .unwrap_err()
                .contains("x: no value")
        );
        assert!(read("<a><b></a>").is_err());
    }
}
