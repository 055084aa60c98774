//! A file of tracked samples that drives a CAVE run, one line per frame:
//!
//! ```text
//! # head right up back [light x y z]
//! 0.2 0.1 0.3  0.1 0.35 0.2
//! 0.21 0.1 0.3 0.1 0.35 0.21
//! ```
//!
//! The head is relative to the CAVE's centre in half-sizes (inside the CAVE: each within ±1);
//! the optional light is the world position of the scene's first light (every line gives one
//! or none does). Frame N takes line N; frames past the last line keep it. `#` starts a
//! comment; blank lines are skipped.

use std::path::Path;

use glam::Vec3;

use super::Pose;
use crate::error::InputError;

/// The most samples a file may hold (a minute at 60 Hz is 3 600).
const MAX_SAMPLES: usize = 1_000_000;
/// The largest file read (a sample line is under 100 bytes).
const MAX_BYTES: u64 = 64 << 20;

#[derive(Clone, Debug, PartialEq)]
pub struct TrackedPath {
    samples: Vec<Pose>,
}

impl TrackedPath {
    pub fn load(path: &Path) -> Result<TrackedPath, InputError> {
        let fail = |why: String| InputError::new(format!("path {}: {why}", path.display()));
        let size = std::fs::metadata(path)
            .map_err(|e| fail(e.to_string()))?
            .len();
        if size > MAX_BYTES {
            return Err(fail(format!(
                "{size} bytes is over the {MAX_BYTES}-byte limit"
            )));
        }
        let text = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
        TrackedPath::parse(&text).map_err(fail)
    }

    pub fn parse(text: &str) -> Result<TrackedPath, String> {
        let mut samples = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let at = |why: String| format!("line {}: {why}", number + 1);
            let values = line
                .split_whitespace()
                .map(|v| {
                    v.parse::<f32>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| at(format!("'{v}' is not a finite number")))
                })
                .collect::<Result<Vec<f32>, String>>()?;
            let head = match values.len() {
                3 | 6 => Vec3::new(values[0], values[1], values[2]),
                n => {
                    return Err(at(format!(
                        "{n} numbers, expected 3 (head) or 6 (head, light)"
                    )));
                }
            };
            if head.abs().max_element() > 1.0 {
                return Err(at(format!(
                    "head {head} leaves the CAVE (each coordinate within ±1 half-size)"
                )));
            }
            let light = (values.len() == 6).then(|| Vec3::new(values[3], values[4], values[5]));
            if samples
                .first()
                .is_some_and(|first: &Pose| first.light.is_some() != light.is_some())
            {
                return Err(at("every line gives a light position or none does".into()));
            }
            if samples.len() == MAX_SAMPLES {
                return Err(format!("more than {MAX_SAMPLES} samples"));
            }
            samples.push(Pose { head, light });
        }
        if samples.is_empty() {
            return Err("no samples".into());
        }
        Ok(TrackedPath { samples })
    }

    /// The pose of frame `frame` (0-based): its line, or the last line past the end.
    pub fn at(&self, frame: u64) -> Pose {
        let index = usize::try_from(frame).map_or(usize::MAX, |f| f);
        self.samples[index.min(self.samples.len() - 1)]
    }

    /// Whether the samples move the light.
    pub fn moves_light(&self) -> bool {
        self.samples[0].light.is_some()
    }

    /// Refuse samples that move a light `scene` does not have.
    pub fn check_scene(&self, scene: &crate::scene::Scene) -> Result<(), InputError> {
        if self.moves_light() && scene.lights.is_empty() {
            return Err(InputError::new(format!(
                "the path moves the first light, but scene '{}' has no point or spot light",
                scene.name
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_drive_frames_in_order_and_the_last_holds() {
        let path =
            TrackedPath::parse("# head, light\n0 0 0 1 2 3\n\n0.5 -0.5 1 1 2 4 # moved\n").unwrap();
        assert!(path.moves_light());
        assert_eq!(path.at(0).light, Some(Vec3::new(1.0, 2.0, 3.0)));
        assert_eq!(path.at(1).head, Vec3::new(0.5, -0.5, 1.0));
        assert_eq!(path.at(7), path.at(1));
        assert_eq!(path.at(u64::MAX), path.at(1));
        let heads = TrackedPath::parse("0.1 0.2 0.3").unwrap();
        assert!(!heads.moves_light());
    }

    #[test]
    fn malformed_samples_name_their_line() {
        for (text, expected) in [
            ("", "no samples"),
            ("# only a comment\n", "no samples"),
            ("0 0\n", "line 1: 2 numbers"),
            ("0 0 0\n0 0 nan\n", "line 2: 'nan' is not a finite"),
            ("0 0 inf\n", "line 1: 'inf'"),
            ("0 0 0 1 1 1\n0 0 0\n", "line 2: every line gives a light"),
            ("0 0 1.5\n", "line 1: head"),
            ("0 0 0 1e39 0 0\n", "line 1: '1e39'"),
        ] {
            let error = TrackedPath::parse(text).unwrap_err();
            assert!(error.contains(expected), "{text:?}: {error}");
        }
    }
}
