//! Barriers derived from what passes declare. A pass says, before the
//! commands it records, which buffers and images they touch and how
//! (`BufferUse`, `ImageUse`: a resource and an `Access`); the recording
//! remembers each one's last write, the reads since and, for an image, its
//! layout, and emits the one barrier those commands need: read after write
//! (the write made visible to the reader), write after write, write after
//! read (the readers finished first), and an image's layout transition. A
//! use that needs nothing emits nothing: reads after reads, or a second
//! reader of a write already made visible to its stage.
//!
//! What a resource went through before this recording is unknown (an
//! earlier submission, the host), so its first use here waits for any
//! earlier write and read; an image starts from the layout the last
//! recording that used it left it in, or drops its contents when the use
//! says so (`ImageUse::discarding`: cleared or overwritten next). Every use
//! after the first in a recording must be declared: an undeclared one is a
//! hazard the synchronization validation layer reports.

use std::collections::HashMap;

use ash::vk;

use crate::gpu::barrier::Access;
use crate::gpu::{Buffer, Image};

/// A buffer's identity, for declaring its uses: a pass may keep the ids of
/// buffers it binds but does not own (its sets keep them alive).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BufferId(pub(super) vk::Buffer);

impl From<&Buffer> for BufferId {
    fn from(buffer: &Buffer) -> Self {
        Self(buffer.raw)
    }
}

/// A buffer and what the next commands do to it.
#[derive(Clone, Copy, Debug)]
pub struct BufferUse {
    pub buffer: BufferId,
    pub access: Access,
}

impl BufferUse {
    pub fn new(buffer: impl Into<BufferId>, access: Access) -> Self {
        Self {
            buffer: buffer.into(),
            access,
        }
    }
}

/// An image (all of it) and what the next commands do to it, in the
/// access's layout.
#[derive(Clone, Copy)]
pub struct ImageUse<'a> {
    pub image: &'a Image,
    pub access: Access,
    /// Its contents are not needed: the transition starts from UNDEFINED.
    pub discard: bool,
}

impl<'a> ImageUse<'a> {
    pub fn new(image: &'a Image, access: Access) -> Self {
        Self {
            image,
            access,
            discard: false,
        }
    }

    /// As `new`, the contents dropped (the commands clear or overwrite it).
    pub fn discarding(image: &'a Image, access: Access) -> Self {
        Self {
            discard: true,
            ..Self::new(image, access)
        }
    }
}

/// An image use as the tracker sees it: the handle, its range, and the
/// layout it was left in before this recording.
#[derive(Clone, Copy, Debug)]
pub(super) struct ImageRequest {
    pub image: vk::Image,
    pub range: vk::ImageSubresourceRange,
    pub layout_before: vk::ImageLayout,
    pub access: Access,
    pub discard: bool,
}

/// A layout transition (with its dependency) of one image.
#[derive(Clone, Copy, Debug)]
pub(super) struct ImageBarrier {
    pub image: vk::Image,
    pub range: vk::ImageSubresourceRange,
    pub dependency: Dependency,
    pub old_layout: vk::ImageLayout,
    pub new_layout: vk::ImageLayout,
}

/// What the next commands need first: one global memory barrier and the
/// images' transitions, recorded together.
#[derive(Debug, Default)]
pub(super) struct Barriers {
    pub memory: Option<Dependency>,
    pub images: Vec<ImageBarrier>,
}

impl Barriers {
    pub fn is_empty(&self) -> bool {
        self.memory.is_none() && self.images.is_empty()
    }
}

/// One resource's history in a recording.
#[derive(Clone, Copy, Debug)]
struct Hazard {
    /// The stages and write flags of the last write.
    write_stage: vk::PipelineStageFlags2,
    write_access: vk::AccessFlags2,
    /// Stages and flags the last write has been made visible to.
    visible_stage: vk::PipelineStageFlags2,
    visible_access: vk::AccessFlags2,
    /// Stages that read since the last write (a writer waits for them).
    read_stage: vk::PipelineStageFlags2,
}

impl Hazard {
    /// Before its first use in a recording: written and read by anything.
    const UNKNOWN: Self = Self {
        write_stage: vk::PipelineStageFlags2::ALL_COMMANDS,
        write_access: vk::AccessFlags2::MEMORY_WRITE,
        visible_stage: vk::PipelineStageFlags2::NONE,
        visible_access: vk::AccessFlags2::NONE,
        read_stage: vk::PipelineStageFlags2::ALL_COMMANDS,
    };

    /// Adds to `dep` what `access` needs after this history.
    fn need(&self, access: Access, dep: &mut Dependency) {
        let writes = access.writes();
        let reads = access.access & !writes;
        let already_visible =
            covers(self.visible_stage, access.stage) && covers(self.visible_access, reads);
        if !reads.is_empty() && !already_visible {
            // Read after write.
            dep.src_stage |= self.write_stage;
            dep.src_access |= self.write_access;
            dep.dst_stage |= access.stage;
            dep.dst_access |= reads;
        }
        if !writes.is_empty() {
            // Write after write, and after the reads since.
            dep.src_stage |= self.write_stage | self.read_stage;
            dep.src_access |= self.write_access;
            dep.dst_stage |= access.stage;
            dep.dst_access |= writes;
        }
    }

    /// After a barrier `dep`: a write it waited for is visible to its
    /// whole destination.
    fn waited(&mut self, dep: &Dependency) {
        if covers(dep.src_stage, self.write_stage) && covers(dep.src_access, self.write_access) {
            self.visible_stage |= dep.dst_stage;
            self.visible_access |= dep.dst_access;
        }
    }

    /// After commands making `access` (their barrier recorded).
    fn used(&mut self, access: Access) {
        let writes = access.writes();
        if writes.is_empty() {
            self.visible_stage |= access.stage;
            self.visible_access |= access.access;
            self.read_stage |= access.stage;
        } else {
            // Written: visible to nobody yet; a later writer also waits
            // for the reads these same commands made.
            *self = Self::written(access.stage, writes);
        }
    }

    fn written(stage: vk::PipelineStageFlags2, writes: vk::AccessFlags2) -> Self {
        Self {
            write_stage: stage,
            write_access: writes,
            visible_stage: vk::PipelineStageFlags2::NONE,
            visible_access: vk::AccessFlags2::NONE,
            read_stage: stage,
        }
    }
}

/// An image's history in a recording, and the layout it is in.
#[derive(Clone, Copy, Debug)]
struct ImageState {
    hazard: Hazard,
    layout: vk::ImageLayout,
}

/// The source and destination of one barrier.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dependency {
    pub src_stage: vk::PipelineStageFlags2,
    pub src_access: vk::AccessFlags2,
    pub dst_stage: vk::PipelineStageFlags2,
    pub dst_access: vk::AccessFlags2,
}

impl Dependency {
    fn is_empty(&self) -> bool {
        self.src_stage.is_empty() && self.dst_stage.is_empty()
    }
}

/// Each declared resource's history in one recording.
#[derive(Default)]
pub struct Tracker {
    buffers: HashMap<BufferId, Hazard>,
    images: HashMap<vk::Image, ImageState>,
}

/// Whether `flags` holds every bit of `part`.
fn covers<T: Copy + std::ops::BitAnd<Output = T> + PartialEq>(flags: T, part: T) -> bool {
    flags & part == part
}

/// One access per resource: all that these commands do to it.
fn merge<K: PartialEq + Copy>(uses: impl Iterator<Item = (K, Access)>) -> Vec<(K, Access)> {
    let mut merged: Vec<(K, Access)> = Vec::new();
    for (key, access) in uses {
        match merged.iter_mut().find(|(k, _)| *k == key) {
            Some((_, a)) => *a = a.and(access),
            None => merged.push((key, access)),
        }
    }
    merged
}

impl Tracker {
    /// Declares that the next commands make `uses`; returns the barrier
    /// they need (None: none), and remembers them.
    pub fn declare(&mut self, uses: &[BufferUse]) -> Option<Dependency> {
        self.declare_all(uses, &[]).memory
    }

    /// As `declare`, with images: those whose layout changes (or whose
    /// contents are dropped) get their own transition, the rest share the
    /// global barrier.
    pub(super) fn declare_all(&mut self, uses: &[BufferUse], images: &[ImageRequest]) -> Barriers {
        let buffers = merge(uses.iter().map(|u| (u.buffer, u.access)));
        let mut dep = Dependency::default();
        for &(buffer, access) in &buffers {
            self.buffers
                .entry(buffer)
                .or_insert(Hazard::UNKNOWN)
                .need(access, &mut dep);
        }
        let mut transitions = Vec::new();
        for request in images {
            let state = self.images.entry(request.image).or_insert(ImageState {
                hazard: Hazard::UNKNOWN,
                layout: request.layout_before,
            });
            let access = request.access;
            if request.discard || state.layout != access.layout {
                // The transition waits for every earlier access and is
                // itself a write, made visible to these commands.
                let h = state.hazard;
                let dependency = Dependency {
                    src_stage: h.write_stage | h.read_stage,
                    src_access: h.write_access,
                    dst_stage: access.stage,
                    dst_access: access.access,
                };
                transitions.push(ImageBarrier {
                    image: request.image,
                    range: request.range,
                    dependency,
                    old_layout: if request.discard {
                        vk::ImageLayout::UNDEFINED
                    } else {
                        state.layout
                    },
                    new_layout: access.layout,
                });
                // Later barriers chain through these commands' stages;
                // `used` below makes it visible to what they read.
                state.hazard = Hazard::written(access.stage, vk::AccessFlags2::NONE);
                state.layout = access.layout;
            } else {
                state.hazard.need(access, &mut dep);
            }
        }
        if !dep.is_empty() {
            for hazard in self.buffers.values_mut() {
                hazard.waited(&dep);
            }
            // Not the images transitioned here: the global barrier is not
            // ordered after their transitions.
            for (image, state) in self.images.iter_mut() {
                if !transitions.iter().any(|t| t.image == *image) {
                    state.hazard.waited(&dep);
                }
            }
        }
        for &(buffer, access) in &buffers {
            self.buffers
                .get_mut(&buffer)
                .expect("inserted above")
                .used(access);
        }
        for request in images {
            let state = self.images.get_mut(&request.image).expect("inserted above");
            state.hazard.used(request.access);
        }
        Barriers {
            memory: (!dep.is_empty()).then_some(dep),
            images: transitions,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn u(n: u64, access: Access) -> BufferUse {
        BufferUse {
            buffer: BufferId(vk::Handle::from_raw(n)),
            access,
        }
    }

    #[test]
    fn a_first_use_waits_for_anything_before() {
        let mut t = Tracker::default();
        let d = t.declare(&[u(1, Access::COMPUTE_READ)]).unwrap();
        assert_eq!(d.src_stage, vk::PipelineStageFlags2::ALL_COMMANDS);
        assert_eq!(d.src_access, vk::AccessFlags2::MEMORY_WRITE);
        assert_eq!(d.dst_access, vk::AccessFlags2::SHADER_STORAGE_READ);
    }

    #[test]
    fn a_read_after_a_write_waits_once() {
        let mut t = Tracker::default();
        t.declare(&[u(1, Access::COMPUTE_WRITE)]);
        let d = t.declare(&[u(1, Access::COMPUTE_READ)]).unwrap();
        assert_eq!(d.src_stage, vk::PipelineStageFlags2::COMPUTE_SHADER);
        assert_eq!(d.src_access, vk::AccessFlags2::SHADER_STORAGE_WRITE);
        assert_eq!(d.dst_stage, vk::PipelineStageFlags2::COMPUTE_SHADER);
        // A second compute reader: already visible.
        assert_eq!(t.declare(&[u(1, Access::COMPUTE_READ)]), None);
        // The vertex input has not seen it yet.
        let d = t.declare(&[u(1, Access::VERTEX_INPUT)]).unwrap();
        assert_eq!(d.dst_stage, vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT);
    }

    #[test]
    fn a_write_after_reads_waits_for_the_readers() {
        let mut t = Tracker::default();
        t.declare(&[u(1, Access::COMPUTE_WRITE)]);
        t.declare(&[u(1, Access::VERTEX_INPUT)]);
        let d = t.declare(&[u(1, Access::COMPUTE_WRITE)]).unwrap();
        assert!(covers(
            d.src_stage,
            vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT
                | vk::PipelineStageFlags2::COMPUTE_SHADER
        ));
        assert_eq!(d.dst_access, vk::AccessFlags2::SHADER_STORAGE_WRITE);
    }

    #[test]
    fn a_barrier_for_one_buffer_makes_others_written_before_visible() {
        let mut t = Tracker::default();
        t.declare(&[u(1, Access::COMPUTE_WRITE), u(2, Access::COMPUTE_WRITE)]);
        assert!(t.declare(&[u(1, Access::COMPUTE_READ)]).is_some());
        // The global barrier also made buffer 2's write visible to compute.
        assert_eq!(t.declare(&[u(2, Access::COMPUTE_READ)]), None);
    }

    #[test]
    fn a_write_declared_with_a_read_is_not_made_visible_by_its_own_barrier() {
        let mut t = Tracker::default();
        t.declare(&[u(1, Access::COMPUTE_WRITE)]);
        // Reading 1 and writing 2 in the same commands: the barrier before
        // them cannot make 2's write visible.
        assert!(t
            .declare(&[u(1, Access::COMPUTE_READ), u(2, Access::COMPUTE_WRITE)])
            .is_some());
        assert!(t.declare(&[u(2, Access::COMPUTE_READ)]).is_some());
    }

    #[test]
    fn a_buffer_read_by_another_stage_in_the_commands_that_write_it_is_not_visible_after() {
        let mut t = Tracker::default();
        let rw_and_indirect = [
            u(1, Access::COMPUTE_READ_WRITE),
            u(1, Access::DRAW_INDIRECT),
        ];
        t.declare(&rw_and_indirect);
        // The same again: its indirect read waits for the last write.
        let d = t.declare(&rw_and_indirect).unwrap();
        assert!(covers(d.dst_stage, vk::PipelineStageFlags2::DRAW_INDIRECT));
        assert!(covers(
            d.src_stage,
            vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::DRAW_INDIRECT
        ));
    }

    #[test]
    fn reads_of_unrelated_buffers_need_nothing_after_their_first() {
        let mut t = Tracker::default();
        t.declare(&[u(1, Access::COMPUTE_READ)]);
        assert_eq!(t.declare(&[u(1, Access::COMPUTE_READ)]), None);
        assert!(t.declare(&[u(2, Access::COMPUTE_READ)]).is_some());
    }

    fn img(n: u64, layout_before: vk::ImageLayout, access: Access, discard: bool) -> ImageRequest {
        ImageRequest {
            image: vk::Handle::from_raw(n),
            range: vk::ImageSubresourceRange::default(),
            layout_before,
            access,
            discard,
        }
    }

    #[test]
    fn an_image_changes_layout_once_and_waits_for_its_writer() {
        let mut t = Tracker::default();
        let clear = img(
            7,
            vk::ImageLayout::UNDEFINED,
            Access::DEPTH_ATTACHMENT,
            true,
        );
        let b = t.declare_all(&[], &[clear]);
        assert_eq!(b.memory, None);
        assert_eq!(b.images.len(), 1);
        assert_eq!(b.images[0].old_layout, vk::ImageLayout::UNDEFINED);
        assert_eq!(b.images[0].new_layout, Access::DEPTH_ATTACHMENT.layout);
        // Discarding still waits for whatever came before.
        assert_eq!(
            b.images[0].dependency.src_stage,
            vk::PipelineStageFlags2::ALL_COMMANDS
        );
        // Sampled next: a transition waiting for the depth writes.
        let sample = img(
            7,
            vk::ImageLayout::UNDEFINED,
            Access::FRAGMENT_SAMPLED,
            false,
        );
        let b = t.declare_all(&[], &[sample]);
        let [barrier] = b.images[..] else {
            panic!("one transition: {b:?}")
        };
        assert_eq!(barrier.old_layout, Access::DEPTH_ATTACHMENT.layout);
        assert_eq!(barrier.new_layout, Access::FRAGMENT_SAMPLED.layout);
        assert!(covers(
            barrier.dependency.src_stage,
            Access::DEPTH_ATTACHMENT.stage
        ));
        assert!(covers(
            barrier.dependency.src_access,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
        ));
        // Sampled again by the same stage: nothing.
        assert!(t.declare_all(&[], &[sample]).is_empty());
    }

    #[test]
    fn an_image_starts_from_the_layout_it_was_left_in() {
        let mut t = Tracker::default();
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        // A texture uploaded earlier, sampled: no transition, a global
        // barrier for the unknown writes before.
        let b = t.declare_all(&[], &[img(3, read, Access::FRAGMENT_SAMPLED, false)]);
        assert!(b.images.is_empty());
        assert!(b.memory.is_some());
        // Sampled by compute next: the layout holds, a reader needs only
        // what is not yet visible to it.
        let b = t.declare_all(&[], &[img(3, read, Access::COMPUTE_SAMPLED, false)]);
        assert!(b.images.is_empty());
    }

    #[test]
    fn a_read_in_another_stage_after_a_transition_chains_through_it() {
        let mut t = Tracker::default();
        t.declare_all(
            &[],
            &[img(5, vk::ImageLayout::UNDEFINED, Access::COPY_WRITE, true)],
        );
        t.declare_all(
            &[],
            &[img(
                5,
                vk::ImageLayout::UNDEFINED,
                Access::COMPUTE_SAMPLED,
                false,
            )],
        );
        let b = t.declare_all(
            &[],
            &[img(
                5,
                vk::ImageLayout::UNDEFINED,
                Access::FRAGMENT_SAMPLED,
                false,
            )],
        );
        let dep = b.memory.expect("the fragment stage waits");
        assert!(covers(dep.src_stage, Access::COMPUTE_SAMPLED.stage));
    }
}
