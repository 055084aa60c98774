//! Command buffers and fences: the ring of frames in flight the frame loop records into, and
//! one-shot submissions for uploads and readbacks.

use std::sync::Arc;

use ash::vk;

use super::context::{DeviceShared, Gpu, Queue};
use super::pass::Recorder;
use super::profiler::{FRAME_SCOPE, Profiler};
use super::scope::{ScopeTag, Stage};
use super::{GpuError, GpuResult, vk_err};

/// Command buffers of one queue family, reused frame after frame.
struct FamilyPool {
    family: u32,
    pool: vk::CommandPool,
    buffers: Vec<vk::CommandBuffer>,
    used: usize,
}

struct Slot {
    pools: Vec<FamilyPool>,
    fence: vk::Fence,
    in_flight: bool,
}

/// A semaphore wait for a submission: wait until `semaphore` reaches `value` before `stage`.
#[derive(Clone, Copy, Debug)]
pub struct SemaphoreWait {
    pub semaphore: vk::Semaphore,
    pub value: u64,
    pub stage: vk::PipelineStageFlags2,
}

/// Frames in flight: frame N reuses the command buffers and query pool of frame
/// N - frames_in_flight only after that frame's fence has signalled. A frame is one or more
/// submissions ("parts"), possibly on different queues, ordered by semaphores; the last part
/// carries the fence, the first resets the frame's timestamp queries.
pub struct FrameRing {
    shared: Arc<DeviceShared>,
    slots: Vec<Slot>,
    frame: u64,
    pub profiler: Profiler,
}

/// A frame being recorded: submit its parts, then [`FrameBuilder::finish`]. A frame dropped
/// unfinished (a recording error after some of its parts were submitted) waits for the device,
/// since only the last part carries the slot's fence: its command buffers are reset when the
/// slot is used again.
pub struct FrameBuilder<'r> {
    ring: &'r mut FrameRing,
    slot: usize,
    first_part: bool,
    frame_scope: Option<u32>,
    /// Parts submitted that no fence of the ring covers yet.
    unfenced: bool,
}

impl FrameRing {
    pub fn new(gpu: &Gpu, frames_in_flight: usize) -> GpuResult<FrameRing> {
        let frames_in_flight = frames_in_flight.max(1);
        let profiler = Profiler::new(gpu, frames_in_flight)?;
        let mut ring = FrameRing {
            shared: gpu.shared.clone(),
            slots: Vec::new(),
            frame: 0,
            profiler,
        };
        for _ in 0..frames_in_flight {
            // SAFETY: valid create info; destroyed in Drop.
            let fence = unsafe {
                gpu.shared
                    .device
                    .create_fence(&vk::FenceCreateInfo::default(), None)
            }
            .map_err(vk_err("creating a frame fence"))?;
            ring.slots.push(Slot {
                pools: Vec::new(),
                fence,
                in_flight: false,
            });
        }
        Ok(ring)
    }

    /// Frames submitted so far.
    pub fn frames_submitted(&self) -> u64 {
        self.frame
    }

    /// The slot and fence of the frame submitted last (None before the first frame).
    pub fn last_submitted(&self) -> Option<(usize, vk::Fence)> {
        let previous = self.frame.checked_sub(1)?;
        let slot = (previous % self.slots.len() as u64) as usize;
        Some((slot, self.slots[slot].fence))
    }

    /// Start the next frame. Waits only for the frame that last used this slot (the CPU-GPU
    /// throttle), then collects its timestamps, which are complete by then.
    pub fn begin_frame(&mut self) -> GpuResult<FrameBuilder<'_>> {
        let slot = (self.frame % self.slots.len() as u64) as usize;
        self.retire(slot)?;
        let device = &self.shared.device;
        for family in &mut self.slots[slot].pools {
            // SAFETY: the slot's previous submissions have completed (retired above).
            unsafe { device.reset_command_pool(family.pool, vk::CommandPoolResetFlags::empty()) }
                .map_err(vk_err("resetting a frame command pool"))?;
            family.used = 0;
        }
        Ok(FrameBuilder {
            ring: self,
            slot,
            first_part: true,
            frame_scope: None,
            unfenced: false,
        })
    }

    /// Record and submit a frame of one part on `queue`.
    pub fn submit_frame<F>(
        &mut self,
        gpu: &Gpu,
        queue: &Queue,
        waits: &[SemaphoreWait],
        record: F,
    ) -> GpuResult<()>
    where
        F: FnOnce(&mut Recorder) -> GpuResult<()>,
    {
        self.begin_frame()?.finish(gpu, queue, waits, &[], record)
    }

    /// Wait for a slot's frame if it is in flight and collect its timestamps.
    fn retire(&mut self, slot: usize) -> GpuResult<()> {
        if !self.slots[slot].in_flight {
            return Ok(());
        }
        let device = &self.shared.device;
        let fence = self.slots[slot].fence;
        // SAFETY: waiting on the fence of a submitted frame.
        unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }
            .map_err(vk_err("waiting for a frame in flight"))?;
        self.profiler.collect_if_ready(slot, fence)?;
        // SAFETY: the fence has signalled and no pending submission uses it.
        unsafe { device.reset_fences(&[fence]) }.map_err(vk_err("resetting a frame fence"))?;
        self.slots[slot].in_flight = false;
        Ok(())
    }

    /// Wait for every frame in flight and collect their timestamps.
    pub fn finish(&mut self) -> GpuResult<()> {
        let count = self.slots.len() as u64;
        // Oldest first, so samples stay in frame order.
        for k in 0..count {
            self.retire(((self.frame + k) % count) as usize)?;
        }
        Ok(())
    }

    /// A command buffer of `family` from the slot's pool, in the recording state.
    fn command_buffer(&mut self, slot: usize, family: u32) -> GpuResult<vk::CommandBuffer> {
        let device = &self.shared.device;
        let pools = &mut self.slots[slot].pools;
        let index = match pools.iter().position(|p| p.family == family) {
            Some(i) => i,
            None => {
                let info = vk::CommandPoolCreateInfo::default().queue_family_index(family);
                // SAFETY: valid create info; destroyed in Drop.
                let pool = unsafe { device.create_command_pool(&info, None) }
                    .map_err(vk_err("creating a frame command pool"))?;
                pools.push(FamilyPool {
                    family,
                    pool,
                    buffers: Vec::new(),
                    used: 0,
                });
                pools.len() - 1
            }
        };
        let family_pool = &mut pools[index];
        if family_pool.used == family_pool.buffers.len() {
            // SAFETY: a pool of this slot, used only from this thread.
            let cmd =
                unsafe { allocate_primary(device, family_pool.pool, "a frame command buffer") }?;
            family_pool.buffers.push(cmd);
        }
        let cmd = family_pool.buffers[family_pool.used];
        family_pool.used += 1;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the pool was reset, so the command buffer is in the initial state.
        unsafe { device.begin_command_buffer(cmd, &begin) }
            .map_err(vk_err("beginning a frame command buffer"))?;
        Ok(cmd)
    }
}

impl FrameBuilder<'_> {
    /// Record one part of the frame and submit it to `queue` after `waits`, signalling
    /// `signals` when done.
    pub fn submit<F>(
        &mut self,
        gpu: &Gpu,
        queue: &Queue,
        waits: &[SemaphoreWait],
        signals: &[(vk::Semaphore, u64)],
        record: F,
    ) -> GpuResult<()>
    where
        F: FnOnce(&mut Recorder) -> GpuResult<()>,
    {
        self.part(gpu, queue, waits, signals, false, record)
    }

    /// The frame-in-flight slot this frame uses (its per-slot resources are free to reuse).
    pub fn slot(&self) -> usize {
        self.slot
    }

    /// Record and submit the frame's last part, which carries the frame's fence and signals
    /// `signals` (e.g. a swapchain image's "rendered" semaphore).
    pub fn finish<F>(
        mut self,
        gpu: &Gpu,
        queue: &Queue,
        waits: &[SemaphoreWait],
        signals: &[(vk::Semaphore, u64)],
        record: F,
    ) -> GpuResult<()>
    where
        F: FnOnce(&mut Recorder) -> GpuResult<()>,
    {
        self.part(gpu, queue, waits, signals, true, record)?;
        self.ring.slots[self.slot].in_flight = true;
        self.ring.frame += 1;
        self.unfenced = false;
        Ok(())
    }

    fn part<F>(
        &mut self,
        gpu: &Gpu,
        queue: &Queue,
        waits: &[SemaphoreWait],
        signals: &[(vk::Semaphore, u64)],
        last: bool,
        record: F,
    ) -> GpuResult<()>
    where
        F: FnOnce(&mut Recorder) -> GpuResult<()>,
    {
        let cmd = self.ring.command_buffer(self.slot, queue.family)?;
        let frame = self.ring.frame;
        let slot = self.slot;
        let timer = if self.first_part {
            self.ring.profiler.begin_frame(slot, frame, cmd)
        } else {
            self.ring.profiler.frame_queries(slot)
        };
        let mut recorder = Recorder::new(gpu, cmd, queue, timer);
        if self.first_part {
            let previous = recorder.set_context(ScopeTag {
                stage: Stage::Frame,
                ..ScopeTag::default()
            });
            self.frame_scope = recorder.begin_scope(FRAME_SCOPE);
            recorder.set_context(previous);
            self.first_part = false;
        }
        let recorded = record(&mut recorder);
        if last {
            recorder.end_scope(self.frame_scope);
        }
        let device = &self.ring.shared.device;
        // SAFETY: ends the recording begun in command_buffer (also after a recording error, so
        // the command buffer leaves the recording state; it is then not submitted).
        let ended = unsafe { device.end_command_buffer(cmd) };
        recorded?;
        ended.map_err(vk_err("ending a frame command buffer"))?;
        let fence = if last {
            self.ring.slots[slot].fence
        } else {
            vk::Fence::null()
        };
        submit(device, queue, cmd, waits, signals, fence)?;
        self.unfenced = !last;
        Ok(())
    }
}

impl Drop for FrameBuilder<'_> {
    fn drop(&mut self) {
        if self.unfenced {
            // SAFETY: waiting for idle has no preconditions; it makes the slot's command
            // buffers free to reset.
            let _ = unsafe { self.ring.shared.device.device_wait_idle() };
        }
    }
}

impl Drop for FrameRing {
    fn drop(&mut self) {
        let device = &self.shared.device;
        for slot in &self.slots {
            // SAFETY: waiting for completion before destroying what the submission uses.
            unsafe {
                if slot.in_flight {
                    let _ = device.wait_for_fences(&[slot.fence], true, u64::MAX);
                }
                device.destroy_fence(slot.fence, None);
                for family in &slot.pools {
                    device.destroy_command_pool(family.pool, None);
                }
            }
        }
    }
}

/// One primary command buffer from `pool`; `what` names it in the error.
///
/// # Safety
/// `pool` belongs to `device` and no other thread uses it during the call.
unsafe fn allocate_primary(
    device: &ash::Device,
    pool: vk::CommandPool,
    what: &str,
) -> GpuResult<vk::CommandBuffer> {
    let alloc = vk::CommandBufferAllocateInfo::default()
        .command_pool(pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(1);
    // SAFETY: the caller guarantees the pool is the device's and externally synchronised.
    let buffers =
        unsafe { device.allocate_command_buffers(&alloc) }.map_err(|result| GpuError::Vulkan {
            what: format!("allocating {what}"),
            result,
        })?;
    Ok(buffers[0])
}

fn submit(
    device: &ash::Device,
    queue: &Queue,
    cmd: vk::CommandBuffer,
    waits: &[SemaphoreWait],
    signals: &[(vk::Semaphore, u64)],
    fence: vk::Fence,
) -> GpuResult<()> {
    let wait_infos: Vec<vk::SemaphoreSubmitInfo> = waits
        .iter()
        .map(|w| {
            vk::SemaphoreSubmitInfo::default()
                .semaphore(w.semaphore)
                .value(w.value)
                .stage_mask(w.stage)
        })
        .collect();
    let signal_infos: Vec<vk::SemaphoreSubmitInfo> = signals
        .iter()
        .map(|&(semaphore, value)| {
            vk::SemaphoreSubmitInfo::default()
                .semaphore(semaphore)
                .value(value)
                .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
        })
        .collect();
    let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
    let submit = vk::SubmitInfo2::default()
        .wait_semaphore_infos(&wait_infos)
        .command_buffer_infos(&cmd_infos)
        .signal_semaphore_infos(&signal_infos);
    // SAFETY: the command buffer is executable; the fence is unsignalled and unused; the queue
    // is only submitted to from this thread.
    unsafe { device.queue_submit2(queue.raw, &[submit], fence) }.map_err(vk_err("submitting work"))
}

/// A timeline semaphore (joins work across queues; host-signalled in tests).
pub struct TimelineSemaphore {
    shared: Arc<DeviceShared>,
    pub raw: vk::Semaphore,
}

impl TimelineSemaphore {
    pub fn new(gpu: &Gpu, initial: u64) -> GpuResult<Self> {
        let mut type_info = vk::SemaphoreTypeCreateInfo::default()
            .semaphore_type(vk::SemaphoreType::TIMELINE)
            .initial_value(initial);
        let info = vk::SemaphoreCreateInfo::default().push_next(&mut type_info);
        // SAFETY: valid create info on a device with timelineSemaphore enabled.
        let raw = unsafe { gpu.shared.device.create_semaphore(&info, None) }
            .map_err(vk_err("creating a timeline semaphore"))?;
        Ok(TimelineSemaphore {
            shared: gpu.shared.clone(),
            raw,
        })
    }

    /// Signal `value` from the host.
    pub fn signal(&self, value: u64) -> GpuResult<()> {
        let info = vk::SemaphoreSignalInfo::default()
            .semaphore(self.raw)
            .value(value);
        // SAFETY: value is greater than the current value (callers count upwards).
        unsafe { self.shared.device.signal_semaphore(&info) }
            .map_err(vk_err("signalling a timeline semaphore"))
    }

    /// Block until the semaphore reaches `value`.
    pub fn wait(&self, value: u64) -> GpuResult<()> {
        let semaphores = [self.raw];
        let values = [value];
        let info = vk::SemaphoreWaitInfo::default()
            .semaphores(&semaphores)
            .values(&values);
        // SAFETY: waiting on a live semaphore.
        unsafe { self.shared.device.wait_semaphores(&info, u64::MAX) }
            .map_err(vk_err("waiting on a timeline semaphore"))
    }
}

impl Drop for TimelineSemaphore {
    fn drop(&mut self) {
        // SAFETY: owners wait for the submissions using the semaphore before dropping it.
        unsafe { self.shared.device.destroy_semaphore(self.raw, None) };
    }
}

impl Gpu {
    /// Record work with `record`, submit it to the graphics queue and wait for it to finish.
    /// For set-up, uploads and readbacks; frames go through a [`FrameRing`].
    pub fn one_shot<F>(&self, record: F) -> GpuResult<()>
    where
        F: FnOnce(&mut Recorder) -> GpuResult<()>,
    {
        let device = &self.shared.device;
        let mut one_shot = self
            .one_shot
            .lock()
            .map_err(|_| GpuError::Setup("one-shot command pool lock poisoned".into()))?;
        // SAFETY: the pool is externally synchronised by the mutex held above, and its command
        // buffer is not pending: every call waited for its submission (or never submitted it).
        unsafe { device.reset_command_pool(one_shot.pool, vk::CommandPoolResetFlags::empty()) }
            .map_err(vk_err("resetting the one-shot command pool"))?;
        // One command buffer, reset with its pool and reused, never freed (see `OneShot`).
        let cmd = match one_shot.buffer {
            Some(cmd) => cmd,
            None => {
                // SAFETY: the pool is externally synchronised by the mutex held above.
                let cmd = unsafe {
                    allocate_primary(device, one_shot.pool, "a one-shot command buffer")
                }?;
                one_shot.buffer = Some(cmd);
                cmd
            }
        };
        // SAFETY: valid create info.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) };
        fence
            .map_err(vk_err("creating a one-shot fence"))
            .and_then(|fence| {
                let run = || -> GpuResult<()> {
                    let begin = vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
                    // SAFETY: the command buffer is in the initial state (its pool was just reset).
                    unsafe { device.begin_command_buffer(cmd, &begin) }
                        .map_err(vk_err("beginning a one-shot command buffer"))?;
                    let mut recorder = Recorder::new(self, cmd, &self.queues.graphics, None);
                    let recorded = record(&mut recorder);
                    // SAFETY: ends the recording begun above.
                    let ended = unsafe { device.end_command_buffer(cmd) };
                    recorded?;
                    ended.map_err(vk_err("ending a one-shot command buffer"))?;
                    submit(device, &self.queues.graphics, cmd, &[], &[], fence)?;
                    // SAFETY: waiting on the fence of the submission above.
                    unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }
                        .map_err(vk_err("waiting for one-shot work"))
                };
                let result = run();
                // SAFETY: the submission (if any) completed: we waited on its fence, or it failed.
                unsafe { device.destroy_fence(fence, None) };
                result
            })
    }
}
