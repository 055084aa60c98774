//! Small PNG plots for reports: scatter series on log-log axes with decade ticks, optional
//! connecting lines, a marked subset (e.g. the Pareto front), a legend and labels drawn with a
//! built-in 3x5 pixel font, so plotting needs no font or graphics library.

use image::{Rgb, RgbImage};

use crate::font::glyph;

const WIDTH: u32 = 900;
const HEIGHT: u32 = 560;
const LEFT: i32 = 90;
const RIGHT: i32 = 30;
const TOP: i32 = 50;
const BOTTOM: i32 = 70;
/// Each font pixel is drawn as a SCALE x SCALE block.
const SCALE: i32 = 2;

pub const PALETTE: [[u8; 3]; 6] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
];

/// One series: points (x, y) > 0, drawn in `colour`; `marked` points get a ring.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub marked: Vec<bool>,
    pub connect: bool,
    pub colour: [u8; 3],
}

pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// Pixel width of `text` when drawn at the plot's scale.
fn text_width(text: &str) -> i32 {
    text.chars().count() as i32 * 4 * SCALE
}

fn put(img: &mut RgbImage, x: i32, y: i32, colour: [u8; 3]) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, Rgb(colour));
    }
}

/// Draw `text` at the plot's scale with its top-left corner at (x, y); vertical text reads
/// bottom to top.
fn draw_text(img: &mut RgbImage, x: i32, y: i32, text: &str, colour: [u8; 3], vertical: bool) {
    draw_text_scaled(img, x, y, text, colour, vertical, SCALE);
}

fn draw_text_scaled(
    img: &mut RgbImage,
    x: i32,
    y: i32,
    text: &str,
    colour: [u8; 3],
    vertical: bool,
    scale: i32,
) {
    for (i, c) in text.chars().enumerate() {
        let rows = glyph(c);
        for (row, bits) in rows.iter().enumerate() {
            for col in 0..3 {
                if bits & (4 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (gx, gy) = ((i as i32 * 4 + col) * scale + dx, row as i32 * scale + dy);
                        if vertical {
                            put(img, x + gy, y - gx, colour);
                        } else {
                            put(img, x + gx, y + gy, colour);
                        }
                    }
                }
            }
        }
    }
}

fn draw_line(img: &mut RgbImage, (x0, y0): (i32, i32), (x1, y1): (i32, i32), colour: [u8; 3]) {
    let steps = (x1 - x0).abs().max((y1 - y0).abs()).max(1);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let x = x0 as f64 + (x1 - x0) as f64 * t;
        let y = y0 as f64 + (y1 - y0) as f64 * t;
        put(img, x.round() as i32, y.round() as i32, colour);
    }
}

fn draw_disc(img: &mut RgbImage, cx: i32, cy: i32, r: i32, colour: [u8; 3]) {
    for dy in -r..=r {
        for dx in -r..=r {
            if dx * dx + dy * dy <= r * r {
                put(img, cx + dx, cy + dy, colour);
            }
        }
    }
}

fn draw_ring(img: &mut RgbImage, cx: i32, cy: i32, r: i32, colour: [u8; 3]) {
    for dy in -r - 1..=r + 1 {
        for dx in -r - 1..=r + 1 {
            let d2 = dx * dx + dy * dy;
            if d2 <= (r + 1) * (r + 1) && d2 >= (r - 1) * (r - 1) {
                put(img, cx + dx, cy + dy, colour);
            }
        }
    }
}

/// A short label for a tick value.
fn tick_label(v: f64) -> String {
    if (1e-3..1e5).contains(&v.abs()) {
        let s = format!("{v:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// Log-scale range covering `values`, widened to whole decades' neighbourhood.
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        return (0.0, 1.0);
    }
    let (lo, hi) = (lo.log10(), hi.log10());
    let pad = ((hi - lo) * 0.08).max(0.05);
    (lo - pad, hi + pad)
}

impl Plot {
    /// Render the plot with logarithmic x and y axes.
    pub fn render(&self) -> RgbImage {
        let mut img = RgbImage::from_pixel(WIDTH, HEIGHT, Rgb([255, 255, 255]));
        let (x0, x1) = log_range(
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.0)),
        );
        let (y0, y1) = log_range(
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.1)),
        );
        let (w, h) = (WIDTH as i32 - LEFT - RIGHT, HEIGHT as i32 - TOP - BOTTOM);
        let to_px = |x: f64, y: f64| -> (i32, i32) {
            let fx = (x.log10() - x0) / (x1 - x0);
            let fy = (y.log10() - y0) / (y1 - y0);
            (
                LEFT + (fx * w as f64).round() as i32,
                TOP + h - (fy * h as f64).round() as i32,
            )
        };
        let grey = [200, 200, 200];
        let black = [0, 0, 0];
        // Decade ticks, subdivided (2 and 5, or every digit) when the range is narrow.
        let ticks = |lo: f64, hi: f64| -> Vec<f64> {
            let mut t = Vec::new();
            let multiples: &[f64] = if hi - lo < 0.6 {
                &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
            } else if hi - lo < 1.5 {
                &[1.0, 2.0, 5.0]
            } else {
                &[1.0]
            };
            for e in (lo.floor() as i32)..=(hi.ceil() as i32) {
                for m in multiples {
                    let v = m * 10f64.powi(e);
                    if v.log10() >= lo && v.log10() <= hi {
                        t.push(v);
                    }
                }
            }
            t
        };
        for v in ticks(x0, x1) {
            let (px, _) = to_px(v, 10f64.powf(y0));
            draw_line(&mut img, (px, TOP), (px, TOP + h), grey);
            let label = tick_label(v);
            draw_text(
                &mut img,
                px - text_width(&label) / 2,
                TOP + h + 8,
                &label,
                black,
                false,
            );
        }
        for v in ticks(y0, y1) {
            let (_, py) = to_px(10f64.powf(x0), v);
            draw_line(&mut img, (LEFT, py), (LEFT + w, py), grey);
            let label = tick_label(v);
            draw_text(
                &mut img,
                LEFT - 8 - text_width(&label),
                py - 5,
                &label,
                black,
                false,
            );
        }
        draw_line(&mut img, (LEFT, TOP + h), (LEFT + w, TOP + h), black);
        draw_line(&mut img, (LEFT, TOP), (LEFT, TOP + h), black);
        draw_text(&mut img, LEFT, 14, &self.title, black, false);
        draw_text(
            &mut img,
            LEFT + w / 2 - text_width(&self.x_label) / 2,
            TOP + h + 32,
            &self.x_label,
            black,
            false,
        );
        draw_text(
            &mut img,
            14,
            TOP + h / 2 + text_width(&self.y_label) / 2,
            &self.y_label,
            black,
            true,
        );
        for (i, s) in self.series.iter().enumerate() {
            let pts: Vec<(i32, i32)> = s.points.iter().map(|&(x, y)| to_px(x, y)).collect();
            if s.connect {
                for pair in pts.windows(2) {
                    draw_line(&mut img, pair[0], pair[1], s.colour);
                }
            }
            for (k, &(px, py)) in pts.iter().enumerate() {
                draw_disc(&mut img, px, py, 3, s.colour);
                if s.marked.get(k).copied().unwrap_or(false) {
                    draw_ring(&mut img, px, py, 7, black);
                }
            }
            let ly = TOP + 8 + i as i32 * 16;
            let lx = LEFT + w - 220;
            draw_disc(&mut img, lx, ly + 4, 4, s.colour);
            draw_text(&mut img, lx + 12, ly, &s.label, black, false);
        }
        img
    }
}

/// Draw a small black label (one pixel per font pixel) with the built-in font.
pub fn label(img: &mut RgbImage, x: i32, y: i32, text: &str) {
    draw_text_scaled(img, x, y, text, [0, 0, 0], false, 1);
}

/// Which points are on the Pareto front of (cost, error), both minimised.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            !points
                .iter()
                .any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let pts = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (4.0, 2.0)];
        assert_eq!(pareto_front(&pts), vec![true, true, false, true, false]);
    }

    #[test]
    fn plots_draw_points_where_the_axes_put_them() {
        let plot = Plot {
            title: "T".into(),
            x_label: "X".into(),
            y_label: "Y".into(),
            series: vec![Series {
                label: "S".into(),
                points: vec![(1.0, 1.0), (100.0, 10.0)],
                marked: vec![true, false],
                connect: true,
                colour: PALETTE[0],
            }],
        };
        let img = plot.render();
        assert_eq!(img.dimensions(), (WIDTH, HEIGHT));
        let coloured = img.pixels().filter(|p| p.0 == PALETTE[0]).count();
        assert!(coloured > 50, "series pixels drawn: {coloured}");
        assert!(
            img.pixels().any(|p| p.0 == [0, 0, 0]),
            "axes and text drawn"
        );
    }
}
