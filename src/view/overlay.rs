//! The window's text overlay: lines of the built-in font in a darkened box at the top left,
//! rasterised on the host into a mask and blended onto the window image by a compute pass.

use gpu_allocator::MemoryLocation;

use crate::font::glyph;
use crate::gpu::{
    Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult, Image, Recorder,
    Specialization,
};
use crate::shader_shared as ids;
use crate::shaders;

/// Screen pixels per font pixel.
const SCALE: u32 = 2;
/// Margin around the text, in screen pixels.
const MARGIN: u32 = 6;
/// Line height in screen pixels (5 font rows, 2 of spacing).
const LINE: u32 = 7 * SCALE;
/// Largest overlay: characters per line and lines.
const MAX_COLUMNS: u32 = 72;
const MAX_LINES: u32 = 40;
/// Distance of the box from the window's top-left corner.
const ORIGIN: [u32; 2] = [8, 8];

/// The mask of `lines`: width, height and one OVERLAY_* value per pixel, row-major. Lines
/// beyond the limits are cut off.
pub fn text_mask(lines: &[String]) -> (u32, u32, Vec<u32>) {
    let lines: Vec<&str> = lines
        .iter()
        .take(MAX_LINES as usize)
        .map(|l| l.as_str())
        .collect();
    let columns = lines
        .iter()
        .map(|l| l.chars().count() as u32)
        .max()
        .unwrap_or(0)
        .min(MAX_COLUMNS);
    if columns == 0 {
        return (0, 0, Vec::new());
    }
    let width = columns * 4 * SCALE + 2 * MARGIN;
    let height = lines.len() as u32 * LINE + 2 * MARGIN - 2 * SCALE;
    let mut mask = vec![ids::OVERLAY_BOX; (width * height) as usize];
    for (row, line) in lines.iter().enumerate() {
        for (column, c) in line.chars().take(columns as usize).enumerate() {
            for (y, bits) in glyph(c).iter().enumerate() {
                for x in 0..3u32 {
                    if bits & (4 >> x) == 0 {
                        continue;
                    }
                    let px = MARGIN + (column as u32 * 4 + x) * SCALE;
                    let py = MARGIN + row as u32 * LINE + y as u32 * SCALE;
                    for dy in 0..SCALE {
                        for dx in 0..SCALE {
                            mask[((py + dy) * width + px + dx) as usize] = ids::OVERLAY_TEXT;
                        }
                    }
                }
            }
        }
    }
    (width, height, mask)
}

crate::push_constants! {
    struct OverlayPush {
        origin: [u32; 2],
        size: [u32; 2],
        target_size: [u32; 2],
    }
}

/// The overlay pass, with one mask buffer per frame in flight (a frame's mask is written only
/// once the frame that last read it has completed).
pub struct Overlay {
    pipeline: ComputePipeline,
    masks: Vec<Buffer>,
    sizes: Vec<(u32, u32)>,
}

impl Overlay {
    pub fn new(gpu: &Gpu, frames_in_flight: usize) -> GpuResult<Overlay> {
        let pipeline = ComputePipeline::new(
            gpu,
            "overlay",
            shaders::VIEW_OVERLAY_COMP,
            &Specialization::new(),
        )?;
        let bytes = u64::from(MAX_COLUMNS * 4 * SCALE + 2 * MARGIN)
            * u64::from(MAX_LINES * LINE + 2 * MARGIN)
            * 4;
        let mut masks = Vec::new();
        for _ in 0..frames_in_flight.max(1) {
            masks.push(gpu.create_buffer(&BufferDesc {
                name: "overlay mask",
                size: bytes,
                usage: ash::vk::BufferUsageFlags::STORAGE_BUFFER,
                location: MemoryLocation::CpuToGpu,
                texels: None,
            })?);
        }
        Ok(Overlay {
            pipeline,
            sizes: vec![(0, 0); masks.len()],
            masks,
        })
    }

    /// Write the text of the frame in `slot` (whose previous frame has completed).
    pub fn set_text(&mut self, slot: usize, lines: &[String]) -> GpuResult<()> {
        let (width, height, mask) = text_mask(lines);
        let slot = slot % self.masks.len();
        if !mask.is_empty() {
            self.masks[slot].write_mapped(0, bytemuck::cast_slice(&mask))?;
        }
        self.sizes[slot] = (width, height);
        Ok(())
    }

    /// Blend the text of `slot` onto `target`.
    pub fn record(&self, rec: &mut Recorder, slot: usize, target: &Image) -> GpuResult<()> {
        let slot = slot % self.masks.len();
        let (width, height) = self.sizes[slot];
        let push = OverlayPush {
            origin: ORIGIN,
            size: [width, height],
            target_size: [target.width(), target.height()],
        };
        rec.compute(&ComputePass {
            name: "overlay",
            pipeline: &self.pipeline,
            bindings: &[
                Binding::image_write(ids::OVERLAY_TARGET, target),
                Binding::read(ids::OVERLAY_MASK, &self.masks[slot]),
            ],
            push: &push,
            threads: [width, height, 1],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_lands_inside_a_box_sized_to_the_longest_line() {
        let (w, h, mask) = text_mask(&["AB".into(), "C".into()]);
        assert_eq!(w, 2 * 4 * SCALE + 2 * MARGIN);
        assert_eq!(h, 2 * LINE + 2 * MARGIN - 2 * SCALE);
        let text = mask.iter().filter(|&&m| m == ids::OVERLAY_TEXT).count() as u32;
        // A and B are 10 font pixels each, C is 7.
        assert_eq!(text, (10 + 10 + 7) * SCALE * SCALE);
        assert_eq!(mask[0], ids::OVERLAY_BOX);
        assert_eq!(text_mask(&[]).2.len(), 0);
    }
}
