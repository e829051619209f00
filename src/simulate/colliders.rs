//! The colliders as the compute kernels read them (`Collider` in
//! glsl/common/collider.glsl): the grass step, which they press, and the
//! wind's forces kernel, whose air they push, each bind a copy. The copy
//! has room for `MAX_COLLIDERS`, so a new set (the viewer's ball) is
//! written into it in place and the descriptor sets stay as they are.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::{Access, Buffer, Commands, Gpu};
use crate::sim::contact::{Collider, GpuCollider, MAX_COLLIDERS};

/// `colliders` uploaded as `name` into a buffer with room for
/// `MAX_COLLIDERS` (the kernels read `count` of them).
pub fn upload(
    gpu: &Gpu,
    commands: &Commands,
    name: &str,
    colliders: &[Collider],
) -> Result<Buffer> {
    check_count(colliders)?;
    let buffer = Buffer::new(
        gpu,
        name,
        (MAX_COLLIDERS * std::mem::size_of::<GpuCollider>()) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        crate::gpu::MemoryLocation::GpuOnly,
    )?;
    write(&buffer, gpu, commands, name, colliders, Access::NONE)?;
    Ok(buffer)
}

/// Writes `colliders` over what `buffer` (made by `upload`) held, after
/// the kernels' earlier reads. Blocks: call between submissions.
pub fn rewrite(
    buffer: &Buffer,
    gpu: &Gpu,
    commands: &Commands,
    name: &str,
    colliders: &[Collider],
) -> Result<()> {
    write(buffer, gpu, commands, name, colliders, Access::COMPUTE_READ)
}

/// The GPU records of `colliders` into `buffer`, after `before`, visible
/// to the kernels' reads; one zeroed record where there are none, so
/// that an upload is never empty.
fn write(
    buffer: &Buffer,
    gpu: &Gpu,
    commands: &Commands,
    name: &str,
    colliders: &[Collider],
    before: Access,
) -> Result<()> {
    check_count(colliders)?;
    let mut records: Vec<GpuCollider> = colliders.iter().map(GpuCollider::from).collect();
    if records.is_empty() {
        records.push(GpuCollider::default());
    }
    buffer.upload(
        gpu,
        commands,
        name,
        bytemuck::cast_slice(&records),
        before,
        Access::COMPUTE_READ,
    )
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
