//! The CAVE as seed 000 ran it (spec 000 §11): a master process that owns the input and sends
//! versioned parameter updates, and render nodes, one process and Vulkan device per wall, that
//! each replicate the whole frame (RSM, injection, propagation) for their own wall, frame-locked:
//! no node starts frame N+1 before every node finished frame N.
//!
//! * `protocol`: the messages and the length-delimited TCP link that carries them;
//! * `path`: the tracked head and light samples that drive a run;
//! * `master`, `node`: `vkgi cave-master` and `vkgi cave-node`.

pub mod display;
pub mod input;
pub mod master;
pub mod node;
pub mod path;
pub mod protocol;
pub mod stereo;

use std::time::Duration;

use glam::Vec3;

use crate::render::Frame;
use crate::scene::Scene;
use crate::view::cave::{Cave, EyeChoice};
use protocol::Update;

/// `value` seconds, or one line of bad input naming `--flag`.
fn seconds(value: f64, flag: &str) -> anyhow::Result<Duration> {
    if !(value.is_finite() && value > 0.0 && value <= 86_400.0) {
        crate::bad_input!("--{flag} must be in (0, 86400] seconds");
    }
    Ok(Duration::from_secs_f64(value))
}

/// A node's name in messages: "front wall", or "front wall (left eye)".
pub fn node_name(wall: &str, eye: EyeChoice) -> String {
    match eye {
        EyeChoice::Mono => format!("{wall} wall"),
        EyeChoice::Both => format!("{wall} wall (both eyes)"),
        eye => format!("{wall} wall ({} eye)", eye.name()),
    }
}

/// The parameters a frame is drawn with, as far as the master sends them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// The tracked head, relative to the CAVE's centre in half-sizes (right, up, back).
    pub head: Vec3,
    /// Where the scene's first light stands (None: where the scene put it).
    pub light: Option<Vec3>,
}

/// The updates that take a node from `before` (None: nothing sent yet) to `now`.
pub fn updates(before: Option<&Pose>, now: &Pose) -> Vec<Update> {
    let mut updates = Vec::new();
    if before.is_none_or(|b| b.head != now.head) {
        updates.push(Update::Head(now.head.to_array()));
    }
    if let Some(light) = now.light
        && before.is_none_or(|b| b.light != Some(light))
    {
        updates.push(Update::Light(light.to_array()));
    }
    updates
}

/// Apply `updates` to the scene, the frame and the CAVE, the way every process of a run does
/// (the master's nodes, and the single-process `vkgi view --cave --path`), so that all of them
/// hand their GI method the same changes in the same frames.
pub fn apply(updates: &[Update], scene: &mut Scene, frame: &mut Frame, cave: &mut Cave) {
    for update in updates {
        match *update {
            Update::Head(head) => cave.head_offset = Vec3::from_array(head),
            Update::Light(position) => {
                if let Some(light) = scene.lights.first_mut() {
                    light.position = Vec3::from_array(position);
                    frame.set_lights(scene);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn updates_carry_only_what_changed_and_everything_at_first() {
        let a = Pose {
            head: Vec3::new(0.1, 0.2, 0.3),
            light: Some(Vec3::ONE),
        };
        assert_eq!(
            updates(None, &a),
            vec![Update::Head([0.1, 0.2, 0.3]), Update::Light([1.0; 3])]
        );
        assert!(updates(Some(&a), &a).is_empty());
        let moved = Pose {
            light: Some(Vec3::ZERO),
            ..a
        };
        assert_eq!(updates(Some(&a), &moved), vec![Update::Light([0.0; 3])]);
        let still = Pose { light: None, ..a };
        assert_eq!(updates(None, &still), vec![Update::Head([0.1, 0.2, 0.3])]);
    }
}
