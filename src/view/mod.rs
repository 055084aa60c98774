//! The windowed renderer's parts that are not glue: the fly camera, the CAVE's off-axis walls,
//! the text overlay and the window outputs (swapchain, composed image, tiles). `vkgi view`
//! (src/app/view.rs) drives them from winit's event loop.

pub mod cave;
pub mod drag;
pub mod fly;
pub mod keys;
pub mod output;
pub mod overlay;
