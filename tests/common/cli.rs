//! Running the `vkgi` binary from a test, and what bad input must look like from outside.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run `vkgi` with validation on (a panic would print a backtrace, which the checks look for).
pub fn vkgi(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vkgi"))
        .args(args)
        .env("VKGI_VALIDATE", "1")
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the vkgi binary runs")
}

/// A fresh folder `vkgi-{suite}-{name}-{pid}` for one test's files.
pub fn scratch(suite: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vkgi-{suite}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Write `text` to `dir/name` and return the path.
pub fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

/// Exit code 2, exactly one line on stderr mentioning `needle`, no panic or backtrace.
pub fn assert_bad_input(output: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "exit code; stderr: {stderr}");
    assert!(
        !stderr.contains("panicked") && !stderr.contains("backtrace"),
        "{stderr}"
    );
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one line expected, got: {stderr}");
    assert!(
        lines[0].to_lowercase().contains(&needle.to_lowercase()),
        "'{needle}' not in: {}",
        lines[0]
    );
}
