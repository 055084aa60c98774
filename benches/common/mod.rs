//! What the plotting benches share.

use std::path::PathBuf;

/// The folder for a bench's plots: its first argument that is not a flag (cargo bench passes
/// `--bench`), docs/images by default; created if missing.
pub fn out_dir() -> anyhow::Result<PathBuf> {
    let dir = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with("--"))
        .map_or_else(|| PathBuf::from("docs/images"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}
