//! The device's achievable limits, measured with micro-kernels and the same timestamp profiler
//! as every pass: memory bandwidth (a vec4 copy) and arithmetic rate (vec4 FMA chains). A limit
//! is the best the probe finds, and a pass must not beat it: the FMA probe keeps independent
//! vec4 chains unrolled 32 deep, which measured 5x the rate of four chains in a plain loop (a
//! fused propagation step had beaten that), and runs with two and with four chains, the faster
//! counting: two (eight 8-wide registers on lavapipe) hid the FMA latency on the Intel Xeons,
//! and on an AMD EPYC four measured 1.1-1.2x two's rate (an ILPV step had beaten two's); the
//! copy runs twice, reading its source as a storage buffer and as texels, and the faster counts
//! (texels on lavapipe, 1.35x).

use serde::Serialize;

use crate::gpu::dispatch::MAX_WORKGROUPS_X;
use crate::gpu::frames::FrameRing;
use crate::gpu::{Binding, BufferDesc, ComputePass, ComputePipeline, Gpu, Specialization};
use crate::shader_shared as ids;
use crate::shaders;

#[derive(Clone, Copy, Debug, Serialize)]
pub struct DeviceLimits {
    /// Bytes moved per nanosecond (read + write) by the copy kernel.
    pub bandwidth_bytes_per_ns: f64,
    /// Floating-point operations per nanosecond of the FMA kernel.
    pub flops_per_ns: f64,
}

impl DeviceLimits {
    /// The better of two measurements, rate by rate (a limit is the best the device does).
    pub fn best(self, other: DeviceLimits) -> DeviceLimits {
        DeviceLimits {
            bandwidth_bytes_per_ns: self
                .bandwidth_bytes_per_ns
                .max(other.bandwidth_bytes_per_ns),
            flops_per_ns: self.flops_per_ns.max(other.flops_per_ns),
        }
    }

    /// The shortest time a step moving `bytes` and computing `flops` can take (ns).
    pub fn bound_ns(&self, bytes: f64, flops: f64) -> f64 {
        (bytes / self.bandwidth_bytes_per_ns).max(flops / self.flops_per_ns)
    }
}

crate::push_constants! {
    struct CopyPush {
        count: u32,
    }
}

crate::push_constants! {
    struct FmaPush {
        count: u32,
        iterations: u32,
    }
}

/// Runs per probe; the fastest is used: a limit is the best the device does (on a shared CPU
/// the median of five moved by up to 2x from one process to the next, with other load).
const RUNS: u32 = 7;
/// Bytes per buffer of the bandwidth probe (less where the dispatch limit or the device's
/// storage-buffer range is lower).
const STREAM_BYTES: u64 = 64 << 20;
/// The arithmetic probe grows until one run takes at least this long, so timer resolution does
/// not matter.
const MIN_RUN_NS: f64 = 2e6;
/// The arithmetic probe's independent vec4 chains per invocation, each count tried.
const FMA_CHAINS: [u32; 2] = [2, 4];

/// The shortest GPU time (ns) of `RUNS` runs of `record`.
fn fastest_ns(
    gpu: &Gpu,
    name: &'static str,
    record: &dyn Fn(&mut crate::gpu::Recorder) -> crate::gpu::GpuResult<()>,
) -> anyhow::Result<f64> {
    let mut ring = FrameRing::new(gpu, 2)?;
    for _ in 0..RUNS {
        ring.submit_frame(gpu, &gpu.queues.graphics, &[], record)?;
    }
    ring.finish()?;
    let report = ring.profiler.report();
    report
        .passes
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.min_ns)
        .filter(|t| *t > 0.0)
        .ok_or_else(|| anyhow::anyhow!("the {name} probe produced no timestamps"))
}

/// Bytes per ns a copy of `count` vec4s moves (read + write), its source read as texels or as a
/// storage buffer.
fn copy_bandwidth(gpu: &Gpu, count: u64, texels: bool) -> anyhow::Result<f64> {
    let none = Specialization::new();
    let bytes = count * 16;
    let (name, spirv, source_desc) = match texels {
        true => (
            "bandwidth probe (texels)",
            shaders::LIMITS_COPY_TEXELS_COMP,
            BufferDesc::storage_texels("probe source", bytes),
        ),
        false => (
            "bandwidth probe",
            shaders::LIMITS_COPY_COMP,
            BufferDesc::storage("probe source", bytes),
        ),
    };
    let copy = ComputePipeline::new(gpu, name, spirv, &none)?;
    let source = gpu.create_buffer(&source_desc)?;
    let destination = gpu.create_buffer(&BufferDesc::storage("probe destination", bytes))?;
    let push = CopyPush {
        count: count as u32,
    };
    let ns = fastest_ns(gpu, name, &|rec| {
        let source = match texels {
            true => Binding::texels(ids::LIMITS_SOURCE, &source),
            false => Binding::read(ids::LIMITS_SOURCE, &source),
        };
        rec.compute(&ComputePass {
            name,
            pipeline: &copy,
            bindings: &[
                source,
                Binding::write(ids::LIMITS_DESTINATION, &destination),
            ],
            push: &push,
            threads: [count as u32, 1, 1],
        })
    })?;
    Ok(2.0 * bytes as f64 / ns)
}

/// Flops per ns of the FMA probe with `chains` independent vec4 chains per invocation.
fn fma_rate(gpu: &Gpu, chains: u32) -> anyhow::Result<f64> {
    let spec = Specialization::new().with_u32(0, chains);
    let fma = ComputePipeline::new(gpu, "arithmetic probe", shaders::LIMITS_FMA_COMP, &spec)?;
    let count: u32 = 1 << 16;
    let destination =
        gpu.create_buffer(&BufferDesc::storage("probe output", u64::from(count) * 16))?;
    let mut iterations: u32 = 4;
    loop {
        let push = FmaPush { count, iterations };
        let ns = fastest_ns(gpu, "arithmetic probe", &|rec| {
            rec.compute(&ComputePass {
                name: "arithmetic probe",
                pipeline: &fma,
                bindings: &[Binding::write(ids::LIMITS_DESTINATION, &destination)],
                push: &push,
                threads: [count, 1, 1],
            })
        })?;
        // Per trip of the loop: chains x unrolled FMAs x 4 components x 2 flops.
        let per_trip = chains * ids::LIMITS_FMA_UNROLL * 8;
        let flops = f64::from(count) * f64::from(iterations) * f64::from(per_trip);
        if ns >= MIN_RUN_NS || iterations >= 1 << 20 {
            return Ok(flops / ns);
        }
        iterations *= 4;
    }
}

/// Measure the device's bandwidth and arithmetic rate.
pub fn measure(gpu: &Gpu) -> anyhow::Result<DeviceLimits> {
    let limit = u64::from(gpu.info.max_storage_buffer_range).min(1 << 28);

    // One copy of buffers of about 64 MiB (or the device's storage-buffer range), beyond a CPU's
    // last-level cache: a size that straddles the cache measured anywhere from 5.7 to 8.9 GB/s
    // here. One vec4 per invocation in a 1-D dispatch: at most 65535 workgroups, the least any
    // device has. (On a GPU the copy takes tens of µs, well above its timer's resolution.)
    let count = (STREAM_BYTES.min(limit) / 16).clamp(
        1,
        u64::from(MAX_WORKGROUPS_X) * u64::from(ids::LINEAR_WORKGROUP),
    );
    let bandwidth = copy_bandwidth(gpu, count, false)?;
    // The texel copy where the device's texel-buffer limit holds the same count.
    let bandwidth = match count <= u64::from(gpu.info.max_texel_buffer_elements) {
        true => bandwidth.max(copy_bandwidth(gpu, count, true)?),
        false => bandwidth,
    };

    let mut rate: f64 = 0.0;
    for chains in FMA_CHAINS {
        rate = rate.max(fma_rate(gpu, chains)?);
    }
    Ok(DeviceLimits {
        bandwidth_bytes_per_ns: bandwidth,
        flops_per_ns: rate,
    })
}
