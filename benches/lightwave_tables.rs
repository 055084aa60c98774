//! Seed 002's tables regenerated as relative trends on this machine (issue #14): Tables 5.1-5.4
//! (cost against angle, VPLs per ray, resolution and indirect shadow maps) with their quality
//! twins 5.5-5.8, Table 5.9 (the alternative reductions) and Tables 5.11-5.13 (integrated
//! shadows against numSteps), each row a `vkgi report` configuration on `lightwave-boxes`.
//!
//! Per row: the median GPU time of a frame, the speed relative to the table's first row (its
//! default) next to the thesis's FPS ratio, the thesis's "% similar" against the first row
//! (lower resolutions stretched to the first row's size, as the thesis did) next to the
//! thesis's, and the row's real error against the path-traced reference: RMSE, relMSE and FLIP
//! of the full image, and its % similar to the reference. The resolutions are the thesis's ÷ 10.
//!
//! cargo bench --bench lightwave_tables [-- OUT_DIR]   (prints the markdown docs/lightwave.md holds)

use std::path::{Path, PathBuf};

use image::imageops::FilterType;
use vkgi::app::report::{self, Report, ReportConfig};
use vkgi::gpu::{Gpu, GpuOptions};
use vkgi::metrics;

/// Frames per configuration (the first untimed).
const FRAMES: u32 = 6;
const SPP: u32 = 256;
const SCENE: &str = "lightwave-boxes";
/// The thesis's 1280x720, ÷ 10.
const SIZE: (u32, u32) = (128, 72);

/// One row of a thesis table: the settings that differ from the default, its size, and what
/// the thesis measured (FPS, % similar to the default where it measured it).
struct Row {
    label: &'static str,
    settings: &'static [(&'static str, &'static str)],
    size: (u32, u32),
    fps: Option<f64>,
    similar: Option<f64>,
}

const fn row(
    label: &'static str,
    settings: &'static [(&'static str, &'static str)],
    fps: Option<f64>,
    similar: Option<f64>,
) -> Row {
    Row {
        label,
        settings,
        size: SIZE,
        fps,
        similar,
    }
}

const fn sized(label: &'static str, size: (u32, u32), fps: f64, similar: f64) -> Row {
    Row {
        label,
        settings: &[],
        size,
        fps: Some(fps),
        similar: Some(similar),
    }
}

struct Table {
    title: &'static str,
    rows: &'static [Row],
}

/// The thesis's default: 5°, 5 VPLs per ray (6485 VPLs), 20 accurate maps, maps 3x the screen.
const DEFAULTS: &[(&str, &str)] = &[
    ("lightwave-gather", "vertex"),
    ("lightwave-angle", "5"),
    ("lightwave-per-ray", "5"),
    ("lightwave-shadows", "accurate"),
    ("lightwave-shadow-maps", "20"),
    ("lightwave-steps", "4"),
    ("lightwave-shadow-ratio", "3"),
    ("lightwave-composite", "eq4.9"),
    ("lightwave-fake", "1.3"),
];

const TABLES: &[Table] = &[
    Table {
        title: "Tables 5.1 and 5.5: the angle between rays",
        rows: &[
            row("5° (6485 VPLs)", &[], Some(55.0), Some(100.0)),
            row(
                "10° (1625)",
                &[("lightwave-angle", "10")],
                Some(65.0),
                Some(97.945),
            ),
            row(
                "30° (185)",
                &[("lightwave-angle", "30")],
                Some(84.0),
                Some(97.956),
            ),
            row(
                "45° (85)",
                &[("lightwave-angle", "45")],
                Some(95.0),
                Some(95.440),
            ),
            row(
                "90° (25)",
                &[("lightwave-angle", "90")],
                Some(100.0),
                Some(92.676),
            ),
        ],
    },
    Table {
        title: "Tables 5.2 and 5.6: VPLs per ray",
        rows: &[
            row("5 (6485 VPLs)", &[], Some(55.0), Some(100.0)),
            row(
                "4 (5188)",
                &[("lightwave-per-ray", "4")],
                Some(56.0),
                Some(92.973),
            ),
            row(
                "3 (3891)",
                &[("lightwave-per-ray", "3")],
                Some(61.0),
                Some(93.458),
            ),
            row(
                "2 (2594)",
                &[("lightwave-per-ray", "2")],
                Some(62.0),
                Some(90.318),
            ),
            row(
                "1 (1297)",
                &[("lightwave-per-ray", "1")],
                Some(78.0),
                Some(91.591),
            ),
            row(
                "6 (7782)",
                &[("lightwave-per-ray", "6")],
                Some(52.0),
                Some(96.509),
            ),
        ],
    },
    Table {
        title: "Tables 5.3 and 5.7: the resolution (the thesis's ÷ 10)",
        rows: &[
            sized("128x72 (1280x720)", (128, 72), 55.0, 100.0),
            sized("112x63 (1120x630)", (112, 63), 82.0, 99.547),
            sized("96x54 (960x540)", (96, 54), 104.0, 99.541),
            sized("80x45 (800x450)", (80, 45), 119.0, 99.418),
            sized("64x36 (640x360)", (64, 36), 133.0, 99.483),
            sized("144x81 (1440x810)", (144, 81), 42.0, 99.741),
        ],
    },
    Table {
        title: "Tables 5.4 and 5.8: accurate indirect shadow maps K",
        rows: &[
            row("20", &[], Some(55.0), Some(100.0)),
            row(
                "15",
                &[("lightwave-shadow-maps", "15")],
                Some(87.0),
                Some(99.475),
            ),
            row(
                "10",
                &[("lightwave-shadow-maps", "10")],
                Some(106.0),
                Some(98.853),
            ),
            row(
                "5",
                &[("lightwave-shadow-maps", "5")],
                Some(128.0),
                Some(93.611),
            ),
            row(
                "1",
                &[("lightwave-shadow-maps", "1")],
                Some(157.0),
                Some(90.897),
            ),
            row(
                "0",
                &[("lightwave-shadow-maps", "0")],
                Some(161.0),
                Some(98.563),
            ),
        ],
    },
    Table {
        title: "Table 5.9: alternative reductions (and vkgi's per-pixel gather)",
        rows: &[
            row("default", &[], Some(55.0), Some(100.0)),
            row(
                "direct only",
                &[("lightwave-composite", "direct-only")],
                Some(681.0),
                Some(84.426),
            ),
            row(
                "no indirect shadows",
                &[("lightwave-shadow-maps", "0")],
                Some(161.0),
                Some(98.563),
            ),
            row(
                "fake 1.1x",
                &[("lightwave-composite", "fake"), ("lightwave-fake", "1.1")],
                Some(681.0),
                Some(88.217),
            ),
            row(
                "fake 1.3x",
                &[("lightwave-composite", "fake"), ("lightwave-fake", "1.3")],
                Some(681.0),
                Some(91.847),
            ),
            row(
                "fake 1.5x",
                &[("lightwave-composite", "fake"), ("lightwave-fake", "1.5")],
                Some(681.0),
                Some(90.161),
            ),
            row(
                "as shipped (0.2/0.8, half direct shadows)",
                &[("lightwave-composite", "shipped")],
                None,
                None,
            ),
            row(
                "per-pixel gather",
                &[("lightwave-gather", "pixel")],
                None,
                None,
            ),
        ],
    },
    Table {
        title: "Table 5.11: integrated shadows, 6485 VPLs",
        rows: &[
            row("accurate, K 20", &[], Some(55.0), None),
            row("2 steps (40 shadows)", INTEGRATED_2, Some(81.0), None),
            row("4 steps (60)", INTEGRATED_4, Some(60.0), None),
            row("6 steps (80)", INTEGRATED_6, Some(48.0), None),
            row("10 steps (120)", INTEGRATED_10, Some(34.0), None),
        ],
    },
    Table {
        title: "Table 5.12: integrated shadows at 64x36 (640x360), 6485 VPLs",
        rows: &[
            Row {
                size: (64, 36),
                ..row("2 steps", INTEGRATED_2, Some(137.0), None)
            },
            Row {
                size: (64, 36),
                ..row("6 steps", INTEGRATED_6, Some(107.0), None)
            },
            Row {
                size: (64, 36),
                ..row("10 steps", INTEGRATED_10, Some(89.0), None)
            },
        ],
    },
    Table {
        title: "Table 5.13: integrated shadows, 30° (185 VPLs)",
        rows: &[
            row("2 steps", INTEGRATED_30_2, Some(150.0), None),
            row("6 steps", INTEGRATED_30_6, Some(65.0), None),
            row("10 steps", INTEGRATED_30_10, Some(42.0), None),
        ],
    },
];

const INTEGRATED_2: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "2"),
];
const INTEGRATED_4: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "4"),
];
const INTEGRATED_6: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "6"),
];
const INTEGRATED_10: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "10"),
];
const INTEGRATED_30_2: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "2"),
    ("lightwave-angle", "30"),
];
const INTEGRATED_30_6: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "6"),
    ("lightwave-angle", "30"),
];
const INTEGRATED_30_10: &[(&str, &str)] = &[
    ("lightwave-shadows", "integrated"),
    ("lightwave-steps", "10"),
    ("lightwave-angle", "30"),
];

/// What one row measured.
#[derive(Clone)]
struct Measured {
    ms: f64,
    rmse: f64,
    rel_mse: f64,
    flip: f64,
    similar_to_truth: f64,
    /// The tone-mapped image the report wrote.
    image: PathBuf,
}

/// Run row `row` as a one-configuration report in `out` (one folder per size, so rows of a size
/// share their path-traced reference).
fn measure(gpu: &Gpu, out: &Path, row: &Row) -> anyhow::Result<Measured> {
    let dir = out.join(format!("{}x{}", row.size.0, row.size.1));
    let grid = DEFAULTS
        .iter()
        .map(|(name, default)| {
            let value = row
                .settings
                .iter()
                .find(|(n, _)| n == name)
                .map_or(*default, |(_, v)| *v);
            (name.to_string(), vec![value.to_string()])
        })
        .collect();
    let config = ReportConfig {
        scene: SCENE.into(),
        out_dir: dir.clone(),
        size: row.size,
        spp: SPP,
        methods: vec!["lightwave".into()],
        grid,
        frames: Some(FRAMES),
    };
    let report: Report = report::run(gpu, &config)?;
    let r = &report.rows[0];
    Ok(Measured {
        ms: r.ms_per_frame,
        rmse: r.full.rmse,
        rel_mse: r.full.rel_mse,
        flip: r.full.flip,
        similar_to_truth: r.full.similarity,
        image: dir.join(&r.image),
    })
}

/// The thesis's "% similar" of `test` to `default` on their 8-bit images, `test` stretched to
/// the default's size first (bilinear) as the thesis stretched its lower resolutions.
fn similar_to_default(test: &Path, default: &Path) -> anyhow::Result<f64> {
    let default = image::open(default)?.into_rgb8();
    let test = image::open(test)?.into_rgb8();
    let test = if test.dimensions() == default.dimensions() {
        test
    } else {
        image::imageops::resize(
            &test,
            default.width(),
            default.height(),
            FilterType::Triangle,
        )
    };
    Ok(100.0 * metrics::similarity_of_bytes(test.as_raw(), default.as_raw()))
}

fn main() -> anyhow::Result<()> {
    let out: PathBuf = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with('-'))
        .map_or_else(|| PathBuf::from("target/lightwave-tables"), PathBuf::from);
    let gpu = Gpu::new(&GpuOptions::default())?;
    println!(
        "Scene `{SCENE}`, {FRAMES} frames per row (median of the last {}), reference {SPP} spp; device {}.\n",
        FRAMES - 1,
        gpu.info.name
    );
    for table in TABLES {
        println!("**{}**\n", table.title);
        println!(
            "| row | ms/frame | speed vs first | thesis FPS ratio | % similar to first | thesis % similar | RMSE | relMSE | FLIP | % similar to truth |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|");
        let mut first: Option<(Measured, Option<f64>)> = None;
        for row in table.rows {
            let m = measure(&gpu, &out, row)?;
            let (base, base_fps) = first.get_or_insert_with(|| (m.clone(), row.fps));
            let fps_ratio = match (row.fps, *base_fps) {
                (Some(f), Some(b)) => format!("{:.2}", f / b),
                _ => "-".into(),
            };
            let thesis_similar = row.similar.map_or("-".into(), |s| format!("{s:.3}"));
            println!(
                "| {} | {:.1} | {:.2} | {fps_ratio} | {:.3} | {thesis_similar} | {:.4} | {:.4} | {:.4} | {:.3} |",
                row.label,
                m.ms,
                base.ms / m.ms,
                similar_to_default(&m.image, &base.image)?,
                m.rmse,
                m.rel_mse,
                m.flip,
                100.0 * m.similar_to_truth,
            );
        }
        println!();
    }
    vkgi::app::render::check_validation(&gpu)?;
    Ok(())
}
