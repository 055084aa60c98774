//! Which pass voxelises the scene for the shadow cones (spec 001 §4.6): the conservative
//! compute pass every device runs, or the public code's path, a draw of every triangle onto the
//! cube face across its dominant axis with overestimating conservative rasterisation, on
//! devices with VK_EXT_conservative_rasterization. The fragment shader keeps the compute pass's
//! exact column test, so the raster path marks no voxel the compute one does not, and with
//! overestimation (a quarter pixel extra, triangles degenerate after snapping still drawn) it
//! reaches every column the compute pass does; `auto` takes it only on such a device. Without
//! the extension it only reaches columns whose centre a triangle covers, a subset; that mode is
//! there for tests.

use ash::vk;

use super::bindings as ids;
use super::voxels::VoxelGrid;
use crate::error::InputError;
use crate::gpu::{
    Binding, Buffer, Draw, Gpu, GpuResult, Image, ImageDesc, RasterPass, RasterPipeline,
    RasterPipelineDesc, Recorder,
};
use crate::shaders;

crate::push_constants! {
    struct VoxelizeRasterPush {
        lo_voxel: [f32; 4],
        resolution: u32,
    }
}

/// `--voxelizer`: auto picks raster where the device rasterises conservatively.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VoxelizerChoice {
    Auto,
    Compute,
    Raster,
}

impl VoxelizerChoice {
    pub fn parse(text: &str) -> Result<VoxelizerChoice, InputError> {
        match text {
            "auto" => Ok(VoxelizerChoice::Auto),
            "compute" => Ok(VoxelizerChoice::Compute),
            "raster" => Ok(VoxelizerChoice::Raster),
            other => Err(InputError::new(format!(
                "--voxelizer {other}: use auto, compute or raster"
            ))),
        }
    }
}

/// The raster voxelisation's pipeline and the attachment that sizes its viewport (one texel per
/// voxel column; its contents are never read).
pub struct RasterVoxelizer {
    pipeline: RasterPipeline,
    columns: Image,
    /// Whether the device overestimates coverage (else the raster path is not conservative).
    pub conservative: bool,
}

impl RasterVoxelizer {
    /// The raster voxelizer for `choice` on this device, or None for the compute pass.
    pub fn new(
        gpu: &Gpu,
        choice: VoxelizerChoice,
        grid: &VoxelGrid,
    ) -> anyhow::Result<Option<RasterVoxelizer>> {
        let device = gpu.info.conservative_rasterization;
        let conservative = device.is_some();
        let stores = gpu.info.fragment_stores_and_atomics;
        let raster = match choice {
            VoxelizerChoice::Compute => false,
            VoxelizerChoice::Auto => {
                stores && device.is_some_and(|c| c.degenerate_triangles_rasterized)
            }
            VoxelizerChoice::Raster if !stores => {
                return Err(InputError::new(
                    "--voxelizer raster: the device cannot write storage buffers from fragment shaders (fragmentStoresAndAtomics)",
                )
                .into());
            }
            VoxelizerChoice::Raster => true,
        };
        if !raster {
            return Ok(None);
        }
        let format = vk::Format::R8_UNORM;
        let pipeline = RasterPipeline::new(
            gpu,
            &RasterPipelineDesc {
                name: "rv voxelize raster",
                vertex: shaders::GI_RADIANCE_VOLUMES_VOXELIZE_RASTER_VERT,
                fragment: Some(shaders::GI_RADIANCE_VOLUMES_VOXELIZE_RASTER_FRAG),
                color_formats: &[format],
                depth: None,
                depth_bias: None,
                additive_blend: false,
                conservative,
                specialization: &crate::gpu::Specialization::new(),
            },
        )?;
        let side = grid.resolution;
        let columns = gpu.create_image(&ImageDesc::new_2d(
            "rv voxel columns",
            format,
            side,
            side,
            vk::ImageUsageFlags::COLOR_ATTACHMENT,
        ))?;
        Ok(Some(RasterVoxelizer {
            pipeline,
            columns,
            conservative,
        }))
    }

    /// Draw the `vertex_count` vertices of the scene's triangles into `target`.
    pub fn record(
        &self,
        rec: &mut Recorder,
        (vertices, triangles, vertex_count): (&Buffer, &Buffer, u32),
        grid: &VoxelGrid,
        target: &Buffer,
    ) -> GpuResult<()> {
        rec.raster(&RasterPass {
            name: "rv voxelize raster",
            pipeline: &self.pipeline,
            bindings: &[
                Binding::read(ids::RV_VERTICES, vertices),
                Binding::read(ids::RV_TRIANGLES, triangles),
                Binding::write(ids::RV_VOXEL_TARGET, target),
            ],
            push: &VoxelizeRasterPush {
                lo_voxel: grid.min.extend(grid.voxel).to_array(),
                resolution: grid.resolution,
            },
            color: &[(&self.columns, 0, [0.0; 4])],
            depth: None,
            draw: Draw::Vertices(vertex_count),
            keep_contents: false,
        })
    }
}
