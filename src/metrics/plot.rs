//! The report's PNG figures: scatter plots on log-log axes (plotters, bitmap backend) and the
//! labelled image strip (panels composited with `image::imageops`). Text uses an embedded subset
//! of DejaVu Sans (assets/fonts, licence beside it) registered with plotters' ab_glyph backend,
//! so no system font or fontconfig is needed.

use std::sync::OnceLock;

use anyhow::anyhow;
use image::RgbImage;
use plotters::prelude::*;
use plotters::style::FontStyle;

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");
const FAMILY: &str = "sans-serif";
const SIZE: (u32, u32) = (900, 560);
/// Height of the label row under each panel of a strip.
const LABEL_HEIGHT: u32 = 18;

/// Series colours, in order (matplotlib's "tab10").
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// One series: points (x, y) (only positive, finite ones can be drawn on log axes); `marked`
/// points get a ring (e.g. the Pareto front).
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub marked: Vec<bool>,
    /// Join the points with a line, in order.
    pub connect: bool,
    /// Index into [`PALETTE`] (wrapping), so a method keeps its colour across plots.
    pub colour: usize,
}

impl Series {
    /// Points joined by a line, none marked.
    pub fn line(label: &str, colour: usize, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            marked: vec![false; points.len()],
            points,
            connect: true,
            colour,
        }
    }
}

pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// Register the embedded font once; later calls return the first call's outcome.
fn register_font() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FAMILY, FontStyle::Normal, FONT)
                .map_err(|_| "the embedded plot font is not a valid TrueType font".to_string())
        })
        .clone()
        .map_err(|e| anyhow!(e))
}

fn drawable(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0
}

/// A log axis range around `values` (one decade around 1 when there are none). Plotters labels
/// only from a power of ten up, so a range without one is extended down to the power below.
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo.is_finite() && hi > 0.0 {
        let (lo, hi) = (lo / 1.3, hi * 1.3);
        let power_below = 10f64.powf(lo.log10().floor());
        // Inside [lo, hi] when the next power of ten up from lo is at most hi.
        if power_below * 10.0 <= hi {
            lo..hi
        } else {
            // Just under the power, so that plotters' rounding still finds it in range.
            power_below * 0.999..hi
        }
    } else {
        0.1..10.0
    }
}

/// A tick label with three significant digits and no trailing zeros.
fn significant(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let decimals = (2 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

fn plot_error<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing a plot: {e:?}")
}

impl Plot {
    pub fn render(&self) -> anyhow::Result<RgbImage> {
        register_font()?;
        let (width, height) = SIZE;
        let mut buffer = vec![255u8; (width * height * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
            root.fill(&WHITE).map_err(plot_error)?;
            let points = || {
                self.series
                    .iter()
                    .flat_map(|s| s.points.iter().copied())
                    .filter(drawable)
            };
            let x = log_range(points().map(|p| p.0));
            let y = log_range(points().map(|p| p.1));
            let mut chart = ChartBuilder::on(&root)
                .caption(&self.title, (FAMILY, 18))
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(72)
                .build_cartesian_2d(x.log_scale(), y.log_scale())
                .map_err(plot_error)?;
            let tick = |v: &f64| significant(*v);
            chart
                .configure_mesh()
                .x_desc(self.x_label.as_str())
                .y_desc(self.y_label.as_str())
                .x_labels(10)
                .y_labels(10)
                .x_label_formatter(&tick)
                .y_label_formatter(&tick)
                .light_line_style(RGBColor(240, 240, 240))
                .bold_line_style(RGBColor(200, 200, 200))
                .label_style((FAMILY, 13))
                .axis_desc_style((FAMILY, 15))
                .draw()
                .map_err(plot_error)?;
            for series in &self.series {
                let colour = PALETTE[series.colour % PALETTE.len()];
                let points: Vec<(f64, f64)> =
                    series.points.iter().copied().filter(drawable).collect();
                if series.connect {
                    chart
                        .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
                        .map_err(plot_error)?;
                }
                chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                    .map_err(plot_error)?
                    .label(series.label.as_str())
                    .legend(move |(x, y)| Circle::new((x, y), 4, colour.filled()));
                let marked = series
                    .points
                    .iter()
                    .zip(&series.marked)
                    .filter(|(p, m)| **m && drawable(p))
                    .map(|(&p, _)| Circle::new(p, 8, colour.stroke_width(2)));
                chart.draw_series(marked).map_err(plot_error)?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font((FAMILY, 13))
                .draw()
                .map_err(plot_error)?;
            root.present().map_err(plot_error)?;
        }
        RgbImage::from_raw(width, height, buffer).ok_or_else(|| anyhow!("plot buffer size"))
    }
}

/// A plot of `series` written to a PNG at `path` (whole or not at all, as every image vkgi
/// writes).
pub fn write_plot(
    path: &std::path::Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: Vec<Series>,
) -> anyhow::Result<()> {
    let plot = Plot {
        title: title.into(),
        x_label: x_label.into(),
        y_label: y_label.into(),
        series,
    };
    crate::imageio::write_rgb(path, &plot.render()?)
}

/// Panels of equal size side by side, each with its label underneath.
pub fn strip(panels: &[(String, RgbImage)]) -> anyhow::Result<RgbImage> {
    register_font()?;
    let (w, h) = panels.first().map_or((1, 1), |(_, p)| p.dimensions());
    let width = w * panels.len().max(1) as u32;
    let mut strip = RgbImage::from_pixel(width, h + LABEL_HEIGHT, image::Rgb([255, 255, 255]));
    for (k, (_, panel)) in panels.iter().enumerate() {
        image::imageops::replace(&mut strip, panel, i64::from(k as u32 * w), 0);
    }
    let (sw, sh) = strip.dimensions();
    {
        let buffer: &mut [u8] = &mut strip;
        let area = BitMapBackend::with_buffer(buffer, (sw, sh)).into_drawing_area();
        let style = TextStyle::from((FAMILY, 12).into_font()).color(&BLACK);
        for (k, (label, _)) in panels.iter().enumerate() {
            let at = ((k as u32 * w + 3) as i32, (h + 3) as i32);
            area.draw_text(label, &style, at).map_err(plot_error)?;
        }
        area.present().map_err(plot_error)?;
    }
    Ok(strip)
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
    fn log_ranges_hold_a_power_of_ten_to_label() {
        // Under a decade: extended down to just under the power below.
        let r = log_range([0.137, 0.276].into_iter());
        assert!(r.start < 0.1 && r.start > 0.099 && r.end > 0.276, "{r:?}");
        // A decade or more: kept around the values.
        let r = log_range([1.0, 32.0].into_iter());
        assert!((r.start - 1.0 / 1.3).abs() < 1e-12 && r.end > 32.0, "{r:?}");
    }

    #[test]
    fn tick_labels_keep_three_significant_digits() {
        assert_eq!(significant(0.012345), "0.0123");
        assert_eq!(significant(100.0), "100");
        assert_eq!(significant(2.5), "2.5");
        assert_eq!(significant(12345.6), "12346");
    }

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let pts = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (4.0, 2.0)];
        assert_eq!(pareto_front(&pts), vec![true, true, false, true, false]);
    }

    #[test]
    fn plots_draw_series_colours_and_text() {
        let plot = Plot {
            title: "T".into(),
            x_label: "X".into(),
            y_label: "Y".into(),
            series: vec![Series {
                label: "S".into(),
                points: vec![(1.0, 1.0), (100.0, 10.0), (-1.0, 0.0)],
                marked: vec![true, false, false],
                connect: true,
                colour: 0,
            }],
        };
        let img = match plot.render() {
            Ok(img) => img,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(img.dimensions(), SIZE);
        let c = PALETTE[0];
        let coloured = img.pixels().filter(|p| p.0 == [c.0, c.1, c.2]).count();
        assert!(coloured > 50, "series pixels drawn: {coloured}");
        assert!(
            img.pixels().any(|p| p.0 == [0, 0, 0]),
            "axes and text drawn"
        );
    }

    #[test]
    fn strips_place_panels_side_by_side_with_labels() {
        let red = RgbImage::from_pixel(20, 10, image::Rgb([255, 0, 0]));
        let blue = RgbImage::from_pixel(20, 10, image::Rgb([0, 0, 255]));
        let s = match strip(&[("a".into(), red), ("b".into(), blue)]) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(s.dimensions(), (40, 10 + LABEL_HEIGHT));
        assert_eq!(s.get_pixel(5, 5).0, [255, 0, 0]);
        assert_eq!(s.get_pixel(25, 5).0, [0, 0, 255]);
        let dark = (0..40)
            .flat_map(|x| (10..10 + LABEL_HEIGHT).map(move |y| (x, y)))
            .filter(|&(x, y)| s.get_pixel(x, y).0[0] < 128)
            .count();
        assert!(dark > 0, "labels drawn");
    }
}
