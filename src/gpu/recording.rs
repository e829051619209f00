//! A command buffer being recorded (`CommandPool::begin`, in
//! src/gpu/command_pool.rs). `Recording` is the only way commands are
//! recorded: each method is one Vulkan command on objects the Vulkan
//! layer's types own.

use std::cell::{Cell, RefCell};

use ash::vk;
use ash::vk::Handle as _;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::barrier::Access;
use crate::gpu::descriptors::DescriptorSet;
use crate::gpu::device::Device;
use crate::gpu::journal::{access_text, dependency_text, Journal};
use crate::gpu::pipeline::Pipeline;
use crate::gpu::sync::{Barriers, BufferUse, ImageRequest, ImageUse, Tracker};
use crate::gpu::{Buffer, Image};

/// How long one submission may run before we call the device hung (lavapipe
/// renders big scenes slowly, so this is generous).
const SUBMIT_TIMEOUT_NS: u64 = 600 * 1_000_000_000;

/// What a render pass instance draws into: a colour target (with the
/// single-sample image it resolves into, when multisampled) and a depth
/// target, cleared on load (colour to opaque black, depth to the far plane).
pub struct Attachments<'a> {
    pub color: Option<(&'a Image, Option<&'a Image>)>,
    pub depth: &'a Image,
    /// Keep the depth after the pass (a shadow map) or drop it.
    pub store_depth: bool,
}

/// A command buffer being recorded. Dropping it without submitting leaves
/// the buffer to the next `begin`, which resets it.
pub struct Recording<'a> {
    pub(super) device: &'a Device,
    pub(super) cmd: vk::CommandBuffer,
    /// The pool's fence, which a submission signals and waits for.
    pub(super) fence: vk::Fence,
    /// The queue the pool's submissions go to.
    pub(super) queue: vk::Queue,
    /// Set by `submit`: the pool's buffer is in flight until the pool
    /// waits for its fence (`CommandPool::wait`).
    pub(super) in_flight: &'a Cell<bool>,
    /// What the passes declared so far (`uses`).
    pub(super) tracker: RefCell<Tracker>,
    /// The pool's journal, which each command writes to when it is on.
    pub(super) journal: &'a Journal,
    /// The dispatches recorded so far (`dispatches`).
    pub(super) dispatches: Cell<Dispatches>,
}

/// Dispatches recorded in a command buffer, counted as each is recorded:
/// a pass reads them before and after its commands to report what it
/// records (the wind step's dispatches per step) without a formula that
/// could drift from the code.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dispatches {
    /// With their workgroup counts in the command.
    pub direct: u32,
    /// Reading their workgroup counts from a buffer (which may hold zero).
    pub indirect: u32,
}

impl std::ops::Sub for Dispatches {
    type Output = Dispatches;
    fn sub(self, earlier: Dispatches) -> Dispatches {
        Dispatches {
            direct: self.direct - earlier.direct,
            indirect: self.indirect - earlier.indirect,
        }
    }
}

/// Blocks until `fence` is signalled, then resets it; a device that does
/// not answer within `SUBMIT_TIMEOUT_NS` is reported lost.
pub(super) fn wait_for_fence(device: &Device, fence: vk::Fence, what: &str) -> Result<()> {
    // SAFETY: the fence belongs to this device.
    let waited = unsafe {
        device
            .raw
            .wait_for_fences(&[fence], true, SUBMIT_TIMEOUT_NS)
    };
    match waited {
        Ok(()) => {}
        Err(vk::Result::TIMEOUT) => {
            // Nothing may be released while the work could still run.
            device.wait_idle();
            return Err(Error::DeviceLost {
                during: format!(
                    "{what} (no answer within {} s)",
                    SUBMIT_TIMEOUT_NS / 1_000_000_000
                ),
            });
        }
        Err(r) => return Err(Error::vk("vkWaitForFences", what, r)),
    }
    // SAFETY: the fence is signalled and no submission waits on it.
    unsafe { device.raw.reset_fences(&[fence]) }.vk_context("vkResetFences", what)
}

impl Recording<'_> {
    /// Ends recording, submits, and blocks until the GPU is done.
    pub fn submit_and_wait(self, what: &str) -> Result<()> {
        self.submit_and_wait_with(what, &[], &[])
    }

    /// As `submit_and_wait`, the submission first waiting for `waits` and
    /// signalling `signals` when done (a swapchain image acquired, then
    /// ready to present; the simulation's steps copied).
    pub fn submit_and_wait_with(
        self,
        what: &str,
        waits: &[vk::SemaphoreSubmitInfo],
        signals: &[vk::SemaphoreSubmitInfo],
    ) -> Result<()> {
        let (device, fence, in_flight) = (self.device, self.fence, self.in_flight);
        self.submit(what, waits, signals)?;
        let waited = wait_for_fence(device, fence, what);
        // Waited for, or lost with the device idle: nothing is left to wait for.
        in_flight.set(false);
        waited
    }

    /// Ends recording and submits to the pool's queue without waiting:
    /// the submission first waits for `waits` and signals `signals` when
    /// done. The pool waits for it before its next `begin` (or `wait`).
    pub fn submit(
        self,
        what: &str,
        waits: &[vk::SemaphoreSubmitInfo],
        signals: &[vk::SemaphoreSubmitInfo],
    ) -> Result<()> {
        self.journal.note(|| format!("submit: {what}"));
        let device = &self.device.raw;
        // SAFETY: `cmd` is in the recording state (begun by `begin`).
        unsafe { device.end_command_buffer(self.cmd) }.vk_context("vkEndCommandBuffer", what)?;
        self.device.faults.submission(what)?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(signals)];
        // SAFETY: the fence is unsignalled (reset after every wait) and the
        // command buffer is not in flight (`begin` waited for it); one
        // thread submits to the queue.
        unsafe { device.queue_submit2(self.queue, &submit, self.fence) }
            .vk_context("vkQueueSubmit2", what)?;
        self.in_flight.set(true);
        Ok(())
    }

    /// Declares what the next commands do to `uses` and records the one
    /// barrier that needs after what was declared before in this recording
    /// (src/gpu/sync.rs); nothing where none is needed.
    pub fn uses(&self, uses: &[BufferUse]) {
        self.declare(uses, &[]);
    }

    /// As `uses`, with images: their layout transitions are recorded in
    /// the same barrier, and each image remembers the layout it is left in.
    pub fn declare(&self, buffers: &[BufferUse], images: &[ImageUse]) {
        let requests: Vec<ImageRequest> = images
            .iter()
            .map(|u| ImageRequest {
                image: u.image.raw,
                range: u.image.subresource_range(),
                layout_before: u.image.layout.get(),
                access: u.access,
                discard: u.discard,
            })
            .collect();
        let barriers = self.tracker.borrow_mut().declare_all(buffers, &requests);
        for u in images {
            u.image.layout.set(u.access.layout);
        }
        self.journal_declaration(buffers, images, &barriers);
        if !barriers.is_empty() {
            self.record_barriers(&barriers);
        }
    }

    /// Writes a declaration and the barrier it needed in the journal (when
    /// one is kept): the objects by their debug names.
    fn journal_declaration(&self, buffers: &[BufferUse], images: &[ImageUse], barriers: &Barriers) {
        self.journal.note(|| {
            let named = |raw: u64, access: Access| {
                format!("{} ({})", self.device.name_of(raw), access_text(access))
            };
            let uses: Vec<String> = buffers
                .iter()
                .map(|u| named(u.buffer.0.as_raw(), u.access))
                .chain(images.iter().map(|u| named(u.image.raw.as_raw(), u.access)))
                .collect();
            format!("  uses: {}", uses.join(", "))
        });
        if let Some(d) = &barriers.memory {
            self.journal.note(|| {
                format!(
                    "  barrier: {}",
                    dependency_text(d.src_stage, d.src_access, d.dst_stage, d.dst_access)
                )
            });
        }
        for t in &barriers.images {
            self.journal.note(|| {
                let d = t.dependency;
                format!(
                    "  transition: {} {:?} -> {:?}, {}",
                    self.device.name_of(t.image.as_raw()),
                    t.old_layout,
                    t.new_layout,
                    dependency_text(d.src_stage, d.src_access, d.dst_stage, d.dst_access)
                )
            });
        }
    }

    /// Records `barriers` (the memory dependency and the images' layout
    /// transitions) as one pipeline barrier.
    fn record_barriers(&self, barriers: &Barriers) {
        let memory: Vec<vk::MemoryBarrier2> = barriers
            .memory
            .iter()
            .map(|d| {
                vk::MemoryBarrier2::default()
                    .src_stage_mask(d.src_stage)
                    .src_access_mask(d.src_access)
                    .dst_stage_mask(d.dst_stage)
                    .dst_access_mask(d.dst_access)
            })
            .collect();
        let transitions: Vec<vk::ImageMemoryBarrier2> = barriers
            .images
            .iter()
            .map(|t| {
                let d = t.dependency;
                vk::ImageMemoryBarrier2::default()
                    .src_stage_mask(d.src_stage)
                    .src_access_mask(d.src_access)
                    .dst_stage_mask(d.dst_stage)
                    .dst_access_mask(d.dst_access)
                    .old_layout(t.old_layout)
                    .new_layout(t.new_layout)
                    .image(t.image)
                    .subresource_range(t.range)
            })
            .collect();
        // SAFETY: recording into a live command buffer, outside rendering
        // (passes declare before they begin one); every image is live.
        unsafe {
            self.device.raw.cmd_pipeline_barrier2(
                self.cmd,
                &vk::DependencyInfo::default()
                    .memory_barriers(&memory)
                    .image_memory_barriers(&transitions),
            )
        };
    }

    /// Sets every 32-bit word of `buffer` to `value`, declaring the write.
    pub fn fill_buffer(&self, buffer: &Buffer, value: u32) {
        self.fill_range(buffer, 0, vk::WHOLE_SIZE, value);
    }

    /// Sets the 32-bit words of `buffer` in `bytes` from `offset` (both
    /// multiples of 4, or `vk::WHOLE_SIZE` for the rest) to `value`,
    /// declaring the write.
    pub fn fill_range(&self, buffer: &Buffer, offset: u64, bytes: u64, value: u32) {
        self.uses(&[BufferUse::new(buffer, Access::TRANSFER_WRITE)]);
        self.journal.note(|| {
            let name = self.device.name_of(buffer.raw.as_raw());
            if offset == 0 && bytes == vk::WHOLE_SIZE {
                format!("fill {name}")
            } else {
                format!("fill {name} at {offset}")
            }
        });
        debug_assert!(offset % 4 == 0 && (bytes == vk::WHOLE_SIZE || bytes % 4 == 0));
        // SAFETY: recording outside rendering; the buffer is live and made
        // with TRANSFER_DST; offset and size are multiples of 4 (asserted
        // above) within the buffer (the callers' ranges are of blades the
        // buffer holds).
        unsafe {
            self.device
                .raw
                .cmd_fill_buffer(self.cmd, buffer.raw, offset, bytes, value)
        };
    }

    /// Writes `words` into `buffer` from byte `offset` (a multiple of 4),
    /// as transfers carried in the command buffer, declaring the write
    /// once: one vkCmdUpdateBuffer per 64 KiB, its most.
    pub fn update_buffer(&self, buffer: &Buffer, offset: u64, words: &[u32]) {
        self.uses(&[BufferUse::new(buffer, Access::TRANSFER_WRITE)]);
        debug_assert!(offset % 4 == 0 && !words.is_empty());
        for (n, chunk) in words.chunks(16384).enumerate() {
            let at = offset + n as u64 * 65536;
            self.journal.note(|| {
                format!(
                    "update {} at {at}",
                    self.device.name_of(buffer.raw.as_raw())
                )
            });
            // SAFETY: recording outside rendering; the buffer is live and
            // made with TRANSFER_DST; offset and size are multiples of 4
            // and the size at most 65536 bytes (the chunks' size), within
            // the buffer (the callers write what it holds).
            unsafe {
                self.device.raw.cmd_update_buffer(
                    self.cmd,
                    buffer.raw,
                    at,
                    bytemuck::cast_slice(chunk),
                )
            };
        }
    }

    /// Copies the first `bytes` of `src` to the start of `dst`.
    pub fn copy_buffer(&self, src: &Buffer, dst: &Buffer, bytes: u64) {
        self.journal.note(|| {
            format!(
                "copy {bytes} bytes {} -> {}",
                self.device.name_of(src.raw.as_raw()),
                self.device.name_of(dst.raw.as_raw())
            )
        });
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: bytes,
        };
        // SAFETY: recording; both buffers are live and at least `bytes` long
        // (the callers size them so).
        unsafe {
            self.device
                .raw
                .cmd_copy_buffer(self.cmd, src.raw, dst.raw, &[region])
        };
    }

    /// Copies mip levels packed one after another in `src` into `dst`,
    /// which is in the COPY_WRITE layout.
    pub fn copy_buffer_to_image(&self, src: &Buffer, dst: &Image, levels: &[vk::Extent2D]) {
        self.journal.note(|| {
            format!(
                "copy {} -> {}",
                self.device.name_of(src.raw.as_raw()),
                self.device.name_of(dst.raw.as_raw())
            )
        });
        let mut offset = 0u64;
        let regions: Vec<_> = levels
            .iter()
            .enumerate()
            .map(|(level, extent)| {
                let region = vk::BufferImageCopy {
                    buffer_offset: offset,
                    buffer_row_length: 0,
                    buffer_image_height: 0,
                    image_subresource: layers(dst.aspect, level as u32),
                    image_offset: vk::Offset3D::default(),
                    image_extent: vk::Extent3D {
                        width: extent.width,
                        height: extent.height,
                        depth: 1,
                    },
                };
                offset += 4 * extent.width as u64 * extent.height as u64;
                region
            })
            .collect();
        // SAFETY: recording; both are live and every region lies inside both.
        unsafe {
            self.device.raw.cmd_copy_buffer_to_image(
                self.cmd,
                src.raw,
                dst.raw,
                Access::COPY_WRITE.layout,
                &regions,
            )
        };
    }

    /// Copies mip level 0 of `src`, in the COPY_READ layout, into `dst`.
    pub fn copy_image_to_buffer(&self, src: &Image, dst: &Buffer) {
        self.journal.note(|| {
            format!(
                "copy {} -> {}",
                self.device.name_of(src.raw.as_raw()),
                self.device.name_of(dst.raw.as_raw())
            )
        });
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: layers(src.aspect, 0),
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: src.extent.width,
                height: src.extent.height,
                depth: 1,
            },
        };
        // SAFETY: recording; both are live and `dst` holds the whole level.
        unsafe {
            self.device.raw.cmd_copy_image_to_buffer(
                self.cmd,
                src.raw,
                Access::COPY_READ.layout,
                dst.raw,
                &[region],
            )
        };
    }

    pub fn bind_pipeline(&self, pipeline: &Pipeline) {
        self.journal
            .note(|| format!("pipeline {}", self.device.name_of(pipeline.raw().as_raw())));
        // SAFETY: recording; the pipeline is live.
        unsafe {
            self.device
                .raw
                .cmd_bind_pipeline(self.cmd, pipeline.bind_point, pipeline.raw())
        };
    }

    /// Binds `set` as set 0 of `pipeline`'s layout.
    pub fn bind_set(&self, pipeline: &Pipeline, set: &DescriptorSet) {
        // SAFETY: recording; the set was made for this layout's set 0.
        unsafe {
            self.device.raw.cmd_bind_descriptor_sets(
                self.cmd,
                pipeline.bind_point,
                pipeline.layout.raw(),
                0,
                &[set.raw],
                &[],
            )
        };
    }

    /// Sets `pipeline`'s push constants (its layout's one range) to `value`.
    pub fn push_constants<T: bytemuck::Pod>(&self, pipeline: &Pipeline, value: &T) {
        // SAFETY: recording; the layout declares a range of this size at 0
        // for these stages (`PipelineLayout::new` takes both from T).
        unsafe {
            self.device.raw.cmd_push_constants(
                self.cmd,
                pipeline.layout.raw(),
                pipeline.layout.push_stages,
                0,
                bytemuck::bytes_of(value),
            )
        };
    }

    /// The dispatches recorded so far.
    pub fn dispatches(&self) -> Dispatches {
        self.dispatches.get()
    }

    fn count_dispatch(&self, indirect: bool) {
        let mut d = self.dispatches.get();
        if indirect {
            d.indirect += 1;
        } else {
            d.direct += 1;
        }
        self.dispatches.set(d);
    }

    pub fn dispatch(&self, groups: u32) {
        self.count_dispatch(false);
        self.journal.note(|| format!("dispatch {groups}"));
        // SAFETY: recording, with a compute pipeline and its set bound.
        unsafe { self.device.raw.cmd_dispatch(self.cmd, groups, 1, 1) };
    }

    /// A dispatch of `x` x `y` workgroups (a kernel over an image).
    pub fn dispatch_2d(&self, x: u32, y: u32) {
        self.count_dispatch(false);
        self.journal.note(|| format!("dispatch {x} x {y}"));
        // SAFETY: recording, with a compute pipeline and its set bound.
        unsafe { self.device.raw.cmd_dispatch(self.cmd, x, y, 1) };
    }

    /// A dispatch whose workgroup counts (a `VkDispatchIndirectCommand`)
    /// the GPU wrote at byte `offset` of `buffer`: declares the kernel's
    /// `uses` and its own read of the command in one (`uses`), then
    /// dispatches.
    pub fn dispatch_indirect(&self, buffer: &Buffer, offset: u64, uses: &[BufferUse]) {
        let mut all = uses.to_vec();
        all.push(BufferUse::new(buffer, Access::DRAW_INDIRECT));
        self.uses(&all);
        self.count_dispatch(true);
        self.journal.note(|| {
            format!(
                "dispatch, indirect from {} at {offset}",
                self.device.name_of(buffer.raw.as_raw())
            )
        });
        // SAFETY: recording, with a compute pipeline and its set bound; the
        // buffer is live, made with INDIRECT_BUFFER, and holds the 12-byte
        // command at the 4-aligned `offset` (the callers' layouts say so).
        unsafe {
            self.device
                .raw
                .cmd_dispatch_indirect(self.cmd, buffer.raw, offset)
        };
    }

    /// Begins rendering into `targets` over their whole extent, with the
    /// viewport and scissor set to it.
    pub fn begin_rendering(&self, targets: &Attachments) {
        self.journal.note(|| {
            format!(
                "begin rendering into {}",
                self.device.name_of(targets.depth.raw.as_raw())
            )
        });
        let extent = targets.depth.extent;
        let clear_color = vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.0, 0.0, 0.0, 1.0],
            },
        };
        let color: Vec<_> = targets
            .color
            .iter()
            .map(|(image, resolve)| {
                let attachment = vk::RenderingAttachmentInfo::default()
                    .image_view(image.view)
                    .image_layout(Access::COLOR_ATTACHMENT.layout)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(clear_color);
                match resolve {
                    Some(resolve) => attachment
                        .store_op(vk::AttachmentStoreOp::DONT_CARE)
                        .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                        .resolve_image_view(resolve.view)
                        .resolve_image_layout(Access::COLOR_ATTACHMENT.layout),
                    None => attachment,
                }
            })
            .collect();
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(targets.depth.view)
            .image_layout(Access::DEPTH_ATTACHMENT.layout)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(if targets.store_depth {
                vk::AttachmentStoreOp::STORE
            } else {
                vk::AttachmentStoreOp::DONT_CARE
            })
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            });
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent,
        };
        let rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: recording, outside rendering; the views are live and in
        // the attachment layouts (the caller's transitions put them there).
        unsafe { self.device.raw.cmd_begin_rendering(self.cmd, &rendering) };
        // SAFETY: recording; every pipeline here takes viewport and scissor
        // as dynamic state.
        unsafe { self.device.raw.cmd_set_viewport(self.cmd, 0, &[viewport]) };
        // SAFETY: as above.
        unsafe { self.device.raw.cmd_set_scissor(self.cmd, 0, &[area]) };
    }

    pub fn end_rendering(&self) {
        self.journal.note(|| "end rendering".to_string());
        // SAFETY: recording, inside the rendering begun by `begin_rendering`.
        unsafe { self.device.raw.cmd_end_rendering(self.cmd) };
    }

    pub fn bind_vertex_buffer(&self, buffer: &Buffer) {
        // SAFETY: recording; the buffer is live and made with VERTEX_BUFFER.
        unsafe {
            self.device
                .raw
                .cmd_bind_vertex_buffers(self.cmd, 0, &[buffer.raw], &[0])
        };
    }

    /// Binds `buffer` as the index buffer, 32-bit indices from its start.
    pub fn bind_index_buffer(&self, buffer: &Buffer) {
        // SAFETY: recording; the buffer is live and made with INDEX_BUFFER.
        unsafe {
            self.device
                .raw
                .cmd_bind_index_buffer(self.cmd, buffer.raw, 0, vk::IndexType::UINT32)
        };
    }

    /// One indexed draw whose parameters (a `VkDrawIndexedIndirectCommand`)
    /// the GPU wrote at byte `offset` of `buffer`.
    pub fn draw_indexed_indirect(&self, buffer: &Buffer, offset: u64) {
        self.journal.note(|| {
            format!(
                "draw indexed, indirect from {} at {offset}",
                self.device.name_of(buffer.raw.as_raw())
            )
        });
        // SAFETY: recording inside rendering with a graphics pipeline, its
        // vertex and index buffers bound; the buffer is live, made with
        // INDIRECT_BUFFER, and holds the 20-byte command at the 4-aligned
        // `offset` (the callers' layouts say so). One draw: no stride.
        unsafe {
            self.device
                .raw
                .cmd_draw_indexed_indirect(self.cmd, buffer.raw, offset, 1, 0)
        };
    }

    pub fn draw(&self, vertices: u32) {
        self.journal.note(|| format!("draw {vertices}"));
        // SAFETY: recording inside rendering with a graphics pipeline bound.
        unsafe { self.device.raw.cmd_draw(self.cmd, vertices, 1, 0, 0) };
    }

    /// Draws the bound index buffer's first `indices` indices, one instance.
    pub fn draw_indexed(&self, indices: u32) {
        self.journal.note(|| format!("draw indexed {indices}"));
        // SAFETY: recording inside rendering with a graphics pipeline, its
        // vertex and index buffers bound; the callers' counts lie inside
        // the bound index buffer, whose indices lie inside the vertices.
        unsafe {
            self.device
                .raw
                .cmd_draw_indexed(self.cmd, indices, 1, 0, 0, 0)
        };
    }

    /// Draws the bound vertex buffer's vertices `range`, one instance.
    pub fn draw_range(&self, range: std::ops::Range<u32>) {
        self.journal.note(|| format!("draw {range:?}"));
        // SAFETY: recording inside rendering with a graphics pipeline bound;
        // the callers' ranges lie inside the bound vertex buffer.
        unsafe {
            self.device
                .raw
                .cmd_draw(self.cmd, range.len() as u32, 1, range.start, 0)
        };
    }
}

fn layers(aspect: vk::ImageAspectFlags, mip_level: u32) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: aspect,
        mip_level,
        base_array_layer: 0,
        layer_count: 1,
    }
}
