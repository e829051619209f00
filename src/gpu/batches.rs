//! Kernels over more items than one storage binding may reach: a device
//! lets one descriptor see at most maxStorageBufferRange bytes (lavapipe:
//! 128 MiB, a million blades' control points; NVIDIA: 4 GiB), so a kernel
//! over a bigger buffer binds it a batch at a time, each batch a part of
//! the buffer (`Bound::Part`) in a descriptor set of its own.

use std::ops::Range;

use crate::error::{Error, Result};
use crate::gpu::{Bound, Buffer, DescriptorSet, Gpu, LayoutBinding, PipelineLayout};

/// Every batch but the last holds a multiple of this many items: a whole
/// number of workgroups (64 and 256 items divide it) whose bytes start at
/// an offset any storage alignment divides (Vulkan caps
/// minStorageBufferOffsetAlignment at 256 bytes).
pub const BATCH_MULTIPLE: u32 = 256;

/// The most items one batch may hold when an item takes `item_bytes` of
/// the largest buffer a kernel binds per item.
pub fn storage_batch_len(gpu: &Gpu, item_bytes: u64) -> Result<u32> {
    let range = gpu.limits().max_storage_buffer_range as u64;
    let items = range / item_bytes.max(1) / BATCH_MULTIPLE as u64 * BATCH_MULTIPLE as u64;
    if items == 0 {
        return Err(Error::InvalidInput(format!(
            "this device's maxStorageBufferRange ({range} bytes) holds fewer than {BATCH_MULTIPLE} items of {item_bytes} bytes"
        )));
    }
    Ok(items.min(u32::MAX as u64 / BATCH_MULTIPLE as u64 * BATCH_MULTIPLE as u64) as u32)
}

/// `items` split into batches of `len` (a positive multiple of
/// `BATCH_MULTIPLE`), in order; the last may be shorter.
pub fn batches(items: u32, len: u32) -> Result<Vec<Range<u32>>> {
    if len == 0 || len % BATCH_MULTIPLE != 0 {
        return Err(Error::InvalidInput(format!(
            "a batch of {len} items is not a positive multiple of {BATCH_MULTIPLE}"
        )));
    }
    Ok((0..items.div_ceil(len))
        .map(|k| k * len..items.min((k + 1).saturating_mul(len)))
        .collect())
}

/// One descriptor set of `layout` per batch of `items` items, as many as
/// one binding of `item_bytes` per item allows (`storage_batch_len`); `bound`
/// gives a batch's resources (`part` binds its share of a per-item
/// buffer). One batch when they fit, named `name`; else each named with its
/// items.
pub fn sets_per_batch<'a>(
    gpu: &Gpu,
    layout: &PipelineLayout,
    bindings: &[LayoutBinding],
    items: u32,
    item_bytes: u64,
    name: &str,
    bound: impl Fn(&Range<u32>) -> Vec<Bound<'a>>,
) -> Result<Vec<(DescriptorSet, Range<u32>)>> {
    let all = batches(items, storage_batch_len(gpu, item_bytes)?)?;
    let many = all.len() > 1;
    all.into_iter()
        .map(|range| {
            let name = if many {
                format!("{name} (items {range:?})")
            } else {
                name.to_string()
            };
            let set = DescriptorSet::new(gpu, layout, bindings, &bound(&range), &name)?;
            Ok((set, range))
        })
        .collect()
}

/// The part of `buffer` that holds `items`, `item_bytes` each.
pub fn part<'a>(buffer: &'a Buffer, items: &Range<u32>, item_bytes: usize) -> Bound<'a> {
    let item_bytes = item_bytes as u64;
    Bound::Part {
        buffer,
        offset: items.start as u64 * item_bytes,
        size: items.len() as u64 * item_bytes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batches_cover_every_item_once_in_order() {
        for (items, len) in [(1, 256), (256, 256), (257, 256), (1_000_000, 262_144)] {
            let b = batches(items, len).unwrap();
            assert_eq!(b.first().unwrap().start, 0);
            assert_eq!(b.last().unwrap().end, items);
            assert!(b.windows(2).all(|w| w[0].end == w[1].start));
            assert!(b.iter().all(|r| !r.is_empty() && r.len() <= len as usize));
        }
        assert_eq!(batches(1_000_000, 262_144).unwrap().len(), 4);
        assert!(batches(10, 100).is_err());
        assert!(batches(10, 0).is_err());
    }
}
