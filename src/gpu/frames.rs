//! Command buffers and fences: the ring of frames in flight the frame loop records into, and
//! one-shot submissions for uploads and readbacks.

use std::sync::Arc;

use ash::vk;

use super::context::{DeviceShared, Gpu, Queue};
use super::pass::Recorder;
use super::profiler::{FRAME_SCOPE, Profiler};
use super::{GpuError, GpuResult, vk_err};

struct Slot {
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
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

/// Frames in flight on one queue: frame N reuses the command buffer and query pool of frame
/// N - frames_in_flight only after that frame's fence has signalled.
pub struct FrameRing {
    shared: Arc<DeviceShared>,
    queue: Queue,
    slots: Vec<Slot>,
    frame: u64,
    pub profiler: Profiler,
}

impl FrameRing {
    pub fn new(gpu: &Gpu, queue: Queue, frames_in_flight: usize) -> GpuResult<FrameRing> {
        let frames_in_flight = frames_in_flight.max(1);
        let profiler = Profiler::new(gpu, frames_in_flight, &queue)?;
        let mut ring = FrameRing {
            shared: gpu.shared.clone(),
            queue,
            slots: Vec::new(),
            frame: 0,
            profiler,
        };
        let device = &gpu.shared.device;
        for _ in 0..frames_in_flight {
            let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(queue.family);
            // SAFETY: valid create info; destroyed in Drop.
            let pool = unsafe { device.create_command_pool(&pool_info, None) }
                .map_err(vk_err("creating a frame command pool"))?;
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            // SAFETY: allocating from the pool just created.
            let cmd = match unsafe { device.allocate_command_buffers(&alloc) } {
                Ok(c) => c[0],
                Err(e) => {
                    // SAFETY: the pool is unused.
                    unsafe { device.destroy_command_pool(pool, None) };
                    return Err(vk_err("allocating a frame command buffer")(e));
                }
            };
            // SAFETY: valid create info; destroyed in Drop.
            let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            {
                Ok(f) => f,
                Err(e) => {
                    // SAFETY: the pool and its buffer are unused.
                    unsafe { device.destroy_command_pool(pool, None) };
                    return Err(vk_err("creating a frame fence")(e));
                }
            };
            ring.slots.push(Slot {
                pool,
                cmd,
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

    /// The slot the next frame will use, and the fence of the frame last submitted from it.
    pub fn next_slot(&self) -> (usize, vk::Fence) {
        let slot = (self.frame % self.slots.len() as u64) as usize;
        (slot, self.slots[slot].fence)
    }

    /// The slot and fence of the frame submitted last (None before the first frame).
    pub fn last_submitted(&self) -> Option<(usize, vk::Fence)> {
        let previous = self.frame.checked_sub(1)?;
        let slot = (previous % self.slots.len() as u64) as usize;
        Some((slot, self.slots[slot].fence))
    }

    /// Record and submit one frame. Waits only for the frame that last used this slot (the
    /// CPU-GPU throttle), then collects its timestamps, which are complete by then.
    pub fn submit_frame<F>(
        &mut self,
        gpu: &Gpu,
        waits: &[SemaphoreWait],
        record: F,
    ) -> GpuResult<()>
    where
        F: FnOnce(&mut Recorder) -> GpuResult<()>,
    {
        let (index, fence) = self.next_slot();
        let device = &self.shared.device;
        if self.slots[index].in_flight {
            // SAFETY: waiting on a fence of a submitted frame.
            unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }
                .map_err(vk_err("waiting for a frame in flight"))?;
            self.profiler.collect_if_ready(index, fence)?;
            // SAFETY: the fence has signalled and is not in use by a pending submission.
            unsafe { device.reset_fences(&[fence]) }.map_err(vk_err("resetting a frame fence"))?;
            self.slots[index].in_flight = false;
        }
        let slot = &self.slots[index];
        // SAFETY: the slot's previous submission has completed, so the pool may be reset.
        unsafe { device.reset_command_pool(slot.pool, vk::CommandPoolResetFlags::empty()) }
            .map_err(vk_err("resetting a frame command pool"))?;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the command buffer is in the initial state after the pool reset.
        unsafe { device.begin_command_buffer(slot.cmd, &begin) }
            .map_err(vk_err("beginning a frame command buffer"))?;
        let cmd = slot.cmd;
        let timer = self.profiler.begin_frame(index, self.frame, cmd);
        let mut recorder = Recorder::new(gpu, cmd, timer);
        let frame_scope = recorder.begin_scope(FRAME_SCOPE);
        let recorded = record(&mut recorder);
        recorder.end_scope(frame_scope);
        // SAFETY: ends the recording begun above (also after a recording error, so the command
        // buffer leaves the recording state; it is then not submitted).
        let ended = unsafe { device.end_command_buffer(cmd) };
        recorded?;
        ended.map_err(vk_err("ending a frame command buffer"))?;
        submit(device, &self.queue, cmd, waits, &[], fence)?;
        self.slots[index].in_flight = true;
        self.frame += 1;
        Ok(())
    }

    /// Wait for every frame in flight and collect their timestamps.
    pub fn finish(&mut self) -> GpuResult<()> {
        let device = &self.shared.device;
        let count = self.slots.len() as u64;
        // Oldest first, so samples stay in frame order.
        for k in 0..count {
            let index = ((self.frame + k) % count) as usize;
            if !self.slots[index].in_flight {
                continue;
            }
            let fence = self.slots[index].fence;
            // SAFETY: waiting on a fence of a submitted frame.
            unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }
                .map_err(vk_err("waiting for the last frames"))?;
            self.profiler.collect_if_ready(index, fence)?;
            // SAFETY: signalled and not in use.
            unsafe { device.reset_fences(&[fence]) }.map_err(vk_err("resetting a frame fence"))?;
            self.slots[index].in_flight = false;
        }
        Ok(())
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
                device.destroy_command_pool(slot.pool, None);
            }
        }
    }
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
        let pool = self
            .one_shot_pool
            .lock()
            .map_err(|_| GpuError::Setup("one-shot command pool lock poisoned".into()))?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is externally synchronised by the mutex held above.
        let cmd = unsafe { device.allocate_command_buffers(&alloc) }
            .map_err(vk_err("allocating a one-shot command buffer"))?[0];
        // SAFETY: valid create info.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) };
        let result = fence
            .map_err(vk_err("creating a one-shot fence"))
            .and_then(|fence| {
                let run = || -> GpuResult<()> {
                    let begin = vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
                    // SAFETY: a freshly allocated command buffer.
                    unsafe { device.begin_command_buffer(cmd, &begin) }
                        .map_err(vk_err("beginning a one-shot command buffer"))?;
                    let mut recorder = Recorder::new(self, cmd, None);
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
            });
        // SAFETY: the command buffer is not pending (completed or never submitted).
        unsafe { device.free_command_buffers(*pool, &[cmd]) };
        result
    }
}
