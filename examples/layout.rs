//! A drawing of the mounted drive (`cargo xtask layout -- ...`,
//! docs/layout.md): pulleys with names and radii, the belt path, running
//! direction, span numbers with free lengths, wrap angles, tight and slack
//! spans at the loads given and the tensioner arms, as an SVG
//! (`belt_drive::drawing`); `cargo xtask layout` renders the PNG beside it.
//!
//! ```text
//! cargo run --features modes --example layout -- [--ssv FILE] [--set NAME=VALUE ...]
//!     [--names NAME1,NAME2,...] [--title TEXT] [--out FILE.svg]
//! ```
//!
//! Prints one line per span and per wrap (the numbers drawn).

use belt_drive::drawing;
use belt_drive::fmu::names::render_error;
use belt_drive::modes::params;
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: layout [--ssv FILE] [--set NAME=VALUE ...] \
                     [--names NAME1,NAME2,...] [--title TEXT] [--out FILE.svg]";

struct Args {
    ssv: Option<PathBuf>,
    sets: Vec<String>,
    names: Vec<String>,
    title: Option<String>,
    out: PathBuf,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        ssv: None,
        sets: Vec::new(),
        names: Vec::new(),
        title: None,
        out: PathBuf::from("dist/layout.svg"),
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let mut val = || {
            it.next()
                .ok_or_else(|| format!("{k} needs a value; {USAGE}"))
        };
        match k.as_str() {
            "--ssv" => a.ssv = Some(PathBuf::from(val()?)),
            "--set" => a.sets.push(val()?),
            "--names" => a.names = val()?.split(',').map(str::to_string).collect(),
            "--title" => a.title = Some(val()?),
            "--out" => a.out = PathBuf::from(val()?),
            "-h" | "--help" => return Err(USAGE.into()),
            _ => return Err(format!("unknown argument {k}; {USAGE}")),
        }
    }
    Ok(a)
}

fn run() -> Result<(), String> {
    let a = parse()?;
    let p = params::drive_params(a.ssv.as_deref(), &a.sets)?;
    let title = a.title.unwrap_or_else(|| {
        a.ssv.as_ref().map_or_else(
            || "BeltDrive default drive".to_string(),
            |s| {
                s.file_stem()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
            },
        )
    });
    let d = drawing::draw(&p, &a.names, &title).map_err(|e| render_error(&e))?;
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(&a.out, &d.svg).map_err(|e| format!("{}: {e}", a.out.display()))?;
    println!("belt path {:.2} mm", d.path_length * 1e3);
    for s in &d.spans {
        println!(
            "span {}: free length {:.2} mm, tension {:.1} N ({})",
            s.number,
            s.length * 1e3,
            s.tension,
            s.side.word()
        );
    }
    for w in &d.wraps {
        println!(
            "pulley {}: wrap {:.2} deg",
            w.pulley + 1,
            w.angle.to_degrees()
        );
    }
    println!("{}", a.out.display());
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("layout: {e}");
            ExitCode::FAILURE
        }
    }
}
