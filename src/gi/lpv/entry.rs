//! LPV and ILPV as registered methods: their settings as data (flags, viewer keys, report
//! sweeps), how many frames they need to settle, and their constructors.

use super::geometry::BlockingLobe;
use super::lattice::CellOrder;
use super::lookup::{LookupFilter, LookupResolution};
use super::technique::{
    self as t, ChannelPlan, Extinction, FarLattice, IlpvLookup, InjectToward, Injection, Kernel, Lpv, LpvSettings,
    Scheme,
};
use crate::error::InputError;
use crate::gi::GiMethod;
use crate::gi::registry::{MethodEntry, Setup};
use crate::gi::settings::{Kind, Setting, Settings};

const LATTICE: Setting = Setting::new(
    "lattice",
    Kind::Int {
        min: 1,
        max: super::lattice::MAX_CELLS as i64,
    },
    "10",
    "Lattice cells along the scene's longest axis (other axes: as many as the bounds need)",
)
.keys('[', ']', 2.0)
.sweep(&["8", "16", "32"]);
const ITERATIONS: Setting = Setting::new(
    "iterations",
    Kind::Int { min: 0, max: 4096 },
    "8",
    "Propagation steps per frame",
)
.keys(',', '.', 1.0)
.sweep(&["4", "8", "16", "32"]);
const INCREMENTAL: Setting = Setting::new(
    "incremental",
    Kind::Float {
        min: 0.0,
        max: 0.999,
    },
    "0.5",
    "λ_incr: weight of last frame's propagated light (0 = plain propagation)",
)
.keys('-', '=', 0.05)
.sweep(&["0.5", "0.9"]);
const RSM: Setting = Setting::new(
    "rsm",
    Kind::Int { min: 8, max: 2048 },
    "256",
    "Reflective-shadow-map resolution per light view",
);
const ABSORPTION: Setting = Setting::new(
    "absorption",
    Kind::Float { min: 0.0, max: 1e6 },
    "0",
    "Absorption coefficient σa of the medium, per metre (a unitless base at most 1 with --extinction thesis)",
);
const SCATTERING: Setting = Setting::new(
    "scattering",
    Kind::Float { min: 0.0, max: 1e6 },
    "0",
    "Scattering coefficient σs of the medium, per metre (a unitless base at most 1 with --extinction thesis)",
);
const EXTINCTION: Setting = Setting::new(
    "extinction",
    Kind::Choice(&["physical", "thesis"]),
    "physical",
    "How σ becomes a per-step probability: physical (1 - exp(-σ d̄), d̄ the mean step in metres) or thesis (σ^d̄, which depends on the scene's unit)",
);
const BLOCKING_LOBE: Setting = Setting::new(
    "blocking-lobe",
    Kind::Choice(&["two-sided", "oriented", "projected", "visibility", "front", "back", "none"]),
    "two-sided",
    "What a surface adds to the geometry (blocking) lattice: its area projected on the direction of travel, one-way toward the void where one of its sides faces it (oriented) or both ways (projected), whether the segment between cell centres crosses a surface (visibility), or one of the thesis's SH lobes",
);
const BLOCKING_STRENGTH: Setting = Setting::new(
    "blocking-strength",
    Kind::Float {
        min: 0.0,
        max: 16.0,
    },
    "1",
    "Scale of the geometry lattice (1: a surface filling a cell blocks a face transfer fully)",
);
const BLOCK_FIRST_STEP: Setting = Setting::new(
    "block-first-step",
    Kind::Flag,
    "",
    "Apply blocking in the first step of a frame too (the thesis leaves it out)",
);
const KERNEL: Setting = Setting::new(
    "kernel",
    Kind::Choice(&[
        "auto",
        "tiled",
        "naive",
        "column",
        "single-column",
        "shared-rows",
    ]),
    "auto",
    "The propagation kernel: auto (the fastest of every kernel on this device, measured by GPU timestamps once and cached), tiled (a shared-memory tile per workgroup, for GPUs), naive (global memory: GPUs whose cache holds the neighbours), column (a bundle of 2x2 columns of cells along z per thread, its sources in registers, for CPU devices), single-column (one column a thread) or shared-rows (one column a thread, each row's cells shared across the subgroup's lanes: CPU devices with subgroup shuffles); all give the same bits",
);
const CHANNEL_PLAN: Setting = Setting::new(
    "channel-plan",
    Kind::Choice(&["auto", "separate", "fused"]),
    "auto",
    "How a propagation step carries the colour channels: auto (the faster on this device, measured with the kernel and cached), separate (a dispatch per channel: three parts, which overlap on devices with a compute queue each under --parts async) or fused (R, G and B in one dispatch, reading the geometry once); both give the same bits",
);
const CELL_ORDER: Setting = Setting::new(
    "cell-order",
    Kind::Choice(&["auto", "rows", "columns"]),
    "auto",
    "How the lattices' buffers hold their cells: auto (columns where a CPU device's kernel walks whole columns and the lookup reads texels, rows elsewhere), rows (x fastest: a GPU's neighbouring lanes read neighbouring words) or columns (z fastest: a column kernel's thread on a CPU walks consecutive lines); columns needs the lookup to read texels (--lookup-filter texels or shared-texels); all give the same bits",
);
const NO_CLAMP_COMPENSATION: Setting = Setting::new(
    "no-clamp-compensation",
    Kind::Flag,
    "",
    "Propagate with the thesis's global κ only, without per-cell clamp compensation",
);
const INJECT_OFFSET: Setting = Setting::new(
    "inject-offset",
    Kind::Float {
        min: -8.0,
        max: 8.0,
    },
    "0.5",
    "Cells VPLs move along their normal before injection (the thesis: 0.5)",
);
const INJECT_TOWARD: Setting = Setting::new(
    "inject-toward",
    Kind::Choice(&["normal", "light"]),
    "normal",
    "Which way VPLs move before injection: along their normal (the thesis) or toward their light, at most half way (no VPL of a light sealed in a box lands in a cell centred outside it)",
);
const INJECTION: Setting = Setting::new(
    "injection",
    Kind::Choice(&["float", "fixed"]),
    "float",
    "How VPLs add into their cells: float atomics (fast; a cell's sum depends on the threads' order) or 64-bit fixed-point integer atomics (the same bits on every run on one device and driver, so a CAVE's nodes agree)",
);
const LOOKUP_OFFSET: Setting = Setting::new(
    "lookup-offset",
    Kind::Float {
        min: -8.0,
        max: 8.0,
    },
    "1",
    "Cells the lookup moves along the surface normal (the thesis: 0.5; default from the accuracy grid in docs/lpv.md)",
);
const LOOKUP_RESOLUTION: Setting = Setting::new(
    "lookup-resolution",
    Kind::Choice(&["full", "half"]),
    "full",
    "Where the lookup evaluates the lattices: at every pixel (full), or at every second pixel in x and y with a depth- and normal-aware upsample (half; vkgi report scores its error against full)",
)
.sweep(&["full", "half"])
.approximating("half", "full");
const LOOKUP_FILTER: Setting = Setting::new(
    "lookup-filter",
    Kind::Choice(&["auto", "sampler", "texels", "shared-texels"]),
    "auto",
    "How the lookup interpolates the lattices: auto (shared-texels on a CPU device whose shaders can ballot, vote and shuffle across a subgroup, texels on another CPU device, sampler elsewhere), sampler (copies of the lattices as 3-D images the sampler filters: one fetch per channel, the texture unit's work on a GPU), texels (the lattices read as texels and interpolated in the shader: eight fetches per channel, about twice as fast as lavapipe's software filter) or shared-texels (texels, each subgroup's lanes fetching the cells around their points together: three fetches a lane for each set of cells the subgroup's points fall in); the texel forms give the same bits, the sampler the same light within float rounding",
);
const ILPV_LOOKUP: Setting = Setting::new(
    "ilpv-lookup",
    Kind::Choice(&["accumulated", "final"]),
    "accumulated",
    "What the ILPV lookup reads: the accumulated steps, or the thesis's final lattice",
);

const FAR_LATTICE: Setting = Setting::new(
    "far-lattice",
    Kind::Text,
    "auto",
    "ILPV in two scales: a coarse far-field lattice carries the light beyond --near-steps steps of the fine --lattice: off (one lattice), auto (cells of 0.45 mean free paths of the scene) or its cells along the longest axis",
);
const FAR_INJECTION: Setting = Setting::new(
    "far-injection",
    Kind::Float { min: 0.0, max: 1.0 },
    "0.3",
    "Two scales: the share of its own injected light the far field adds (the near field holds the rest)",
);
const NEAR_STEPS: Setting = Setting::new(
    "near-steps",
    Kind::Int { min: 1, max: 64 },
    "2",
    "Two scales: steps per frame of the fine near-field lattice, at λ_incr 0 (--iterations and --incremental then drive the far field)",
);

const ILPV_SETTINGS: &[Setting] = &[
    LATTICE,
    ITERATIONS,
    INCREMENTAL,
    RSM,
    ABSORPTION,
    SCATTERING,
    EXTINCTION,
    BLOCKING_LOBE,
    BLOCKING_STRENGTH,
    BLOCK_FIRST_STEP,
    KERNEL,
    CHANNEL_PLAN,
    CELL_ORDER,
    NO_CLAMP_COMPENSATION,
    INJECT_OFFSET,
    INJECT_TOWARD,
    INJECTION,
    LOOKUP_OFFSET,
    LOOKUP_RESOLUTION,
    LOOKUP_FILTER,
    ILPV_LOOKUP,
    FAR_LATTICE,
    NEAR_STEPS,
    FAR_INJECTION,
];
const LPV_SETTINGS: &[Setting] = &[
    LATTICE,
    ITERATIONS,
    RSM,
    BLOCKING_LOBE,
    BLOCKING_STRENGTH,
    BLOCK_FIRST_STEP,
    KERNEL,
    CHANNEL_PLAN,
    CELL_ORDER,
    INJECT_OFFSET,
    INJECT_TOWARD,
    INJECTION,
    LOOKUP_OFFSET,
    LOOKUP_RESOLUTION,
    LOOKUP_FILTER,
];

/// ILPV (the default method) and classic LPV.
pub const METHODS: &[MethodEntry] = &[
    MethodEntry {
        name: "ilpv",
        description: "seed 000's incremental light propagation volumes (26 neighbours, blended across frames)",
        default: true,
        settings: ILPV_SETTINGS,
        settle_frames: ilpv_settle_frames,
        profile_axis: Some("lattice"),
        create: create_ilpv,
    },
    MethodEntry {
        name: "lpv",
        description: "classic light propagation volumes (Kaplanyan & Dachsbacher: 6 neighbours, 5 faces)",
        default: false,
        settings: LPV_SETTINGS,
        settle_frames: |_| 1,
        profile_axis: Some("lattice"),
        create: create_lpv,
    },
];

/// Frames until the blend has settled: λ^(frames-1) < 1% (at least 4).
fn ilpv_settle_frames(settings: &Settings) -> u32 {
    settle_frames(settings.float("incremental").unwrap_or(0.0))
}

/// Frames until light from before a change weighs less than 1%: λ^(frames-1) < 0.01.
pub fn settle_frames(incremental: f64) -> u32 {
    if incremental <= 0.0 {
        return 4;
    }
    ((0.01f64.ln() / incremental.ln()).ceil() as u32 + 1).max(4)
}

fn create_ilpv(setup: &Setup, settings: &Settings) -> anyhow::Result<Box<dyn GiMethod>> {
    super::two_scale::create(setup, lpv_settings(Scheme::Ilpv, settings)?)
}

fn create_lpv(setup: &Setup, settings: &Settings) -> anyhow::Result<Box<dyn GiMethod>> {
    Ok(Box::new(Lpv::new(setup, lpv_settings(Scheme::Lpv, settings)?)?))
}

/// The typed settings of `scheme` from the registry's values (settings the scheme does not
/// declare keep their defaults).
pub fn lpv_settings(scheme: Scheme, s: &Settings) -> Result<LpvSettings, InputError> {
    let defaults = LpvSettings::default();
    let float_or = |name: &str, default: f32| -> Result<f32, InputError> {
        if s.has(name) {
            Ok(s.float(name)? as f32)
        } else {
            Ok(default)
        }
    };
    let u32_or = |name: &str, default: u32| -> Result<u32, InputError> {
        if s.has(name) { s.u32(name) } else { Ok(default) }
    };
    let flag = |name: &str| -> Result<bool, InputError> {
        if s.has(name) { s.flag(name) } else { Ok(false) }
    };
    let extinction = match s.has("extinction").then(|| s.text("extinction")).transpose()? {
        Some("thesis") => Extinction::Thesis,
        _ => Extinction::Physical,
    };
    let blocking_lobe = match s.text("blocking-lobe")? {
        "front" => BlockingLobe::Front,
        "back" => BlockingLobe::Back,
        "none" => BlockingLobe::None,
        "oriented" => BlockingLobe::Oriented,
        "projected" => BlockingLobe::Projected,
        "visibility" => BlockingLobe::Visibility,
        _ => BlockingLobe::TwoSided,
    };
    let ilpv_lookup = match s.has("ilpv-lookup").then(|| s.text("ilpv-lookup")).transpose()? {
        Some("final") => IlpvLookup::Final,
        _ => IlpvLookup::Accumulated,
    };
    Ok(LpvSettings {
        scheme,
        lattice: s.u32("lattice")?,
        iterations: s.u32("iterations")?,
        incremental: match scheme {
            Scheme::Ilpv => float_or("incremental", t::DEFAULT_INCREMENTAL)?,
            Scheme::Lpv => 0.0,
        },
        rsm: s.u32("rsm")?,
        absorption: float_or("absorption", defaults.absorption)?,
        scattering: float_or("scattering", defaults.scattering)?,
        extinction,
        blocking_lobe,
        blocking_strength: float_or("blocking-strength", defaults.blocking_strength)?,
        first_step_unblocked: !flag("block-first-step")?,
        // "auto" names no kernel: the autotune chooses.
        kernel: match s.has("kernel").then(|| s.text("kernel")).transpose()? {
            Some(name) => Kernel::ALL.into_iter().find(|k| k.name() == name),
            None => None,
        },
        channels: match s.has("channel-plan").then(|| s.text("channel-plan")).transpose()? {
            Some("separate") => Some(ChannelPlan::Separate),
            Some("fused") => Some(ChannelPlan::Fused),
            _ => None,
        },
        cell_order: match s.has("cell-order").then(|| s.text("cell-order")).transpose()? {
            Some("rows") => Some(CellOrder::Rows),
            Some("columns") => Some(CellOrder::Columns),
            _ => None,
        },
        clamp_compensation: !flag("no-clamp-compensation")?,
        ilpv_lookup,
        inject_offset: float_or("inject-offset", defaults.inject_offset)?,
        inject_toward: match s.has("inject-toward").then(|| s.text("inject-toward")).transpose()? {
            Some("light") => InjectToward::Light,
            _ => InjectToward::Normal,
        },
        injection: match s.has("injection").then(|| s.text("injection")).transpose()? {
            Some("fixed") => Injection::Fixed,
            _ => Injection::Float,
        },
        lookup_offset: float_or("lookup-offset", defaults.lookup_offset)?,
        lookup_resolution: match s.has("lookup-resolution").then(|| s.text("lookup-resolution")).transpose()? {
            Some("half") => LookupResolution::Half,
            Some(_) => LookupResolution::Full,
            None => defaults.lookup_resolution,
        },
        lookup_filter: match s.has("lookup-filter").then(|| s.text("lookup-filter")).transpose()? {
            Some("sampler") => Some(LookupFilter::Sampler),
            Some("texels") => Some(LookupFilter::Texels),
            Some("shared-texels") => Some(LookupFilter::SharedTexels),
            Some(_) => None,
            None => defaults.lookup_filter,
        },
        far_lattice: match s.has("far-lattice").then(|| s.text("far-lattice")).transpose()? {
            Some(text) => far_lattice(text)?,
            None => defaults.far_lattice,
        },
        near_steps: u32_or("near-steps", defaults.near_steps)?,
        far_injection: float_or("far-injection", defaults.far_injection)?,
    })
}

/// `--far-lattice`: off, auto or a cell count.
fn far_lattice(text: &str) -> Result<FarLattice, InputError> {
    match text {
        "off" | "0" => Ok(FarLattice::Off),
        "auto" => Ok(FarLattice::Auto),
        cells => match cells.parse::<u32>() {
            Ok(n) if n <= super::lattice::MAX_CELLS => Ok(FarLattice::Cells(n)),
            _ => Err(InputError::new(format!(
                "--far-lattice {text} is neither off, auto nor a cell count in 1..={}",
                super::lattice::MAX_CELLS
            ))),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registered_defaults_are_the_technique_defaults() {
        for (entry, scheme) in METHODS.iter().zip([Scheme::Ilpv, Scheme::Lpv]) {
            let settings = match Settings::defaults(entry.settings) {
                Ok(s) => s,
                Err(e) => panic!("{e}"),
            };
            let typed = match lpv_settings(scheme, &settings) {
                Ok(s) => s,
                Err(e) => panic!("{e}"),
            };
            let expected = LpvSettings {
                scheme,
                incremental: if scheme == Scheme::Ilpv {
                    t::DEFAULT_INCREMENTAL
                } else {
                    0.0
                },
                ..LpvSettings::default()
            };
            assert_eq!(format!("{typed:?}"), format!("{expected:?}"));
        }
    }

    #[test]
    fn ilpv_runs_until_the_blend_settles() {
        assert_eq!(settle_frames(0.0), 4);
        assert_eq!(settle_frames(0.5), 8);
        assert!(0.9f64.powi(settle_frames(0.9) as i32 - 1) < 0.01);
    }
}
