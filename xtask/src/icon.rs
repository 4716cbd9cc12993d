//! The model icon `model.png` in the FMU root (FMI 2.0 section 2.3): a
//! schematic of the paper's drive, two pulleys and the belt wrapped around
//! them, drawn from geometry here so every build yields the same bytes.
//!
//! The picture is rasterised with 4x4 supersampling per pixel and written as
//! an 8-bit RGBA PNG by the `png` crate.

use std::f64::consts::PI;

/// Edge length of the square icon in pixels.
pub const SIZE: u32 = 256;

const SUBSAMPLES: u32 = 4;

/// A circle of the schematic in pixel coordinates (y down).
#[derive(Clone, Copy)]
struct Circle {
    cx: f64,
    cy: f64,
    r: f64,
}

/// The drawing: a larger driving pulley on the left, a smaller driven one
/// on the right, the belt wrapped around both (open belt).
struct Schematic {
    pulleys: [Circle; 2],
    /// Belt thickness; the belt lies on the rims, r .. r + thickness.
    thickness: f64,
    /// Unit normal of the upper tangent (local frame: x from pulley 1 to 2).
    normal: (f64, f64),
}

const BELT: [f64; 3] = [0.13, 0.23, 0.34];
const PULLEY: [f64; 3] = [0.70, 0.74, 0.78];
const RIM: [f64; 3] = [0.36, 0.40, 0.45];
const HUB: [f64; 3] = [0.25, 0.28, 0.32];

impl Schematic {
    fn new() -> Self {
        let s = SIZE as f64;
        let pulleys = [
            Circle {
                cx: 0.30 * s,
                cy: 0.5 * s,
                r: 0.21 * s,
            },
            Circle {
                cx: 0.77 * s,
                cy: 0.5 * s,
                r: 0.12 * s,
            },
        ];
        let thickness = 0.045 * s;
        // Upper common tangent of the belt's centre circles (radius r + t/2):
        // n = (sin b, cos b) with sin b = (R1 - R2) / d, the tangent touching
        // circle 1 at c1 + R1 n and circle 2 at c2 + R2 n.
        let d = pulleys[1].cx - pulleys[0].cx;
        let sin_b = (pulleys[0].r - pulleys[1].r) / d;
        let normal = (sin_b, (1.0 - sin_b * sin_b).sqrt());
        Schematic {
            pulleys,
            thickness,
            normal,
        }
    }

    /// Colour and coverage (0 or 1) of the sample at (x, y), pixels, y down.
    fn sample(&self, x: f64, y: f64) -> Option<[f64; 3]> {
        let t = self.thickness;
        let (nx, ny) = self.normal;
        let [p1, p2] = self.pulleys;
        // Local frame: origin at pulley 1, x towards pulley 2, y upwards
        // (mirror-symmetric about the axis, so use |y|).
        let lx = x - p1.cx;
        let ly = (p1.cy - y).abs();
        // Belt: the two tangent segments and the wrapped arcs between them.
        let (r1, r2) = (p1.r + 0.5 * t, p2.r + 0.5 * t);
        let a = (r1 * nx, r1 * ny);
        let b = (p2.cx - p1.cx + r2 * nx, r2 * ny);
        let on_segment = distance_to_segment((lx, ly), a, b) <= 0.5 * t;
        // Arc on pulley 1: outward directions beyond the tangent normal
        // (the far side); on pulley 2: directions before it.
        let dir1 = ly.atan2(lx);
        let theta_n = ny.atan2(nx);
        let ring1 = ((lx.hypot(ly)) - r1).abs() <= 0.5 * t && dir1 >= theta_n;
        let dir2 = ly.atan2(lx - (p2.cx - p1.cx));
        let ring2 = ((lx - (p2.cx - p1.cx)).hypot(ly) - r2).abs() <= 0.5 * t && dir2 <= theta_n;
        if on_segment || ring1 || ring2 {
            return Some(BELT);
        }
        for p in [p1, p2] {
            let rho = (x - p.cx).hypot(y - p.cy);
            if rho > p.r {
                continue;
            }
            // Hub, five lightening holes on a pitch circle, the rim band.
            if rho <= 0.16 * p.r {
                return Some(HUB);
            }
            let pitch = 0.55 * p.r;
            for k in 0..5 {
                let a = -PI / 2.0 + 2.0 * PI * k as f64 / 5.0;
                let (hx, hy) = (p.cx + pitch * a.cos(), p.cy + pitch * a.sin());
                if (x - hx).hypot(y - hy) <= 0.17 * p.r {
                    return None;
                }
            }
            return Some(if rho >= 0.9 * p.r { RIM } else { PULLEY });
        }
        None
    }

    /// Straight (non-premultiplied) RGBA rows, supersampled.
    fn rgba(&self) -> Vec<u8> {
        let n = SUBSAMPLES;
        let mut out = Vec::with_capacity((SIZE * SIZE * 4) as usize);
        for py in 0..SIZE {
            for px in 0..SIZE {
                let mut sum = [0.0; 3];
                let mut hits = 0u32;
                for sy in 0..n {
                    for sx in 0..n {
                        let x = px as f64 + (sx as f64 + 0.5) / n as f64;
                        let y = py as f64 + (sy as f64 + 0.5) / n as f64;
                        if let Some(c) = self.sample(x, y) {
                            hits += 1;
                            for (s, c) in sum.iter_mut().zip(c) {
                                *s += c;
                            }
                        }
                    }
                }
                let alpha = hits as f64 / (n * n) as f64;
                for s in sum {
                    let c = if hits > 0 { s / hits as f64 } else { 0.0 };
                    out.push((c * 255.0).round() as u8);
                }
                out.push((alpha * 255.0).round() as u8);
            }
        }
        out
    }
}

fn distance_to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (abx, aby) = (b.0 - a.0, b.1 - a.1);
    let s = (((p.0 - a.0) * abx + (p.1 - a.1) * aby) / (abx * abx + aby * aby)).clamp(0.0, 1.0);
    (p.0 - a.0 - s * abx).hypot(p.1 - a.1 - s * aby)
}

/// PNG file of `rgba` (`width * height * 4` bytes, rows top to bottom).
fn png(width: u32, height: u32, rgba: &[u8]) -> Vec<u8> {
    assert_eq!(rgba.len(), (width * height * 4) as usize);
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::High);
    let mut writer = enc.write_header().expect("writing to memory");
    writer.write_image_data(rgba).expect("writing to memory");
    writer.finish().expect("writing to memory");
    out
}

/// The bytes of `model.png`.
pub fn model_png() -> Vec<u8> {
    png(SIZE, SIZE, &Schematic::new().rgba())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_structure_and_pixels() {
        let png = model_png();
        assert_eq!(png, model_png(), "reproducible");
        let mut reader = png::Decoder::new(std::io::Cursor::new(&png))
            .read_info()
            .expect("a valid PNG");
        let mut raw = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut raw).expect("one frame");
        assert_eq!((info.width, info.height), (SIZE, SIZE));
        assert_eq!(
            (info.color_type, info.bit_depth),
            (png::ColorType::Rgba, png::BitDepth::Eight)
        );
        let row = 4 * SIZE as usize;
        let pixel = |x: usize, y: usize| -> [u8; 4] {
            raw[y * row + 4 * x..y * row + 4 + 4 * x]
                .try_into()
                .unwrap()
        };
        let s = Schematic::new();
        let [p1, p2] = s.pulleys;
        let rgb = |c: [f64; 3]| c.map(|v| (v * 255.0).round() as u8);
        // Corner: transparent; hubs; belt on top of pulley 1 and below pulley 2.
        assert_eq!(pixel(0, 0)[3], 0);
        for p in [p1, p2] {
            assert_eq!(pixel(p.cx as usize, p.cy as usize)[..3], rgb(HUB));
            assert_eq!(pixel(p.cx as usize, p.cy as usize)[3], 255);
        }
        let belt_y = |p: Circle, sign: f64| (p.cy + sign * (p.r + 0.5 * s.thickness)) as usize;
        assert_eq!(pixel(p1.cx as usize, belt_y(p1, -1.0))[..3], rgb(BELT));
        assert_eq!(pixel(p2.cx as usize, belt_y(p2, 1.0))[..3], rgb(BELT));
        // Between the pulleys on the axis: no belt, no pulley.
        let mid = ((p1.cx + p1.r + p2.cx - p2.r) / 2.0) as usize;
        assert_eq!(pixel(mid, p1.cy as usize)[3], 0);
    }
}
