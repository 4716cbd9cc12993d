//! The warnings every parameter set of parameters/ gets at initialisation
//! (`Drive::warnings`, as the FMU logs them), and those of the built-in
//! paper drives: `cargo run --profile ci --example mesh_warnings -- [FILE.ssv ...]`.

#[path = "common/ssv.rs"]
mod ssv;

use belt_drive::fmu::names::render;
use belt_drive::{Drive, DriveParams};

fn show(name: &str, p: &DriveParams) {
    match Drive::mounted(p, 0.0) {
        Ok(d) => {
            println!("{name}: {} warning(s)", d.warnings().len());
            for w in d.warnings() {
                println!("  {}", render(w));
            }
        }
        Err(e) => println!("{name}: refused: {e:?}"),
    }
}

fn main() {
    let mut files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("parameters");
        let mut all: Vec<String> = std::fs::read_dir(dir)
            .expect("parameters/")
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|f| f.ends_with(".ssv"))
            .collect();
        all.sort();
        files = all;
        show("DriveParams::default()", &DriveParams::default());
        show("kubas_section3()", &DriveParams::kubas_section3());
        show("kubas_section4()", &DriveParams::kubas_section4());
    }
    for f in &files {
        show(f, &ssv::from_ssv(f));
    }
}
