//! GPU timestamps per pass, in a ring of query pools (one per frame in flight).
//!
//! A frame's queries are read only after that frame's fence has signalled, and without
//! `VK_QUERY_RESULT_WAIT_BIT`, so reading never stalls the CPU on fresh queries. Deltas are
//! masked with the `timestampValidBits` of the queue family each scope ran on (wrap-safe), zero
//! or inverted pairs are dropped, and ticks become nanoseconds through `timestampPeriod`. Every
//! scope carries its [`ScopeTag`], so reports select passes by method, stage, part and step.

use std::sync::Arc;

use ash::vk;
use serde::Serialize;

use super::context::{DeviceShared, Gpu};
use super::scope::{ScopeTag, Stage};
use super::{GpuResult, vk_err};

/// Timestamp pairs a frame can hold (passes per frame): radiosity's pd mode records about 120
/// passes per shot (importance shot, radiosity shot and table deliveries, 16 locations each),
/// so 8 shots a frame need about 1000. A pool of 16 Ki queries is 128 KiB per frame in flight.
const SCOPES_PER_FRAME: u32 = 8192;
/// The name of the scope that spans the whole frame.
pub const FRAME_SCOPE: &str = "frame";

/// The query pool of one frame in flight, and the tags and queue families of the scopes
/// recorded into it.
pub struct FrameQueries {
    pool: vk::QueryPool,
    scopes: Vec<(ScopeTag, u32)>,
    /// Timestamp bits per queue family (0: the family has no timestamps).
    valid_bits: Vec<u32>,
    /// Scopes that did not fit into the pool this frame.
    overflowed: u32,
}

impl FrameQueries {
    /// Start a timestamp scope on a command buffer of queue family `family`; None when the pool
    /// is full (the scope goes untimed and counted) or the family has no timestamps.
    pub(crate) fn begin(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        family: u32,
        tag: ScopeTag,
    ) -> Option<u32> {
        if self.valid_bits.get(family as usize).copied().unwrap_or(0) == 0 {
            return None;
        }
        let index = self.scopes.len() as u32;
        if index >= SCOPES_PER_FRAME {
            self.overflowed += 1;
            return None;
        }
        self.scopes.push((tag, family));
        // SAFETY: query 2*index was reset at the start of this frame and is written once.
        unsafe {
            device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                2 * index,
            )
        };
        Some(index)
    }

    pub(crate) fn end(&mut self, device: &ash::Device, cmd: vk::CommandBuffer, index: u32) {
        // SAFETY: as in `begin`, for the scope's second query.
        unsafe {
            device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                2 * index + 1,
            )
        };
    }
}

/// One timed scope of one frame, in nanoseconds from the first collected frame's start.
#[derive(Clone, Debug, Serialize)]
pub struct ScopeSample {
    pub name: String,
    pub tag: ScopeTag,
    pub frame: u64,
    pub start_ns: f64,
    pub duration_ns: f64,
}

/// Statistics of one pass over the collected frames.
#[derive(Clone, Debug, Serialize)]
pub struct PassTiming {
    pub name: String,
    /// The tag of the pass's first sample (passes of one name share method, stage and pass).
    pub tag: ScopeTag,
    /// Times the pass ran in total (a pass may run several times per frame).
    pub samples: usize,
    /// Per-frame sums of the pass's time (ns), one per frame it ran in.
    pub per_frame_ns: Vec<f64>,
    pub avg_ns: f64,
    pub median_ns: f64,
    pub min_ns: f64,
    pub max_ns: f64,
    /// Share of the average frame time.
    pub percent_of_frame: f64,
}

/// What the profiler measured, ready to print or serialise.
#[derive(Clone, Debug, Serialize)]
pub struct ProfileReport {
    pub device: String,
    pub frames: u64,
    /// Frames whose queries came back incomplete or inverted and were dropped.
    pub dropped_scopes: u64,
    pub passes: Vec<PassTiming>,
    pub frame: Option<PassTiming>,
    /// Notes about how the profile was taken (queue plan, tile sizes, missing timestamps).
    pub notes: Vec<String>,
}

pub struct Profiler {
    shared: Arc<DeviceShared>,
    slots: Vec<FrameQueries>,
    slot_frame: Vec<Option<u64>>,
    period_ns: f64,
    enabled: bool,
    origin_ticks: Option<u64>,
    samples: Vec<ScopeSample>,
    frames_collected: u64,
    dropped: u64,
    device: String,
    notes: Vec<String>,
}

impl Profiler {
    /// A profiler with one query pool per frame in flight, for work submitted to the queues of
    /// the GPU's queue plan.
    pub fn new(gpu: &Gpu, frames_in_flight: usize) -> GpuResult<Profiler> {
        let plan = &gpu.queues;
        let mut valid_bits = Vec::new();
        for queue in std::iter::once(&plan.graphics).chain(&plan.async_compute) {
            let family = queue.family as usize;
            if valid_bits.len() <= family {
                valid_bits.resize(family + 1, 0);
            }
            valid_bits[family] = queue.timestamp_valid_bits;
        }
        let enabled = plan.graphics.timestamp_valid_bits > 0 && gpu.info.timestamp_period_ns > 0.0;
        let mut notes = Vec::new();
        for (family, &bits) in valid_bits.iter().enumerate() {
            let used = std::iter::once(&plan.graphics)
                .chain(&plan.async_compute)
                .any(|q| q.family as usize == family);
            if used && bits == 0 {
                notes.push(format!(
                    "queue family {family} has no timestamps (timestampValidBits = 0): its passes are not timed"
                ));
            }
        }
        let mut profiler = Profiler {
            shared: gpu.shared.clone(),
            slots: Vec::new(),
            slot_frame: vec![None; frames_in_flight],
            period_ns: gpu.info.timestamp_period_ns,
            enabled,
            origin_ticks: None,
            samples: Vec::new(),
            frames_collected: 0,
            dropped: 0,
            device: gpu.info.name.clone(),
            notes,
        };
        if enabled {
            for _ in 0..frames_in_flight {
                let info = vk::QueryPoolCreateInfo::default()
                    .query_type(vk::QueryType::TIMESTAMP)
                    .query_count(2 * SCOPES_PER_FRAME);
                // SAFETY: valid create info; destroyed in Drop.
                let pool = unsafe { gpu.shared.device.create_query_pool(&info, None) }
                    .map_err(vk_err("creating a timestamp query pool"))?;
                profiler.slots.push(FrameQueries {
                    pool,
                    scopes: Vec::new(),
                    valid_bits: valid_bits.clone(),
                    overflowed: 0,
                });
            }
        }
        Ok(profiler)
    }

    pub fn add_note(&mut self, note: impl Into<String>) {
        let note = note.into();
        if !self.notes.contains(&note) {
            self.notes.push(note);
        }
    }

    /// Start recording frame `frame` into `slot`: resets that slot's queries in `cmd`.
    /// The caller must have collected the slot's previous frame (its fence has signalled).
    pub fn begin_frame(
        &mut self,
        slot: usize,
        frame: u64,
        cmd: vk::CommandBuffer,
    ) -> Option<&mut FrameQueries> {
        if !self.enabled {
            return None;
        }
        self.slot_frame[slot] = Some(frame);
        let queries = &mut self.slots[slot];
        queries.scopes.clear();
        queries.overflowed = 0;
        // SAFETY: the slot's previous frame has completed (its fence signalled and it was
        // collected), so no pending command uses these queries.
        unsafe {
            self.shared
                .device
                .cmd_reset_query_pool(cmd, queries.pool, 0, 2 * SCOPES_PER_FRAME)
        };
        Some(queries)
    }

    /// The queries of the frame being recorded in `slot`, for a later part of that frame.
    pub fn frame_queries(&mut self, slot: usize) -> Option<&mut FrameQueries> {
        if !self.enabled || self.slot_frame[slot].is_none() {
            return None;
        }
        Some(&mut self.slots[slot])
    }

    /// Collect `slot` if `fence` (the fence of the slot's frame) has signalled; returns whether
    /// results were collected. Never waits: an unsignalled fence means "try later".
    pub fn collect_if_ready(&mut self, slot: usize, fence: vk::Fence) -> GpuResult<bool> {
        if !self.enabled || self.slot_frame[slot].is_none() {
            return Ok(true);
        }
        // SAFETY: querying the status of a live fence does not block.
        let signalled = unsafe { self.shared.device.get_fence_status(fence) }
            .map_err(vk_err("querying a frame fence"))?;
        if !signalled {
            return Ok(false);
        }
        self.read_slot(slot)?;
        Ok(true)
    }

    fn read_slot(&mut self, slot: usize) -> GpuResult<()> {
        let Some(frame) = self.slot_frame[slot].take() else {
            return Ok(());
        };
        let queries = &self.slots[slot];
        let count = queries.scopes.len();
        self.dropped += u64::from(queries.overflowed);
        if count == 0 {
            return Ok(());
        }
        let mut results = vec![[0u64; 2]; 2 * count];
        // SAFETY: the frame's fence has signalled, so these queries were written; no WAIT flag,
        // availability is returned alongside each value.
        let status = unsafe {
            self.shared.device.get_query_pool_results(
                queries.pool,
                0,
                &mut results,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY,
            )
        };
        match status {
            Ok(()) | Err(vk::Result::NOT_READY) => {}
            Err(e) => return Err(vk_err("reading timestamp queries")(e)),
        }
        let scopes = queries.scopes.clone();
        let valid_bits = queries.valid_bits.clone();
        let frame_family = scopes.first().map_or(0, |s| s.1);
        let mask = |family: u32| {
            let bits = valid_bits[family as usize];
            if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            }
        };
        let frame_mask = mask(frame_family);
        let mut any = false;
        for (index, (tag, family)) in scopes.into_iter().enumerate() {
            let valid_mask = mask(family);
            let [start, start_ok] = results[2 * index];
            let [end, end_ok] = results[2 * index + 1];
            let Some(ticks) = timestamp_delta(valid_mask, [start, start_ok], [end, end_ok]) else {
                self.dropped += 1;
                continue;
            };
            // Start times are placed on the frame's (first scope's) timeline; queues of one
            // device share the timestamp clock, masked to the narrower width.
            let start = start & valid_mask & frame_mask;
            let origin = *self.origin_ticks.get_or_insert(start);
            let since_origin = start.wrapping_sub(origin) & valid_mask & frame_mask;
            self.samples.push(ScopeSample {
                name: tag.name(),
                tag,
                frame,
                start_ns: since_origin as f64 * self.period_ns,
                duration_ns: ticks as f64 * self.period_ns,
            });
            any = true;
        }
        if any {
            self.frames_collected += 1;
        }
        Ok(())
    }

    /// Every collected scope sample, in collection order.
    pub fn samples(&self) -> &[ScopeSample] {
        &self.samples
    }

    pub fn frames_collected(&self) -> u64 {
        self.frames_collected
    }

    /// Forget everything collected so far (e.g. after warm-up frames).
    pub fn clear(&mut self) {
        self.samples.clear();
        self.frames_collected = 0;
        self.dropped = 0;
    }

    pub fn report(&self) -> ProfileReport {
        let mut order: Vec<String> = Vec::new();
        for s in &self.samples {
            if !order.contains(&s.name) {
                order.push(s.name.clone());
            }
        }
        let stats = |name: &str| -> PassTiming {
            let mut per_frame: Vec<(u64, f64)> = Vec::new();
            let mut count = 0;
            for s in self.samples.iter().filter(|s| s.name == name) {
                count += 1;
                match per_frame.iter_mut().find(|(f, _)| *f == s.frame) {
                    Some(entry) => entry.1 += s.duration_ns,
                    None => per_frame.push((s.frame, s.duration_ns)),
                }
            }
            let values: Vec<f64> = per_frame.iter().map(|p| p.1).collect();
            let mut timing = summarize(name, count, values);
            if let Some(first) = self.samples.iter().find(|s| s.name == name) {
                timing.tag = first.tag;
            }
            timing
        };
        let frame = order
            .iter()
            .any(|n| n == FRAME_SCOPE)
            .then(|| stats(FRAME_SCOPE));
        let frame_avg = frame.as_ref().map_or(0.0, |f| f.avg_ns);
        let passes = order
            .iter()
            .filter(|n| n.as_str() != FRAME_SCOPE)
            .map(|n| {
                let mut t = stats(n);
                t.percent_of_frame = if frame_avg > 0.0 {
                    100.0 * t.avg_ns / frame_avg
                } else {
                    0.0
                };
                t
            })
            .collect();
        ProfileReport {
            device: self.device.clone(),
            frames: self.frames_collected,
            dropped_scopes: self.dropped,
            passes,
            frame: frame.map(|mut f| {
                f.percent_of_frame = 100.0;
                f
            }),
            notes: self.notes.clone(),
        }
    }

    /// A Chrome trace (chrome://tracing, Perfetto) of every collected scope.
    pub fn chrome_trace(&self) -> serde_json::Value {
        let events: Vec<serde_json::Value> = self
            .samples
            .iter()
            .map(|s| {
                serde_json::json!({
                    "name": s.name,
                    "cat": "gpu",
                    "ph": "X",
                    "ts": s.start_ns / 1000.0,
                    "dur": s.duration_ns / 1000.0,
                    "pid": 1,
                    "tid": match (s.tag.stage, s.tag.part) {
                        (Stage::Frame, _) => 0,
                        (_, Some(part)) => 2 + part.index,
                        _ => 1,
                    },
                    "args": { "frame": s.frame },
                })
            })
            .collect();
        serde_json::json!({ "traceEvents": events, "displayTimeUnit": "ns" })
    }
}

impl Drop for Profiler {
    fn drop(&mut self) {
        for slot in &self.slots {
            // SAFETY: the frame ring waits for its fences before dropping the profiler, so no
            // pending command uses the pools.
            unsafe { self.shared.device.destroy_query_pool(slot.pool, None) };
        }
    }
}

/// Ticks between two `[value, available]` timestamps: masked to the valid bits, so a counter
/// wrap still gives the right difference; None if either is unavailable, the delta is zero, or
/// it is inverted (a "negative" delta shows up as more than half the counter range).
pub fn timestamp_delta(valid_mask: u64, start: [u64; 2], end: [u64; 2]) -> Option<u64> {
    if start[1] == 0 || end[1] == 0 {
        return None;
    }
    let delta = end[0].wrapping_sub(start[0]) & valid_mask;
    (delta != 0 && delta <= valid_mask / 2).then_some(delta)
}

/// Median, min, max and mean of per-frame values.
pub fn summarize(name: &str, samples: usize, mut values: Vec<f64>) -> PassTiming {
    values.retain(|v| v.is_finite());
    let per_frame = values.clone();
    values.sort_by(|a, b| a.total_cmp(b));
    let n = values.len();
    let median = match n {
        0 => 0.0,
        _ if n % 2 == 1 => values[n / 2],
        _ => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    };
    PassTiming {
        name: name.to_string(),
        tag: ScopeTag::default(),
        samples,
        per_frame_ns: per_frame,
        avg_ns: if n > 0 {
            values.iter().sum::<f64>() / n as f64
        } else {
            0.0
        },
        median_ns: median,
        min_ns: values.first().copied().unwrap_or(0.0),
        max_ns: values.last().copied().unwrap_or(0.0),
        percent_of_frame: 0.0,
    }
}

impl ProfileReport {
    /// The per-pass table: average, median, min and max nanoseconds and share of the frame.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "GPU profile on {} over {} frame(s)",
            self.device, self.frames
        );
        for note in &self.notes {
            let _ = writeln!(out, "  {note}");
        }
        let width = self
            .passes
            .iter()
            .map(|p| p.name.len())
            .chain([12])
            .max()
            .unwrap_or(12);
        let _ = writeln!(
            out,
            "{:<width$} {:>14} {:>14} {:>14} {:>14} {:>7}",
            "pass", "avg ns", "median ns", "min ns", "max ns", "%"
        );
        let row = |out: &mut String, t: &PassTiming| {
            let _ = writeln!(
                out,
                "{:<width$} {:>14.0} {:>14.0} {:>14.0} {:>14.0} {:>6.1}%",
                t.name, t.avg_ns, t.median_ns, t.min_ns, t.max_ns, t.percent_of_frame
            );
        };
        for p in &self.passes {
            row(&mut out, p);
        }
        if let Some(frame) = &self.frame {
            row(&mut out, frame);
        }
        if self.dropped_scopes > 0 {
            let _ = writeln!(
                out,
                "  {} scope(s) dropped (unavailable or inverted)",
                self.dropped_scopes
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamp_deltas_survive_wrap_and_drop_bad_pairs() {
        let mask36 = (1u64 << 36) - 1;
        // A 36-bit counter that wrapped between start and end.
        assert_eq!(timestamp_delta(mask36, [mask36 - 9, 1], [5, 1]), Some(15));
        assert_eq!(timestamp_delta(u64::MAX, [100, 1], [250, 1]), Some(150));
        assert_eq!(timestamp_delta(u64::MAX, [100, 1], [100, 1]), None, "zero");
        assert_eq!(
            timestamp_delta(u64::MAX, [250, 1], [100, 1]),
            None,
            "inverted"
        );
        assert_eq!(
            timestamp_delta(mask36, [250, 1], [100, 1]),
            None,
            "inverted, 36 bits"
        );
        assert_eq!(
            timestamp_delta(u64::MAX, [100, 0], [250, 1]),
            None,
            "unavailable"
        );
    }

    #[test]
    fn summarize_takes_median_of_even_and_odd_counts() {
        let t = summarize("a", 3, vec![3.0, 1.0, 2.0]);
        assert_eq!(
            (t.median_ns, t.min_ns, t.max_ns, t.avg_ns),
            (2.0, 1.0, 3.0, 2.0)
        );
        let t = summarize("a", 4, vec![4.0, 1.0, 2.0, 3.0]);
        assert_eq!(t.median_ns, 2.5);
    }
}
