//! The colliders as the compute kernels read them (`Collider` in
//! glsl/common/collider.glsl): the grass step, which they press, and the
//! wind's forces kernel, whose air they push, each bind a copy.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::{Access, Buffer, Commands, Gpu};
use crate::sim::contact::{Collider, GpuCollider, MAX_COLLIDERS};

/// `colliders` uploaded as `name`; at least one entry (zeroed) so that the
/// binding always names a live buffer (the kernels read `count` of them).
pub fn upload(
    gpu: &Gpu,
    commands: &Commands,
    name: &str,
    colliders: &[Collider],
) -> Result<Buffer> {
    if colliders.len() > MAX_COLLIDERS {
        return Err(Error::InvalidInput(format!(
            "{} colliders cannot be simulated, at most {MAX_COLLIDERS}",
            colliders.len()
        )));
    }
    let mut records: Vec<GpuCollider> = colliders.iter().map(GpuCollider::from).collect();
    if records.is_empty() {
        records.push(GpuCollider::default());
    }
    Buffer::with_data(
        gpu,
        commands,
        name,
        bytemuck::cast_slice(&records),
        vk::BufferUsageFlags::STORAGE_BUFFER,
        Access::COMPUTE_READ,
    )
}
