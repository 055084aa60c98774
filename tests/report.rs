//! `vkgi profile` and `vkgi report` end to end on lavapipe, validation on, at tiny sizes.

use std::collections::HashSet;
use std::path::PathBuf;
use std::process::Command;

fn vkgi(args: &[&str]) -> std::process::Output {
    let output = Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(args)
        .env("VKGI_VALIDATE", "1")
        .output()
        .expect("the vkgi binary runs");
    assert!(
        output.status.success(),
        "vkgi {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vkgi-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A frame's first propagation step blocks nothing, so it reads no geometry: its row is held
/// to that lesser bound, the later steps' rows to the configuration's core bound.
fn assert_first_step_held_to_its_own_bound(
    config: &serde_json::Value,
    passes: &[serde_json::Value],
) {
    let method = config["method"].as_str().unwrap();
    let core = &config["core"];
    if !method.contains("lpv") {
        return;
    }
    let number = |v: &serde_json::Value| v.as_f64().unwrap();
    let first = &core["first_run"];
    assert!(
        number(&first["bytes"]) < number(&core["bytes_per_unit"])
            && number(&first["flops"]) < number(&core["flops_per_unit"]),
        "{method}: {core}"
    );
    let units = number(&core["units"]);
    let limits = &config["limits"];
    let bound = |bytes: f64, flops: f64| {
        (bytes * units / number(&limits["bandwidth_bytes_per_ns"]))
            .max(flops * units / number(&limits["flops_per_ns"]))
    };
    let row = |pass: &str| {
        passes
            .iter()
            .find(|p| {
                p["method"] == config["method"]
                    && p["value"] == config["value"]
                    && p["pass"] == pass
            })
            .unwrap_or_else(|| panic!("{method}: no {pass}"))
    };
    for (pass, bytes, flops) in [
        ("propagate R step 1", &first["bytes"], &first["flops"]),
        (
            "propagate R step 2",
            &core["bytes_per_unit"],
            &core["flops_per_unit"],
        ),
    ] {
        let p = row(pass);
        let expected = bound(number(bytes), number(flops)) / number(&p["median_ns"]);
        let fraction = number(&p["fraction_of_bound"]);
        assert!(
            (fraction - expected).abs() <= 1e-9 * expected,
            "{method} {pass}: {fraction} against {expected}"
        );
    }
}

#[test]
fn the_profile_has_one_positive_entry_per_method_lattice_and_pass() {
    let dir = scratch("profile");
    let json = dir.join("profile.json");
    let csv = dir.join("profile.csv");
    let output = vkgi(&[
        "profile",
        "--lattice",
        "4,8",
        "--iterations",
        "2",
        // A dispatch per colour channel: the parts R, G, B below.
        "--channel-plan",
        "separate",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--size",
        "32x24",
        "--json",
        json.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("device limits") && stdout.contains("scaling ilpv"),
        "{stdout}"
    );
    let profile: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let passes = profile["passes"].as_array().unwrap();
    let mut seen = HashSet::new();
    for p in passes {
        let key = (
            p["method"].as_str().unwrap().to_string(),
            p["value"].as_str().unwrap_or("-").to_string(),
            p["pass"].as_str().unwrap().to_string(),
        );
        assert!(seen.insert(key.clone()), "duplicate entry {key:?}");
        assert!(p["median_ns"].as_f64().unwrap() > 0.0, "{p}");
        assert!(p["min_ns"].as_f64().unwrap() > 0.0, "{p}");
        if let Some(fraction) = p["fraction_of_bound"].as_f64() {
            assert!(fraction > 0.0 && fraction <= 1.0, "{p}");
        }
    }
    for method in ["lpv", "ilpv"] {
        for lattice in ["4", "8"] {
            let names: HashSet<&str> = seen
                .iter()
                .filter(|(m, l, _)| m == method && l == lattice)
                .map(|(_, _, p)| p.as_str())
                .collect();
            for pass in [
                "rsm view 0",
                "inject",
                "propagate R step 1",
                "propagate B step 2",
                "direct lighting + lpv lookup",
                "frame",
            ] {
                assert!(
                    names.contains(pass),
                    "{method} {lattice}: no '{pass}' in {names:?}"
                );
            }
        }
    }
    assert!(
        seen.contains(&(
            "ambient".to_string(),
            "-".to_string(),
            "direct lighting + ambient".to_string()
        )),
        "the baseline without a size axis is profiled once: {seen:?}"
    );
    assert!(
        profile["limits"]["bandwidth_bytes_per_ns"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(profile["limits"]["flops_per_ns"].as_f64().unwrap() > 0.0);
    for s in profile["scaling"].as_array().unwrap() {
        assert!(s["exponent"].as_f64().unwrap().is_finite());
    }
    assert!(stdout.contains("ns per pixel"), "{stdout}");
    let rate = |limits: &serde_json::Value, key: &str| limits[key].as_f64().unwrap();
    for config in profile["configs"].as_array().unwrap() {
        let method = config["method"].as_str().unwrap();
        assert_first_step_held_to_its_own_bound(config, passes);
        // Each configuration's bounds use the limits probed around its frames; the run's are
        // the best of them.
        for key in ["bandwidth_bytes_per_ns", "flops_per_ns"] {
            let own = rate(&config["limits"], key);
            assert!(
                own > 0.0 && own <= rate(&profile["limits"], key),
                "{method}: {key}"
            );
        }
        let pixel_passes = config["pixel_passes"].as_array().unwrap();
        let names: Vec<&str> = pixel_passes
            .iter()
            .map(|p| p["pass"].as_str().unwrap())
            .collect();
        // LPV and ILPV draw their lookup inside direct lighting, ambient its term, radiosity
        // its display: one pass in place of two, whose bound the profile states.
        let inside = match method {
            "lpv" | "ilpv" => Some("direct lighting + lpv lookup"),
            "ambient" => Some("direct lighting + ambient"),
            "radiosity" => Some("direct lighting + radiosity display"),
            _ => None,
        };
        // The other methods' per-pixel passes state theirs after the frame's.
        let own = match method {
            "radiance-volumes" => Some("rv apply"),
            "lightwave" => Some("lightwave gather"),
            "irradiance-cache" => Some("ic normalise"),
            _ => None,
        };
        let expected = match (inside, own) {
            (Some(pass), _) => vec!["g-buffer", "tone map", pass],
            (None, Some(pass)) => vec!["g-buffer", "direct lighting", "tone map", pass],
            (None, None) => vec!["g-buffer", "direct lighting", "tone map"],
        };
        assert_eq!(names, expected, "{method}");
        for p in pixel_passes {
            assert_eq!(p["unit"], "pixel", "{p}");
            assert_eq!(p["units"].as_u64(), Some(32 * 24), "{p}");
            for key in [
                "median_ns",
                "ns_per_unit",
                "bytes_per_unit",
                "flops_per_unit",
            ] {
                assert!(p[key].as_f64().unwrap() > 0.0, "{method}: {key} in {p}");
            }
            // A bound no pass beats: the probes measure the device's best.
            let fraction = p["fraction_of_bound"].as_f64().unwrap();
            assert!(
                fraction.is_finite() && fraction > 0.0 && fraction <= 1.0,
                "{method}: {p}"
            );
        }
    }
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap().lines().count(),
        passes.len() + 1
    );
}

#[test]
fn the_report_scores_a_tiny_grid_and_every_row_points_at_an_image() {
    let dir = scratch("report");
    let args = [
        "report",
        "--out-dir",
        dir.to_str().unwrap(),
        "--size",
        "32x24",
        "--spp",
        "8",
        "--lattice",
        "4",
        "--iterations",
        "1,2",
        "--incremental",
        "0.5",
        "--lightwave-shadow-maps",
        "0",
        "--frames",
        "2",
    ];
    vkgi(&args);
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    let rows = report["rows"].as_array().unwrap();
    assert_eq!(
        rows.len(),
        13,
        "the ambient baseline, lpv and ilpv at 1 and 2 steps and at full and half lookup resolution, lightwave, radiosity, irradiance-cache, radiance-volumes"
    );
    // Rows at half lookup resolution are scored against the same configuration at full.
    let mut halves = 0;
    for r in rows {
        let settings = r["settings"].as_array().unwrap();
        let half = settings
            .iter()
            .any(|s| s[0] == "lookup-resolution" && s[1] == "half");
        let against_exact = &r["vs_exact_setting"];
        if half {
            let rel_mse = against_exact["rel_mse"].as_f64().unwrap();
            assert!(rel_mse.is_finite() && rel_mse >= 0.0, "{r}");
            halves += 1;
        } else {
            assert!(against_exact.is_null(), "{r}");
        }
    }
    assert_eq!(halves, 4);
    assert!(rows.iter().any(|r| r["method"] == "irradiance-cache"));
    assert!(rows.iter().any(|r| r["method"] == "radiance-volumes"));
    let mut methods_seen = Vec::new();
    for r in rows {
        for part in ["indirect", "full"] {
            for metric in ["rmse", "rel_mse", "flip"] {
                let v = r[part][metric].as_f64().unwrap();
                assert!(v.is_finite() && v >= 0.0, "{part} {metric} = {v}");
            }
            let similarity = r[part]["similarity"].as_f64().unwrap();
            assert!(0.0 < similarity && similarity <= 1.0, "{part} {similarity}");
        }
        // The thesis's similarity against the method's first row: 1 for that row itself.
        let to_first = r["similarity_vs_first"].as_f64().unwrap();
        if methods_seen.contains(&r["method"]) {
            assert!(0.0 < to_first && to_first <= 1.0, "{r}");
        } else {
            assert_eq!(to_first, 1.0, "{r}");
            methods_seen.push(r["method"].clone());
        }
        assert!(r["ms_per_frame"].as_f64().unwrap() > 0.0);
        let ratio = r["rel_mse_vs_ambient"].as_f64().unwrap();
        assert!(ratio.is_finite() && ratio > 0.0, "{r}");
        if r["method"] == "ambient" {
            assert_eq!(ratio, 1.0);
        }
    }
    let markdown = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let table_rows: Vec<&str> = markdown
        .lines()
        .filter(|l| {
            ["| lpv", "| ilpv", "| ambient"]
                .iter()
                .any(|m| l.starts_with(m))
        })
        .collect();
    assert_eq!(table_rows.len(), 9);
    for row in table_rows {
        let link = row
            .rsplit("](")
            .next()
            .unwrap()
            .trim_end_matches(" |")
            .trim_end_matches(')');
        assert!(
            dir.join(link).is_file(),
            "row points at a missing image: {row}"
        );
    }
    for file in [
        "error_vs_time.png",
        "ns_per_unit.png",
        "strip.png",
        "reference.exr",
        "reference.exr.json",
    ] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    assert_eq!(report["reference"]["reused"], false);
    // A second run reuses the cached reference.
    vkgi(&args);
    let again: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(again["reference"]["reused"], true);
}
