//! The ownership model's promise: an object alive at teardown is reported
//! as a leak (its allocation by name), and the device outlives it safely.

use crate::common;

use common::strict_gpu;
use meadow::gpu::{Buffer, MemoryLocation};

#[test]
fn an_object_kept_past_teardown_is_reported_by_name() {
    let gpu = strict_gpu();
    let kept = Buffer::new(
        &gpu,
        "buffer kept too long",
        256,
        ash::vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    let report = gpu.destroy();
    let ids: Vec<&str> = report.messages.iter().map(|m| m.id.as_str()).collect();
    assert!(ids.contains(&"meadow-leaked-object"), "{ids:?}");
    let allocation = report
        .messages
        .iter()
        .find(|m| m.id == "meadow-leaked-allocation")
        .expect("the allocation is reported");
    assert!(allocation.first_text.contains("buffer kept too long"));
    assert!(report.check().is_err(), "a leak fails the run");
    // The device is still there for it: dropping it now releases it, and
    // then the device and the instance go.
    drop(kept);
}

#[test]
fn nothing_is_reported_when_every_object_went_first() {
    let gpu = strict_gpu();
    let buffer = Buffer::new(
        &gpu,
        "short-lived buffer",
        256,
        ash::vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    drop(buffer);
    common::finish(gpu);
}

#[test]
fn a_descriptor_set_keeps_the_buffer_it_binds_until_it_goes() {
    use meadow::gpu::{Bound, DescriptorSet, LayoutBinding, PipelineLayout};
    let gpu = strict_gpu();
    let bindings = [LayoutBinding::compute_storage(0)];
    let layout = PipelineLayout::new::<()>(
        &gpu,
        &bindings,
        ash::vk::ShaderStageFlags::empty(),
        "ownership test",
    )
    .unwrap();
    let buffer = Buffer::new(
        &gpu,
        "buffer only a set binds",
        256,
        ash::vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    let set = DescriptorSet::new(
        &gpu,
        &layout,
        &bindings,
        &[Bound::Buffer(&buffer)],
        "ownership test set",
    )
    .unwrap();
    // Its owner lets go first: the set still holds it, so it is alive (and
    // reported) at teardown; the set and the layout release it after.
    drop(buffer);
    let report = gpu.destroy();
    assert!(
        report
            .messages
            .iter()
            .any(|m| m.id == "meadow-leaked-allocation"
                && m.first_text.contains("buffer only a set binds")),
        "{:#?}",
        report.messages
    );
    drop(set);
    drop(layout);
}

/// `Gpu::device_memory` (every report's `device_memory`): the bytes of the
/// live allocations, and the most there were at once.
#[test]
fn device_memory_counts_the_live_allocations_and_keeps_the_peak() {
    let gpu = strict_gpu();
    let before = gpu.device_memory();
    let mib = |n: u64| {
        Buffer::new(
            &gpu,
            "device memory test buffer",
            n << 20,
            ash::vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )
        .unwrap()
    };
    let a = mib(4);
    let b = mib(2);
    let both = gpu.device_memory();
    // Each allocation at least its buffer's size (alignment may add).
    assert!(
        both.allocated_bytes >= before.allocated_bytes + (6 << 20),
        "{both:?}"
    );
    assert!(
        both.allocated_bytes < before.allocated_bytes + (7 << 20),
        "{both:?}"
    );
    assert_eq!(both.peak_bytes, both.allocated_bytes.max(before.peak_bytes));
    drop(a);
    let one = gpu.device_memory();
    assert!(
        one.allocated_bytes + (4 << 20) <= both.allocated_bytes,
        "{one:?}"
    );
    assert_eq!(one.peak_bytes, both.peak_bytes, "the peak stays");
    drop(b);
    assert_eq!(gpu.device_memory().allocated_bytes, before.allocated_bytes);
    common::finish(gpu);
}
