//! Seed 003's Table 8.1 regenerated on `atrium` (issue #15): the relative RMS error of a record's
//! irradiance against a hemisphere integral, for plane sampling, [LC04]'s coverage division and
//! border stretching (the chapter, on Sibenik: 18.1% / 10.4% / 5.8%), over the chapter's 10 000
//! camera points, 64² hemispheres and a 128² reference.
//!
//! cargo bench --bench ic_table81 [-- POINTS]   (markdown to stdout; CPU only, about 2 minutes
//! for 10 000 points on 2 idle cores)

use std::time::Instant;

use vkgi::gi::irradiance_cache::coverage_study::{COLUMNS, StudySize, coverage_study};
use vkgi::scene::Scene;

fn main() {
    let points = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(10_000);
    let scene = Scene::load("atrium").expect("atrium");
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let start = Instant::now();
    let study = coverage_study(
        &scene,
        StudySize {
            points,
            resolution: 64,
            reference_side: 128,
            threads,
        },
    );
    println!(
        "| {} | {} of {points} points lit, {:.0} s |",
        COLUMNS.map(|c| format!("{c:?}")).join(" | "),
        study.points,
        start.elapsed().as_secs_f64()
    );
    println!("|---|---|---|---|");
    let percent = |v: [f64; 3]| v.map(|r| format!("{:.1}%", 100.0 * r)).join(" | ");
    println!("| {} | RMS of relative errors |", percent(study.rms));
    println!(
        "| {} | RMS error over mean E |",
        percent(study.normalised_rms)
    );
}
