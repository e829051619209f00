//! The simulation beside the drawing (`render.overlap`): a frame's wind
//! and grass steps go to the GPU in a submission of their own, on the
//! queue beside the main one where the device has one, while the frame
//! before is drawn. The steps write blades of their own (the simulated
//! control points); the submission ends by copying them into the blades
//! the passes draw, once the frame before has finished reading those.
//!
//! Two timeline semaphores order it, with no wait on the host:
//!
//! steps(n) -> copy into the drawn blades -> signal `simulated` = n
//! draw(n) waits `simulated` = n ... signals `drawn` = n
//! steps(n + 1) run while draw(n) does; their copy waits `drawn` = n.
//!
//! A change to the wind or the colliders made after a frame's steps were
//! submitted shows a frame later: the one frame of latency. On a device
//! with one queue the same submissions run in order on it: no overlap on
//! the GPU, but the host reads a frame back while the next frame's steps
//! run.

use ash::vk;

use super::record::{record_steps, Timer};
use super::timing::Phase;
use crate::compute::Simulation;
use crate::error::{Error, Result};
use crate::gpu::query::SpanTimer;
use crate::gpu::{Access, Buffer, BufferUse, CommandPool, Gpu, Timeline};

pub(super) struct Ahead {
    /// The steps' submissions (on the queue beside the main one).
    commands: CommandPool,
    /// Spans of the wind and grass steps in them.
    timer: Option<SpanTimer<Phase>>,
    /// The steps' own blades, which the grass step writes.
    simulated_blades: Buffer,
    /// Signalled when a submission of steps has copied its blades into
    /// the drawn ones.
    simulated: Timeline,
    /// Signalled when a frame's drawing, the last reader of the drawn
    /// blades, is done.
    drawn: Timeline,
    /// The steps submitted for the next frame, not drawn yet.
    in_flight: Option<u64>,
    /// On a queue of their own (else in order on the main one).
    own_queue: bool,
}

impl Ahead {
    /// `simulated_blades`: the steps' blades, holding the same rest shape
    /// as the drawn ones.
    pub(super) fn new(gpu: &Gpu, simulated_blades: Buffer) -> Result<Self> {
        Ok(Self {
            commands: CommandPool::on_simulation_queue(
                gpu,
                "simulation commands (beside the drawing)",
            )?,
            timer: SpanTimer::new(gpu, 16, "simulation step timestamps")?,
            simulated_blades,
            simulated: Timeline::new(gpu, "simulated blades copied (timeline)")?,
            drawn: Timeline::new(gpu, "drawn blades read (timeline)")?,
            in_flight: None,
            own_queue: gpu.has_simulation_queue(),
        })
    }

    /// The blades the simulation writes (its grass step's output).
    pub(super) fn simulated_blades(&self) -> &Buffer {
        &self.simulated_blades
    }

    /// The steps submitted for the next frame, if any.
    pub(super) fn in_flight(&self) -> Option<u64> {
        self.in_flight
    }

    /// Submits `steps` steps of `simulation` and the copy of their blades
    /// into `drawn_blades`, to run beside whatever the main queue draws;
    /// the copy waits for the last frame drawn. Their timings are read by
    /// `collect`, the steps' own waits by `settle`.
    /// `gpu` where the steps are timed (a frame's), None where not.
    pub(super) fn submit(
        &mut self,
        gpu: Option<&Gpu>,
        simulation: &mut Simulation,
        drawn_blades: &Buffer,
        steps: u64,
    ) -> Result<()> {
        if let Some(steps) = self.in_flight {
            return Err(Error::InvalidInput(format!(
                "{steps} simulation steps are already on their way to the next frame; draw it first"
            )));
        }
        // The pool waits for its last submission before recording again:
        // its timer is free to resize.
        self.commands.wait("the simulation's last steps")?;
        if let (Some(gpu), Some(timer)) = (gpu, self.timer.as_mut()) {
            let pairs = u32::try_from(steps.saturating_mul(2)).map_err(|_| {
                Error::InvalidInput(format!(
                    "{steps} simulation steps in one frame are too many to time"
                ))
            })?;
            timer.reserve(gpu, pairs.max(1))?;
        }
        let rec = self.commands.begin()?;
        let timer = gpu.and(self.timer.as_mut());
        let mut t = Timer(timer, None);
        t.reset(&rec);
        record_steps(simulation, &rec, &mut t, glam::Vec2::ZERO, steps)?;
        rec.uses(&[
            BufferUse::new(&self.simulated_blades, Access::COPY_READ),
            BufferUse::new(drawn_blades, Access::TRANSFER_WRITE),
        ]);
        rec.copy_buffer(&self.simulated_blades, drawn_blades, drawn_blades.size);
        let waits: Vec<_> = self
            .drawn
            .wait_last(vk::PipelineStageFlags2::ALL_TRANSFER)
            .into_iter()
            .collect();
        let signals = [self
            .simulated
            .signal_next(vk::PipelineStageFlags2::ALL_COMMANDS)];
        rec.submit("simulating beside the drawing", &waits, &signals)?;
        self.in_flight = Some(steps);
        Ok(())
    }

    /// The frame about to be drawn takes the steps in flight: they must be
    /// `steps` (0 with none in flight and none asked).
    pub(super) fn take(&mut self, steps: u64) -> Result<()> {
        match self.in_flight.take() {
            Some(n) if n == steps => Ok(()),
            None if steps == 0 => Ok(()),
            in_flight => {
                let had = in_flight.unwrap_or(0);
                self.in_flight = in_flight;
                Err(Error::InvalidInput(format!(
                    "a frame of {steps} simulation steps drawn after {had} were simulated ahead for it"
                )))
            }
        }
    }

    /// Waits on the host for the steps submitted last: before the host
    /// changes what they read (the wind's drive), or asks whether to go on.
    pub(super) fn settle(&self) -> Result<()> {
        self.commands.wait("the simulation's steps")
    }

    /// The wind and grass milliseconds of the steps submitted last, once
    /// they are done (waited for here); None without timestamps.
    pub(super) fn collect(&self) -> Result<Option<(f64, f64)>> {
        self.settle()?;
        let Some(timer) = &self.timer else {
            return Ok(None);
        };
        let (mut wind, mut grass) = (0.0, 0.0);
        for (phase, ms) in timer.read()? {
            match phase {
                Phase::Wind => wind += ms,
                Phase::Grass => grass += ms,
                _ => {}
            }
        }
        Ok(Some((wind, grass)))
    }

    /// What the frame's first graphics submission waits for: the last
    /// steps' copy into the drawn blades.
    pub(super) fn waits(&self) -> Vec<vk::SemaphoreSubmitInfo<'static>> {
        self.simulated
            .wait_last(vk::PipelineStageFlags2::ALL_COMMANDS)
            .into_iter()
            .collect()
    }

    /// What the frame's last graphics submission signals: done reading
    /// the drawn blades. Only for a submission that is made.
    pub(super) fn signals(&self) -> Vec<vk::SemaphoreSubmitInfo<'static>> {
        vec![self
            .drawn
            .signal_next(vk::PipelineStageFlags2::ALL_COMMANDS)]
    }

    /// Whether the steps run on a queue of their own.
    pub(super) fn own_queue(&self) -> bool {
        self.own_queue
    }
}
