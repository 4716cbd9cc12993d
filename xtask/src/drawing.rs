//! `cargo xtask layout`: the drawing of the mounted drive. The SVG comes from
//! the physics core's own layout (`examples/layout.rs`,
//! `belt_drive::drawing`); the PNG beside it is that SVG rendered by resvg.

use crate::{cargo, root, run, Result};
use std::fs;
use std::path::{Path, PathBuf};

/// Pixels per SVG unit of the PNG (the SVG is about 1,000 units wide).
const PNG_SCALE: f32 = 1.5;

/// `cargo xtask layout -- [--ssv FILE] [--set NAME=VALUE ...] [--names A,B,...]
/// [--title TEXT] [--out FILE.svg]`: writes the SVG (default
/// `dist/layout.svg`) and the PNG beside it; returns the PNG's path.
pub fn layout(args: &[String]) -> Result<PathBuf> {
    let args = args.strip_prefix(&["--".to_string()]).unwrap_or(args);
    run(
        cargo()
            .args([
                "run",
                "--profile",
                "ci",
                "--features",
                "modes",
                "--example",
                "layout",
                "--",
            ])
            .args(args),
        "drive drawing (SVG)",
    )?;
    let svg = args
        .iter()
        .position(|a| a == "--out")
        .and_then(|i| args.get(i + 1))
        .map_or_else(|| PathBuf::from("dist/layout.svg"), PathBuf::from);
    let svg = if svg.is_absolute() {
        svg
    } else {
        root().join(svg)
    };
    let png = svg.with_extension("png");
    write_png(&svg, &png)?;
    println!("{}", png.display());
    Ok(png)
}

/// Renders the SVG file `svg` into the PNG file `png`.
pub fn write_png(svg: &Path, png: &Path) -> Result<()> {
    let text = fs::read_to_string(svg).map_err(|e| format!("{}: {e}", svg.display()))?;
    let bytes = png_of(&text)?;
    fs::write(png, bytes).map_err(|e| format!("{}: {e}", png.display()))
}

/// The PNG of an SVG document, text in the system's fonts.
pub fn png_of(svg: &str) -> Result<Vec<u8>> {
    use resvg::{tiny_skia, usvg};
    let mut opt = usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    if opt.fontdb.is_empty() {
        eprintln!("xtask: no system fonts found: the PNG has no labels (the SVG has them)");
    }
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| format!("SVG: {e}"))?;
    let size = tree
        .size()
        .to_int_size()
        .scale_by(PNG_SCALE)
        .ok_or("SVG: empty size")?;
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| format!("cannot allocate a {}x{} image", size.width(), size.height()))?;
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(PNG_SCALE, PNG_SCALE),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| format!("PNG: {e}"))
}
