//! A command pool's journal: what its recordings declare, the barriers
//! and layout transitions that follow, and the commands between them
//! (pipelines bound, dispatches, draws, copies, submissions), in words and
//! by the objects' debug names. Off unless started: it is for a person
//! asking why a barrier is where it is (`CommandPool::journal`; a frame's
//! is its recorder's pool's, `FrameRecorder::commands`), and for the
//! snapshot test that holds one frame's (tests/frame_journal.rs).

use std::cell::RefCell;

use ash::vk;

use crate::gpu::barrier::Access;

/// The lines written since `start`, or None while off.
#[derive(Default)]
pub struct Journal {
    lines: RefCell<Option<Vec<String>>>,
}

impl Journal {
    /// Starts writing (again, from nothing).
    pub fn start(&self) {
        *self.lines.borrow_mut() = Some(Vec::new());
    }

    /// The lines written since `start`, and stops writing.
    pub fn take(&self) -> Vec<String> {
        self.lines.borrow_mut().take().unwrap_or_default()
    }

    /// Writes the line `line` makes, when on (`line` is not called when off).
    pub(super) fn note(&self, line: impl FnOnce() -> String) {
        if let Some(lines) = self.lines.borrow_mut().as_mut() {
            lines.push(line());
        }
    }
}

/// An access as the journal writes it: its stages, accesses and layout.
pub(super) fn access_text(access: Access) -> String {
    let mut text = format!("{:?} / {:?}", access.stage, access.access);
    if access.layout != vk::ImageLayout::UNDEFINED {
        text.push_str(&format!(" in {:?}", access.layout));
    }
    text
}

/// One barrier's source and destination as the journal writes them.
pub(super) fn dependency_text(
    src_stage: vk::PipelineStageFlags2,
    src_access: vk::AccessFlags2,
    dst_stage: vk::PipelineStageFlags2,
    dst_access: vk::AccessFlags2,
) -> String {
    format!("{src_stage:?} / {src_access:?} -> {dst_stage:?} / {dst_access:?}")
}
