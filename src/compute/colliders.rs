//! The colliders as the compute kernels read them (`Collider` in
//! glsl/common/collider.glsl): the grass step's binning, which evaluates
//! them for the blades they press, and the wind's forces kernel, whose air
//! they push, each bind a copy. The copy has room for `MAX_COLLIDERS` and
//! is written in the command buffer before each step that reads it
//! (`record_write`), so a new set (the viewer's ball, every frame it
//! moves) costs no upload and no wait, and the descriptor sets stay.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::{Buffer, Gpu, Recording};
use crate::model::contact::{Collider, GpuCollider, MAX_COLLIDERS};

/// A buffer named `name` with room for `MAX_COLLIDERS` records, written
/// by `record_write`.
pub fn buffer(gpu: &Gpu, name: &str) -> Result<Buffer> {
    Buffer::new(
        gpu,
        name,
        (MAX_COLLIDERS * std::mem::size_of::<GpuCollider>()) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        crate::gpu::MemoryLocation::GpuOnly,
    )
}

/// The GPU records of `colliders`, refused past `MAX_COLLIDERS`.
pub fn records(colliders: &[Collider]) -> Result<Vec<GpuCollider>> {
    check_count(colliders)?;
    Ok(colliders.iter().map(GpuCollider::from).collect())
}

/// Records `records` written over `buffer` (made by `buffer`), declared
/// as a transfer write: the kernels that read them declare their reads.
/// Nothing where there are none: the kernels then read none. At most
/// 22.5 KiB, carried in the command buffer.
pub fn record_write(buffer: &Buffer, rec: &Recording, records: &[GpuCollider]) {
    if records.is_empty() {
        return;
    }
    rec.update_buffer(buffer, 0, bytemuck::cast_slice(records));
}

/// Refuses more colliders than a step simulates (before anything is made).
pub fn check_count(colliders: &[Collider]) -> Result<()> {
    if colliders.len() > MAX_COLLIDERS {
        return Err(Error::InvalidInput(format!(
            "{} colliders cannot be simulated, at most {MAX_COLLIDERS}",
            colliders.len()
        )));
    }
    Ok(())
}
