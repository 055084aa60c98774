//! The raster frame: what it renders into (eyes, views, G-buffers), its own passes (shadow
//! maps, G-buffer, direct light, tone mapping), THE frame that orders them around a GI method,
//! and the loop that runs frames and reads their profile.

pub mod cost;
pub mod frame;
pub mod full_screen;
pub mod part_ledger;
pub mod passes;
pub mod runner;
pub mod targets;

pub use frame::{Epilogue, Frame, FrameOptions, SubmitPlan};
pub use targets::{Eye, GBuffer, MAX_IMAGE_SIDE, View, check_image_size};
