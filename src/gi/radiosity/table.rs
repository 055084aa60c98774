//! The stored radiosity table of perspective-driven radiosity (spec 004 §6.2–6.5): while a
//! receiver surface is out of the simulated view, each shooting location's unshot radiosity for
//! it is summed into the entry (column of that location, row of that receiver) instead of being
//! shot; when the simulated view widens or moves, the columns holding entries for receivers now
//! in view are delivered one by one, through the location's item buffer, with the disc form
//! factor of the location's area. Column c is shooter × location slots + slot: a surface always
//! shoots the same blocks, so a column is one location of fixed position and area, and its
//! entries can be summed over shots without the thesis's bin over-count (§6.2 note).

use super::bindings as ids;
use crate::error::InputError;
use crate::gpu::dispatch::MAX_WORKGROUPS_X;
use crate::gpu::{Binding, Buffer, BufferDesc, ComputePass, ComputePipeline, Gpu, GpuResult, Recorder, Specialization};
use crate::shaders;

/// Bytes of one entry (`TableEntry` in radiosity.glsl: emitted and reflected, two vec4).
const ENTRY_BYTES: u64 = 32;
/// Bytes of one column's location (`Location` in radiosity.glsl).
const LOCATION_BYTES: u64 = 64;
/// The table's memory limit: it is O(k N²) (§11.5), so pd refuses scenes it cannot hold.
pub const TABLE_LIMIT_BYTES: u64 = 256 << 20;
/// Columns one dispatch of the scan can cover (its y dimension).
const MAX_COLUMNS: u64 = MAX_WORKGROUPS_X as u64;

crate::push_constants! {
    struct StorePush {
        surface_count: u32,
        slots: u32,
    }
}

crate::push_constants! {
    struct ScanPush {
        surface_count: u32,
        column_count: u32,
    }
}

crate::push_constants! {
    struct PickPush {
        column_count: u32,
    }
}

crate::push_constants! {
    struct ClearPush {
        surface_count: u32,
    }
}

pub struct StoredTable {
    surface_count: u32,
    slots: u32,
    entries: Buffer,
    locations: Buffer,
    columns: Buffer,
    delivery: Buffer,
    store: ComputePipeline,
    scan: ComputePipeline,
    pick: ComputePipeline,
    clear: ComputePipeline,
}

/// Bytes a table for `surfaces` surfaces and `slots` locations per shot needs.
pub fn table_bytes(surfaces: u64, slots: u64) -> u64 {
    surfaces * slots * (surfaces * ENTRY_BYTES + LOCATION_BYTES + 4)
}

impl StoredTable {
    /// A table for `surfaces` receivers and shooters; `used` false gives the one-entry
    /// placeholder the passes bind in the pr and id modes.
    pub fn new(gpu: &Gpu, surfaces: u32, slots: u32, used: bool) -> anyhow::Result<StoredTable> {
        let (n, k) = if used { (u64::from(surfaces), u64::from(slots)) } else { (1, 1) };
        let bytes = table_bytes(n, k);
        if bytes > TABLE_LIMIT_BYTES || n * k > MAX_COLUMNS {
            return Err(InputError::new(format!(
                "--radiosity-mode pd: the stored radiosity table of {n} surfaces x {k} shooting locations would need {} MiB (at most {} MiB and {MAX_COLUMNS} columns); use fewer --shooting-locations or --elements on fewer surfaces, or the pr or id mode",
                bytes >> 20,
                TABLE_LIMIT_BYTES >> 20
            ))
            .into());
        }
        let storage = |name: &str, bytes: u64| gpu.create_buffer(&BufferDesc::storage(name, bytes.max(16)));
        let compute = |name, spirv| ComputePipeline::new(gpu, name, spirv, &Specialization::new());
        Ok(StoredTable {
            surface_count: n as u32,
            slots: k as u32,
            entries: storage("radiosity table entries", n * k * n * ENTRY_BYTES)?,
            locations: storage("radiosity table locations", n * k * LOCATION_BYTES)?,
            columns: storage("radiosity table columns", n * k * 4)?,
            delivery: storage("radiosity table delivery", 16)?,
            store: compute("radiosity table store", shaders::GI_RADIOSITY_TABLE_STORE_COMP)?,
            scan: compute("radiosity table scan", shaders::GI_RADIOSITY_TABLE_SCAN_COMP)?,
            pick: compute("radiosity table pick", shaders::GI_RADIOSITY_TABLE_PICK_COMP)?,
            clear: compute("radiosity table clear", shaders::GI_RADIOSITY_TABLE_CLEAR_COMP)?,
        })
    }

    fn column_count(&self) -> u32 {
        self.surface_count * self.slots
    }

    /// The fills that empty the table (a restart), for the restart's one clearing pass.
    pub fn clearing_fills(&self) -> [(&Buffer, u32); 3] {
        [(&self.entries, 0), (&self.columns, 0), (&self.delivery, 0)]
    }

    /// What the gather reads of a delivery.
    pub fn gather_bindings(&self) -> [Binding<'_>; 2] {
        [
            Binding::read(ids::RAD_TABLE, &self.entries),
            Binding::read(ids::RAD_DELIVERY, &self.delivery),
        ]
    }

    /// Store the current shot's share for every receiver out of view (after its locations).
    pub fn record_store(&self, rec: &mut Recorder, shot: &Buffer, locations: &Buffer, visible: &Buffer) -> GpuResult<()> {
        rec.compute(&ComputePass {
            name: "radiosity table store",
            pipeline: &self.store,
            bindings: &[
                Binding::read(ids::RAD_SHOT, shot),
                Binding::read(ids::RAD_LOCATIONS, locations),
                Binding::read(ids::RAD_VISIBLE, visible),
                Binding::write(ids::RAD_TABLE, &self.entries),
                Binding::write(ids::RAD_TABLE_LOCATIONS, &self.locations),
            ],
            push: &StorePush {
                surface_count: self.surface_count,
                slots: self.slots,
            },
            threads: [self.surface_count, self.slots, 1],
        })
    }

    /// Mark the columns with entries for receivers now in view (after the view changed, its
    /// `generation`-th change).
    pub fn record_scan(&self, rec: &mut Recorder, visible: &Buffer, generation: u32) -> GpuResult<()> {
        rec.fill_buffer("radiosity table columns clear", &self.columns, 0);
        rec.update_buffer_at("radiosity table generation", &self.delivery, 8, &generation.to_le_bytes());
        rec.compute(&ComputePass {
            name: "radiosity table scan",
            pipeline: &self.scan,
            bindings: &[
                Binding::read(ids::RAD_VISIBLE, visible),
                Binding::read(ids::RAD_TABLE, &self.entries),
                Binding::write(ids::RAD_TABLE_COLUMNS, &self.columns),
            ],
            push: &ScanPush {
                surface_count: self.surface_count,
                column_count: self.column_count(),
            },
            threads: [self.surface_count, self.column_count(), 1],
        })
    }

    /// Put the next marked column's location into slot 0 of `locations` (kind none when no
    /// column is marked) and its number into the delivery state.
    pub fn record_pick(&self, rec: &mut Recorder, locations: &Buffer, shot: &Buffer) -> GpuResult<()> {
        rec.compute(&ComputePass {
            name: "radiosity table pick",
            pipeline: &self.pick,
            bindings: &[
                Binding::read(ids::RAD_TABLE_COLUMNS, &self.columns),
                Binding::read(ids::RAD_TABLE_LOCATIONS, &self.locations),
                Binding::write(ids::RAD_LOCATIONS, locations),
                Binding::write(ids::RAD_DELIVERY, &self.delivery),
                Binding::write(ids::RAD_SHOT, shot),
            ],
            push: &PickPush {
                column_count: self.column_count(),
            },
            threads: [256, 1, 1],
        })
    }

    /// The delivered column's entries for receivers in view are spent.
    pub fn record_spent(&self, rec: &mut Recorder, visible: &Buffer) -> GpuResult<()> {
        rec.compute(&ComputePass {
            name: "radiosity table clear",
            pipeline: &self.clear,
            bindings: &[
                Binding::read(ids::RAD_VISIBLE, visible),
                Binding::read(ids::RAD_DELIVERY, &self.delivery),
                Binding::write(ids::RAD_TABLE, &self.entries),
                Binding::write(ids::RAD_TABLE_COLUMNS, &self.columns),
            ],
            push: &ClearPush {
                surface_count: self.surface_count,
            },
            threads: [self.surface_count, 1, 1],
        })
    }
}
