//! The blade buffer: four control points (`BladeVertex`) per blade, in
//! device memory. The grass dynamics (compute) writes it in place each
//! step; the blade pipeline reads it as its vertex buffer. It is the one
//! thing the simulating and rendering phases share.

use ash::vk;

use crate::error::{try_collect, Error, Result};
use crate::gpu::{Access, Buffer, CommandPool, Gpu, MemoryLocation};
use crate::model::{Blade, BladeVertex};

const USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::VERTEX_BUFFER.as_raw()
        | vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw(),
);

pub struct BladeBuffer {
    buffer: Buffer,
    count: u32,
}

impl BladeBuffer {
    /// The blades' rest shape, uploaded once.
    pub fn new(gpu: &Gpu, commands: &CommandPool, blades: &[Blade]) -> Result<Self> {
        let count = drawable(blades.len())?;
        let vertices = rest_vertices(blades)?;
        let buffer = Buffer::with_data(
            gpu,
            commands,
            "blade control points (vertex buffer)",
            bytemuck::cast_slice(&vertices),
            USAGE,
            Access::VERTEX_INPUT,
        )?;
        Ok(Self { buffer, count })
    }

    /// The blades' rest shape, uploaded once, and after them room for
    /// `room` more that a pass writes each frame (the cover's tiles).
    pub fn with_room(
        gpu: &Gpu,
        commands: &CommandPool,
        blades: &[Blade],
        room: u32,
    ) -> Result<Self> {
        if room == 0 {
            return Self::new(gpu, commands, blades);
        }
        let count = drawable(blades.len() + room as usize)?;
        let buffer = Buffer::new(
            gpu,
            "blade control points (vertex buffer; the cover's after the patches')",
            count as u64 * 4 * std::mem::size_of::<BladeVertex>() as u64,
            USAGE | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        if !blades.is_empty() {
            let vertices = rest_vertices(blades)?;
            buffer.upload(
                gpu,
                commands,
                "blade control points (vertex buffer)",
                bytemuck::cast_slice(&vertices),
                Access::VERTEX_INPUT,
            )?;
        }
        Ok(Self { buffer, count })
    }

    /// The blades' rest shape in a buffer of its own, which the steps
    /// write beside the drawing and copy into the drawn one.
    pub fn simulated_twin(gpu: &Gpu, commands: &CommandPool, blades: &[Blade]) -> Result<Buffer> {
        let vertices = rest_vertices(blades)?;
        Buffer::with_data(
            gpu,
            commands,
            "simulated blade control points (copied into the drawn ones)",
            bytemuck::cast_slice(&vertices),
            USAGE,
            Access::COMPUTE_READ,
        )
    }

    /// Room for `blades` blades, contents undefined until the grass
    /// dynamics writes them (for timing the grass step alone, and tests).
    pub fn uninitialised(gpu: &Gpu, name: &str, blades: usize) -> Result<Self> {
        let count = drawable(blades)?;
        let buffer = Buffer::new(
            gpu,
            name,
            (blades * 4 * std::mem::size_of::<BladeVertex>()) as u64,
            USAGE,
            MemoryLocation::GpuOnly,
        )?;
        Ok(Self { buffer, count })
    }

    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    pub fn count(&self) -> u32 {
        self.count
    }
}

/// The blades' four control points each, at rest.
fn rest_vertices(blades: &[Blade]) -> Result<Vec<BladeVertex>> {
    try_collect(
        4 * blades.len(),
        blades.iter().flat_map(Blade::vertices),
        "the blades' control points",
    )
}

fn drawable(blades: usize) -> Result<u32> {
    u32::try_from(blades)
        .ok()
        .filter(|&n| n > 0 && (n as u64) * 4 <= u32::MAX as u64)
        .ok_or_else(|| Error::InvalidInput(format!("{blades} blades cannot be drawn in one call")))
}
