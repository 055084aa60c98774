//! A window the renderer shows views in: its surface and swapchain, the image the views are
//! composed into (with the overlay), and where each view goes.

use std::sync::Arc;

use ash::vk;
use winit::window::Window;

use crate::gpu::swapchain::{Acquired, Surface, Swapchain};
use crate::gpu::{Gpu, GpuResult, Image, ImageDesc, Recorder};
use crate::render::Frame;

/// Where a view goes in the window: its index and the square or rectangle it fills
/// (x, y, width, height in window pixels).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub view: usize,
    pub rect: [i32; 4],
}

pub struct Output {
    // Field order is drop order: the swapchain before its surface, both before the window.
    swapchain: Swapchain,
    /// The window image: views blitted into their tiles, then the overlay.
    pub composed: Image,
    pub tiles: Vec<Tile>,
    pub window: Arc<Window>,
}

impl Output {
    pub fn new(
        gpu: &Gpu,
        window: Arc<Window>,
        vsync: bool,
        frames_in_flight: usize,
    ) -> anyhow::Result<Output> {
        use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
        let display = window.display_handle()?.as_raw();
        let handle = window.window_handle()?.as_raw();
        let surface = Arc::new(Surface::new(gpu, display, handle)?);
        let size = window.inner_size();
        let swapchain = Swapchain::new(
            gpu,
            surface,
            (size.width.max(1), size.height.max(1)),
            vsync,
            frames_in_flight,
        )?;
        let composed = composed_image(gpu, swapchain.extent)?;
        Ok(Output {
            swapchain,
            composed,
            tiles: Vec::new(),
            window,
        })
    }

    /// The swapchain's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.swapchain.extent.width, self.swapchain.extent.height)
    }

    /// Rebuild the swapchain and window image for the window's current size. The device must
    /// be idle.
    pub fn resize(&mut self, gpu: &Gpu) -> GpuResult<()> {
        let size = self.window.inner_size();
        self.swapchain.recreate((size.width, size.height))?;
        self.composed = composed_image(gpu, self.swapchain.extent)?;
        Ok(())
    }

    pub fn acquire(&self, slot: usize) -> GpuResult<Option<Acquired>> {
        self.swapchain.acquire(slot)
    }

    /// Compose the views into the window image, leaving the overlay to the caller. The window
    /// is cleared first unless one view fills it.
    pub fn record_compose(&self, rec: &mut Recorder, frame: &Frame) {
        let whole = [
            0,
            0,
            self.composed.width() as i32,
            self.composed.height() as i32,
        ];
        if !self.tiles.iter().any(|tile| tile.rect == whole) {
            rec.clear_image("clear window", &self.composed, [0.0, 0.0, 0.0, 1.0]);
        }
        for tile in &self.tiles {
            let view = &frame.views[tile.view];
            let from = [0, 0, view.width() as i32, view.height() as i32];
            rec.blit("show view", &view.ldr, from, &self.composed, tile.rect);
        }
    }

    /// Copy the window image to the acquired swapchain image.
    pub fn record_present(&self, rec: &mut Recorder, acquired: &Acquired) {
        rec.blit_to_swapchain(&self.composed, acquired.image);
    }

    pub fn swapchain(&self) -> &Swapchain {
        &self.swapchain
    }
}

/// The CAVE's walls tiled as a cross in a window of `width` x `height`: the side of each
/// square wall, and the tiles (views in wall order: front, left, right, floor), centred.
pub fn cave_tiles(width: u32, height: u32) -> (u32, Vec<Tile>) {
    let (columns, rows) = crate::view::cave::TILES;
    let side = (width / columns).min(height / rows).max(1);
    let x0 = (width.saturating_sub(columns * side) / 2) as i32;
    let y0 = (height.saturating_sub(rows * side) / 2) as i32;
    // (column, row) of the front, left, right and floor walls.
    let walls = [(1, 0), (0, 0), (2, 0), (1, 1)];
    let tiles = walls
        .iter()
        .enumerate()
        .map(|(view, &(column, row))| Tile {
            view,
            rect: [
                x0 + column * side as i32,
                y0 + row * side as i32,
                side as i32,
                side as i32,
            ],
        })
        .collect();
    (side, tiles)
}

fn composed_image(gpu: &Gpu, extent: vk::Extent2D) -> GpuResult<Image> {
    gpu.create_image(&ImageDesc::new_2d(
        "window image",
        vk::Format::R8G8B8A8_UNORM,
        extent.width.max(1),
        extent.height.max(1),
        vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cave_tiles_form_a_centred_cross_of_squares() {
        let (side, tiles) = cave_tiles(700, 400);
        assert_eq!(side, 200);
        let rects: Vec<[i32; 4]> = tiles.iter().map(|t| t.rect).collect();
        assert_eq!(
            rects,
            vec![
                [250, 0, 200, 200],
                [50, 0, 200, 200],
                [450, 0, 200, 200],
                [250, 200, 200, 200]
            ]
        );
    }
}
