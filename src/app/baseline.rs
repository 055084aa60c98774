//! Stored timings a bench compares its run against, so that a slowdown shows as a number
//! (issue #18 item 6). One JSON file per bench under `benches/baselines/`, holding for each
//! device name the median nanoseconds per measured key (a pass, or a configuration's core
//! pass). `--save-baseline` on a bench writes this run's numbers for this device.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

/// Median nanoseconds per key, per device.
pub type Timings = BTreeMap<String, f64>;

#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Baselines {
    pub devices: BTreeMap<String, Timings>,
}

/// Where bench `bench`'s baselines live.
pub fn path(bench: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("benches/baselines")
        .join(format!("{bench}.json"))
}

impl Baselines {
    /// The stored baselines at `path` (none stored: empty).
    pub fn load(path: &Path) -> anyhow::Result<Baselines> {
        match std::fs::read_to_string(path) {
            Ok(text) => serde_json::from_str(&text)
                .with_context(|| format!("{}: not a baselines file", path.display())),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Baselines::default()),
            Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
        }
    }

    /// Write to `path` whole or not at all.
    pub fn save(&self, path: &Path) -> anyhow::Result<()> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let text = serde_json::to_string_pretty(self)?;
        crate::imageio::write_atomically(path, |tmp| Ok(std::fs::write(tmp, text)?))
    }
}

/// A table of `now` against `baseline`: each key's baseline and current median and their ratio
/// (above 1: slower now), then the geometric mean of the ratios of the keys both have.
pub fn compare(baseline: &Timings, now: &Timings) -> String {
    let mut out =
        String::from("| key | baseline ns | now ns | now / baseline |\n|---|---|---|---|\n");
    let mut log_sum = 0.0;
    let mut count = 0;
    for (key, &ns) in now {
        match baseline.get(key) {
            Some(&base) if base > 0.0 && ns > 0.0 => {
                let ratio = ns / base;
                log_sum += ratio.ln();
                count += 1;
                let _ = writeln!(out, "| {key} | {base:.0} | {ns:.0} | {ratio:.3} |");
            }
            _ => {
                let _ = writeln!(out, "| {key} | - | {ns:.0} | new |");
            }
        }
    }
    for key in baseline.keys().filter(|k| !now.contains_key(*k)) {
        let _ = writeln!(out, "| {key} | {:.0} | - | gone |", baseline[key]);
    }
    if count > 0 {
        let _ = writeln!(
            out,
            "\ngeometric mean of {count} ratios: {:.3}",
            (log_sum / f64::from(count)).exp()
        );
    }
    out
}

/// The bench's ending: with `--save-baseline` among the arguments store `now` as `device`'s
/// baseline of `bench`, else print `now` against the stored one.
pub fn finish(bench: &str, device: &str, now: Timings) -> anyhow::Result<()> {
    let file = path(bench);
    let mut stored = Baselines::load(&file)?;
    if std::env::args().any(|a| a == "--save-baseline") {
        stored.devices.insert(device.to_string(), now);
        stored.save(&file)?;
        println!("baseline for {device} saved to {}", file.display());
        return Ok(());
    }
    match stored.devices.get(device) {
        Some(baseline) => {
            println!(
                "\nagainst the stored baseline for {device} ({}):\n",
                file.display()
            );
            print!("{}", compare(baseline, &now));
        }
        None => println!(
            "\nno stored baseline for {device} in {} (run the bench with --save-baseline)",
            file.display()
        ),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timings(pairs: &[(&str, f64)]) -> Timings {
        pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    #[test]
    fn ratios_and_their_geometric_mean() {
        let baseline = timings(&[("a", 100.0), ("b", 200.0), ("old", 5.0)]);
        let now = timings(&[("a", 200.0), ("b", 100.0), ("new", 7.0)]);
        let table = compare(&baseline, &now);
        assert!(table.contains("| a | 100 | 200 | 2.000 |"), "{table}");
        assert!(table.contains("| b | 200 | 100 | 0.500 |"), "{table}");
        assert!(table.contains("| new | - | 7 | new |"), "{table}");
        assert!(table.contains("| old | 5 | - | gone |"), "{table}");
        assert!(
            table.contains("geometric mean of 2 ratios: 1.000"),
            "{table}"
        );
    }

    #[test]
    fn baselines_round_trip_and_a_missing_file_is_empty() {
        let dir = std::env::temp_dir().join(format!("vkgi-baseline-{}", std::process::id()));
        let file = dir.join("bench.json");
        assert!(Baselines::load(&file).unwrap().devices.is_empty());
        let mut stored = Baselines::default();
        stored
            .devices
            .insert("device".into(), timings(&[("pass", 1234.5)]));
        stored.save(&file).unwrap();
        let loaded = Baselines::load(&file).unwrap();
        assert_eq!(loaded.devices["device"]["pass"], 1234.5);
        std::fs::write(&file, "not json").unwrap();
        assert!(Baselines::load(&file).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
