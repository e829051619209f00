//! Barriers derived from what passes declare. A pass says, before the
//! commands it records, which buffers they touch and how (`BufferUse`: a
//! buffer and an `Access`); the recording remembers each buffer's last
//! write and the reads since, and emits the one barrier those commands
//! need: read after write (the write made visible to the reader), write
//! after write, and write after read (the readers finished first). A use
//! that needs nothing emits nothing: reads after reads, or a second reader
//! of a write already made visible to its stage.
//!
//! What a buffer went through before this recording is unknown (an
//! earlier submission, the host), so its first use here waits for any
//! earlier write and read. Every use of a buffer after its first in a
//! recording must be declared: an undeclared one is a hazard the
//! synchronization validation layer reports.

use std::collections::HashMap;

use ash::vk;

use crate::gpu::barrier::Access;
use crate::gpu::Buffer;

/// A buffer's identity, for declaring its uses: a pass may keep the ids of
/// buffers it binds but does not own (their owners outlive it).
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

/// One buffer's history in a recording.
#[derive(Clone, Copy, Debug)]
struct BufferState {
    /// The stages and write flags of the last write.
    write_stage: vk::PipelineStageFlags2,
    write_access: vk::AccessFlags2,
    /// Stages and flags the last write has been made visible to.
    visible_stage: vk::PipelineStageFlags2,
    visible_access: vk::AccessFlags2,
    /// Stages that read since the last write (a writer waits for them).
    read_stage: vk::PipelineStageFlags2,
}

impl BufferState {
    /// Before its first use in a recording: written and read by anything.
    const UNKNOWN: Self = Self {
        write_stage: vk::PipelineStageFlags2::ALL_COMMANDS,
        write_access: vk::AccessFlags2::MEMORY_WRITE,
        visible_stage: vk::PipelineStageFlags2::NONE,
        visible_access: vk::AccessFlags2::NONE,
        read_stage: vk::PipelineStageFlags2::ALL_COMMANDS,
    };
}

/// The source and destination of one global memory barrier.
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

/// Each declared buffer's history in one recording.
#[derive(Default)]
pub struct Tracker {
    buffers: HashMap<BufferId, BufferState>,
}

/// Whether `flags` holds every bit of `part`.
fn covers<T: Copy + std::ops::BitAnd<Output = T> + PartialEq>(flags: T, part: T) -> bool {
    flags & part == part
}

impl Tracker {
    /// Declares that the next commands make `uses`; returns the barrier
    /// they need (None: none), and remembers them.
    pub fn declare(&mut self, uses: &[BufferUse]) -> Option<Dependency> {
        // One access per buffer: all that these commands do to it.
        let mut merged: Vec<(BufferId, Access)> = Vec::with_capacity(uses.len());
        for &BufferUse { buffer, access } in uses {
            match merged.iter_mut().find(|(b, _)| *b == buffer) {
                Some((_, a)) => *a = a.and(access),
                None => merged.push((buffer, access)),
            }
        }
        let mut dep = Dependency::default();
        for &(buffer, access) in &merged {
            let state = self.buffers.entry(buffer).or_insert(BufferState::UNKNOWN);
            let writes = access.writes();
            let reads = access.access & !writes;
            let already_visible =
                covers(state.visible_stage, access.stage) && covers(state.visible_access, reads);
            if !reads.is_empty() && !already_visible {
                // Read after write.
                dep.src_stage |= state.write_stage;
                dep.src_access |= state.write_access;
                dep.dst_stage |= access.stage;
                dep.dst_access |= reads;
            }
            if !writes.is_empty() {
                // Write after write, and after the reads since.
                dep.src_stage |= state.write_stage | state.read_stage;
                dep.src_access |= state.write_access;
                dep.dst_stage |= access.stage;
                dep.dst_access |= writes;
            }
        }
        // A global barrier makes every write it waited for visible to its
        // whole destination, whichever buffer the write was to; then these
        // commands run.
        if !dep.is_empty() {
            for state in self.buffers.values_mut() {
                if covers(dep.src_stage, state.write_stage)
                    && covers(dep.src_access, state.write_access)
                {
                    state.visible_stage |= dep.dst_stage;
                    state.visible_access |= dep.dst_access;
                }
            }
        }
        for &(buffer, access) in &merged {
            let state = self.buffers.get_mut(&buffer).expect("inserted above");
            let writes = access.writes();
            if writes.is_empty() {
                state.visible_stage |= access.stage;
                state.visible_access |= access.access;
                state.read_stage |= access.stage;
            } else {
                // Written: visible to nobody yet; a later writer also
                // waits for the reads these same commands made.
                *state = BufferState {
                    write_stage: access.stage,
                    write_access: writes,
                    visible_stage: vk::PipelineStageFlags2::NONE,
                    visible_access: vk::AccessFlags2::NONE,
                    read_stage: access.stage,
                };
            }
        }
        if dep.is_empty() {
            return None;
        }
        Some(dep)
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
}
