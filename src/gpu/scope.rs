//! Typed tags of timed scopes: which method, frame stage, independent part, step and layer a
//! pass belongs to. The recorder tags every pass from its context, so the profile, the viewer's
//! overlay and the reports group and select passes by these fields instead of parsing names.

use serde::Serialize;

/// Where in the frame a pass runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stage {
    /// Recorded outside a frame's stages (tests, tools, one-shot work).
    #[default]
    Other,
    /// The scope spanning a whole frame.
    Frame,
    /// Light updates, shadow maps and G-buffers.
    Scene,
    /// A GI method's work for one view, before its light work.
    GiView,
    /// A GI method's work once per frame for all views (e.g. RSM, injection).
    GiLight,
    /// One of a GI method's independent parts (may run on its own compute queue).
    GiPart,
    /// Direct lighting of a view.
    Direct,
    /// A GI method adding indirect light to a view's HDR image.
    GiLookup,
    /// Tone mapping, composition, overlay and presentation.
    Output,
}

/// One of a method's independent parts: its index and its label (e.g. 0, "R").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct Part {
    pub index: u32,
    pub label: &'static str,
}

/// What the recorder tags the passes it records with, set by whoever drives the recording
/// (the frame sets method, stage, part and view; a method sets steps and layers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
pub struct ScopeTag {
    /// The registered name of the GI method that recorded the pass (None: the frame's own).
    pub method: Option<&'static str>,
    pub stage: Stage,
    /// The pass itself, without part, step or layer (e.g. "propagate").
    pub pass: &'static str,
    pub part: Option<Part>,
    /// Iteration of a repeated pass within a frame, from 1 (e.g. propagation steps).
    pub step: Option<u32>,
    /// Layer of a layered target the pass renders (e.g. a light's shadow view).
    pub layer: Option<u32>,
    /// The view (CAVE wall) a per-view pass works on.
    pub view: Option<u32>,
}

impl ScopeTag {
    /// The display name: the pass, then its part label, step and layer ("propagate R step 3",
    /// "rsm view 0"). The view is not part of the name: a view's passes sum per frame.
    pub fn name(&self) -> String {
        let mut name = self.pass.to_string();
        if let Some(part) = self.part {
            name.push(' ');
            name.push_str(part.label);
        }
        if let Some(step) = self.step {
            name.push_str(&format!(" step {step}"));
        }
        if let Some(layer) = self.layer {
            name.push_str(&format!(" view {layer}"));
        }
        name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_pass_then_part_step_and_layer() {
        let tag = ScopeTag {
            pass: "propagate",
            part: Some(Part {
                index: 0,
                label: "R",
            }),
            step: Some(3),
            ..ScopeTag::default()
        };
        assert_eq!(tag.name(), "propagate R step 3");
        let rsm = ScopeTag {
            pass: "rsm",
            layer: Some(0),
            view: Some(2),
            ..ScopeTag::default()
        };
        assert_eq!(rsm.name(), "rsm view 0");
    }
}
