//! Project tasks: `cargo xtask <fmu|venv|run|test>`.
//!
//! * `fmu`  - release build, then `dist/BeltDrive.fmu` (model description with
//!   its GUID, the Linux binary, generated documentation).
//! * `venv` - `.venv` with the Python test harness (FMPy, pytest, ...).
//! * `run`  - the main job: build the FMU and simulate the paper's drive with
//!   it through FMPy (headline figures + `dist/default_drive.png`).
//! * `test` - everything CI runs: fmt, clippy, cargo tests, FMU, pytest.

#[path = "../../modelDescription/guid.rs"]
mod guid;

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{exit, Command};

type Result<T> = std::result::Result<T, String>;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

fn run(cmd: &mut Command, what: &str) -> Result<()> {
    eprintln!("xtask: {what}: {cmd:?}");
    let status = cmd
        .current_dir(root())
        .status()
        .map_err(|e| format!("{what}: cannot start: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{what} failed ({status})"))
    }
}

fn cargo() -> Command {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
}

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Attribute `name` of an XML start tag (the model description is ours and
/// uses double quotes throughout).
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// documentation/index.html: variables table from the model description
/// plus docs/model.md verbatim.
fn documentation(xml: &str) -> String {
    let mut rows = String::new();
    for chunk in xml.split("<ScalarVariable").skip(1) {
        let end = chunk.find("</ScalarVariable>").unwrap_or(chunk.len());
        let sv = &chunk[..end];
        let head = &sv[..sv.find('>').unwrap_or(sv.len())];
        let ty_tag = sv
            .split('<')
            .nth(1)
            .map(|s| s.trim_end_matches(['/', '>', ' ', '\n']))
            .unwrap_or("");
        let ty = ty_tag.split_whitespace().next().unwrap_or("");
        let ty_attrs = format!(" {ty_tag}");
        let unit = attr(&ty_attrs, "declaredType").unwrap_or("");
        let start = attr(&ty_attrs, "start").unwrap_or("");
        rows.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape_html(attr(head, "name").unwrap_or("")),
            escape_html(attr(head, "causality").unwrap_or("local")),
            escape_html(ty),
            escape_html(unit),
            escape_html(start),
            escape_html(attr(head, "description").unwrap_or("")),
        ));
    }
    let model_md = fs::read_to_string(root().join("docs/model.md")).unwrap_or_default();
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>BeltDrive</title>\
         <style>body{{font-family:sans-serif;max-width:70em;margin:auto}}td,th{{border:1px solid #ccc;padding:2px 6px}}\
         table{{border-collapse:collapse}}pre{{white-space:pre-wrap}}</style></head><body>\n\
         <h1>BeltDrive</h1><p>Planar discrete belt-drive model (K. Kubas 2014) as an FMI 2.0 Co-Simulation FMU. \
         Default start values simulate the paper's section-4 5PK drive; the section-3 verification drive is \
         described in the model notes below.</p>\n<h2>Variables</h2><table><tr><th>name</th><th>causality</th>\
         <th>type</th><th>declared type</th><th>start</th><th>description</th></tr>\n{rows}</table>\n\
         <h2>Model, equations and verification</h2><pre>{}</pre></body></html>\n",
        escape_html(&model_md)
    )
}

fn fmu() -> Result<PathBuf> {
    run(
        cargo().args(["build", "--release", "--lib", "-p", "belt_drive"]),
        "release build",
    )?;
    let root = root();
    let template = fs::read_to_string(root.join("modelDescription/modelDescription.xml"))
        .map_err(|e| format!("reading the model description: {e}"))?;
    let xml = guid::substitute_guid(&template, &guid::guid_for_xml(&template))
        .ok_or("modelDescription.xml must hold the @GUID@ placeholder exactly once")?;
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| root.join("target"));
    let so = fs::read(target.join("release/libbelt_drive.so"))
        .map_err(|e| format!("reading the built library: {e}"))?;
    let dist = root.join("dist");
    fs::create_dir_all(&dist).map_err(|e| e.to_string())?;
    let path = dist.join("BeltDrive.fmu");
    let file = fs::File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    let mut add = |name: &str, bytes: &[u8]| -> Result<()> {
        zip.start_file(name, opts).map_err(|e| e.to_string())?;
        zip.write_all(bytes).map_err(|e| e.to_string())
    };
    add("modelDescription.xml", xml.as_bytes())?;
    add("binaries/linux64/BeltDrive.so", &so)?;
    add("documentation/index.html", documentation(&xml).as_bytes())?;
    if let Ok(png) = fs::read(root.join("modelDescription/model.png")) {
        add("model.png", &png)?;
    }
    zip.finish().map_err(|e| e.to_string())?;
    eprintln!("xtask: wrote {}", path.display());
    Ok(path)
}

fn venv_python() -> PathBuf {
    root().join(".venv/bin/python")
}

fn venv() -> Result<()> {
    let root = root();
    let reqs = root.join("tests/python/requirements.txt");
    let text = fs::read_to_string(&reqs).map_err(|e| format!("{}: {e}", reqs.display()))?;
    let stamp = root.join(".venv/.requirements");
    if venv_python().exists() && fs::read_to_string(&stamp).ok().as_deref() == Some(&text) {
        return Ok(());
    }
    if !venv_python().exists() {
        let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
        run(
            Command::new(python).args(["-m", "venv", ".venv"]),
            "create .venv",
        )?;
    }
    run(
        Command::new(venv_python())
            .args(["-m", "pip", "install", "--quiet", "-r"])
            .arg(&reqs),
        "install the Python harness",
    )?;
    fs::write(stamp, text).map_err(|e| e.to_string())
}

fn main_job(args: &[String]) -> Result<()> {
    // `cargo xtask run -- --stop-time 0.5`: drop the separator.
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    fmu()?;
    venv()?;
    run(
        Command::new(venv_python())
            .arg("tests/python/run_default.py")
            .args(args),
        "simulate the default drive",
    )
}

fn test() -> Result<()> {
    run(
        cargo().args(["fmt", "--all", "--", "--check"]),
        "cargo fmt --check",
    )?;
    run(
        cargo().args([
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ]),
        "cargo clippy",
    )?;
    run(
        cargo().args(["test", "--workspace", "--release"]),
        "cargo test",
    )?;
    fmu()?;
    venv()?;
    run(
        Command::new(venv_python()).args(["-m", "pytest", "-q", "tests/python"]),
        "pytest (FMU through FMPy)",
    )
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("fmu") => fmu().map(|_| ()),
        Some("venv") => venv(),
        Some("run") => main_job(&args[1..]),
        Some("test") => test(),
        _ => Err("usage: cargo xtask <fmu|venv|run|test>".into()),
    };
    if let Err(e) = result {
        eprintln!("xtask: {e}");
        exit(1);
    }
}
