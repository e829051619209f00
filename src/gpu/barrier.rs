//! Accesses by name. An `Access` is what a stage does to a resource (and
//! the image layout it does it in): passes declare theirs (src/gpu/sync.rs
//! derives the barriers); the swapchain's own images, which no pass
//! declares, go through `image_barrier`. Only writes need making
//! available, so a barrier drops the read flags of its earlier side.

use ash::vk;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Access {
    pub(super) stage: vk::PipelineStageFlags2,
    pub(super) access: vk::AccessFlags2,
    /// The layout an image is in for this access (UNDEFINED for buffers).
    pub(super) layout: vk::ImageLayout,
}

const fn access(
    stage: vk::PipelineStageFlags2,
    access: vk::AccessFlags2,
    layout: vk::ImageLayout,
) -> Access {
    Access {
        stage,
        access,
        layout,
    }
}

const NO_LAYOUT: vk::ImageLayout = vk::ImageLayout::UNDEFINED;
const FRAGMENT_TESTS: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(
    vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
);

impl Access {
    /// Transfers writing (fills and copies).
    pub const TRANSFER_WRITE: Self = access(
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_WRITE,
        NO_LAYOUT,
    );
    /// Copies and blits reading (a frame read back or shown in a window).
    pub const COPY_READ: Self = access(
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_READ,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    /// Blits writing (a frame into a window's swapchain image).
    pub const BLIT_WRITE: Self = access(
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_WRITE,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    /// Presentation: the semaphore it waits on orders it, so no stage.
    pub const PRESENT: Self = access(
        vk::PipelineStageFlags2::NONE,
        vk::AccessFlags2::NONE,
        vk::ImageLayout::PRESENT_SRC_KHR,
    );
    pub const COPY_WRITE: Self = access(
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_WRITE,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    pub const HOST_READ: Self = access(
        vk::PipelineStageFlags2::HOST,
        vk::AccessFlags2::HOST_READ,
        NO_LAYOUT,
    );
    pub const COMPUTE_READ: Self = access(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_STORAGE_READ,
        NO_LAYOUT,
    );
    pub const COMPUTE_WRITE: Self = access(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_STORAGE_WRITE,
        NO_LAYOUT,
    );
    pub const COMPUTE_READ_WRITE: Self = Self::COMPUTE_READ.and(Self::COMPUTE_WRITE);
    /// A kernel reading a uniform buffer.
    pub const COMPUTE_UNIFORM_READ: Self = access(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::UNIFORM_READ,
        NO_LAYOUT,
    );
    /// The vertex stage reading a storage buffer.
    pub const VERTEX_SHADER_READ: Self = access(
        vk::PipelineStageFlags2::VERTEX_SHADER,
        vk::AccessFlags2::SHADER_STORAGE_READ,
        NO_LAYOUT,
    );
    /// Vertex input reading a vertex buffer.
    pub const VERTEX_INPUT: Self = access(
        vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT,
        vk::AccessFlags2::VERTEX_ATTRIBUTE_READ,
        NO_LAYOUT,
    );
    /// Index fetch reading an index buffer.
    pub const INDEX_INPUT: Self = access(
        vk::PipelineStageFlags2::INDEX_INPUT,
        vk::AccessFlags2::INDEX_READ,
        NO_LAYOUT,
    );
    /// An indirect draw reading its parameters from a buffer.
    pub const DRAW_INDIRECT: Self = access(
        vk::PipelineStageFlags2::DRAW_INDIRECT,
        vk::AccessFlags2::INDIRECT_COMMAND_READ,
        NO_LAYOUT,
    );
    pub const COLOR_ATTACHMENT_WRITE: Self = access(
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    );
    pub const COLOR_ATTACHMENT: Self = Self::COLOR_ATTACHMENT_WRITE.and(access(
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_READ,
        NO_LAYOUT,
    ));
    pub const DEPTH_ATTACHMENT: Self = access(
        FRAGMENT_TESTS,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
        ),
        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
    );
    /// Compute shaders sampling an image (the depth pyramid reading the
    /// colour pass's depth).
    pub const COMPUTE_SAMPLED: Self = access(
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_SAMPLED_READ,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    );
    /// Fragment shaders sampling an image.
    pub const FRAGMENT_SAMPLED: Self = access(
        vk::PipelineStageFlags2::FRAGMENT_SHADER,
        vk::AccessFlags2::SHADER_SAMPLED_READ,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    );

    /// Both accesses (stages and flags); the layout stays `self`'s.
    pub const fn and(self, other: Self) -> Self {
        access(
            vk::PipelineStageFlags2::from_raw(self.stage.as_raw() | other.stage.as_raw()),
            vk::AccessFlags2::from_raw(self.access.as_raw() | other.access.as_raw()),
            self.layout,
        )
    }

    /// The write flags alone: what an earlier side must make available.
    pub(super) fn writes(self) -> vk::AccessFlags2 {
        let writes = vk::AccessFlags2::SHADER_WRITE
            | vk::AccessFlags2::SHADER_STORAGE_WRITE
            | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
            | vk::AccessFlags2::TRANSFER_WRITE
            | vk::AccessFlags2::HOST_WRITE
            | vk::AccessFlags2::MEMORY_WRITE;
        self.access & writes
    }
}

/// The barrier taking `image` (`range` of it) from one access to another,
/// its contents dropped with `discard`: for images meadow does not own as
/// an `Image` (a swapchain's).
pub(super) fn image_barrier(
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    from: Access,
    to: Access,
    discard: bool,
) -> vk::ImageMemoryBarrier2<'static> {
    let old = if discard {
        vk::ImageLayout::UNDEFINED
    } else {
        from.layout
    };
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(from.stage)
        .src_access_mask(from.writes())
        .dst_stage_mask(to.stage)
        .dst_access_mask(to.access)
        .old_layout(old)
        .new_layout(to.layout)
        .image(image)
        .subresource_range(range)
}
