//! How many simulation steps go to the GPU in one submission when nothing
//! but a stop waits for them (steps toward a frame far ahead, a trace's
//! steps between samples): as many as the last submission's pace fits in
//! `SUBMISSION_TARGET` of wall time. A stop (Ctrl-C, SIGTERM) is seen
//! between submissions, so it waits at most about that for the GPU, on a
//! busy machine too: the pace is measured as it goes, not assumed. A fixed
//! count cannot do this: 8 steps of Table 1's wind took 0.3 s on an idle
//! lavapipe and 3.2 s on a loaded one.

use std::time::{Duration, Instant};

/// Wall time one submission of steps aims at.
pub const SUBMISSION_TARGET: Duration = Duration::from_millis(250);

/// The most steps in one submission, however fast they run: a device
/// that has sped up is measured again soon.
pub const MOST_STEPS: u64 = 64;

/// The pace of the last submission of steps.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepPace {
    seconds_per_step: Option<f64>,
}

impl StepPace {
    /// Steps for the next submission, of `left` still to run: one while
    /// nothing is measured yet.
    pub fn next(&self, left: u64) -> u64 {
        let fit = match self.seconds_per_step {
            None => 1,
            Some(s) if s <= 0.0 => MOST_STEPS,
            Some(s) => (SUBMISSION_TARGET.as_secs_f64() / s) as u64,
        };
        fit.clamp(1, MOST_STEPS).min(left)
    }

    /// A submission of `steps` took `took`, waiting for the GPU included.
    pub fn ran(&mut self, steps: u64, took: Duration) {
        if steps > 0 {
            self.seconds_per_step = Some(took.as_secs_f64() / steps as f64);
        }
    }

    /// Runs the next batch of `left` steps through `submit` (which submits
    /// and waits for them), timing it for the batch after; returns how
    /// many steps it ran.
    pub fn run<E>(
        &mut self,
        left: u64,
        submit: impl FnOnce(u64) -> Result<(), E>,
    ) -> Result<u64, E> {
        let batch = self.next(left);
        let started = Instant::now();
        submit(batch)?;
        self.ran(batch, started.elapsed());
        Ok(batch)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_batch_fits_the_target_at_the_last_pace() {
        let mut pace = StepPace::default();
        assert_eq!(pace.next(1000), 1, "nothing measured: one step");
        assert_eq!(pace.next(0), 0);
        pace.ran(1, Duration::from_millis(10));
        assert_eq!(pace.next(1000), 25);
        assert_eq!(pace.next(7), 7, "never more than is left");
        // A machine that got busy: the next batch shrinks at once.
        pace.ran(25, Duration::from_millis(2500));
        assert_eq!(pace.next(1000), 2);
        pace.ran(2, Duration::from_secs(3));
        assert_eq!(pace.next(1000), 1, "at least one step");
        pace.ran(1, Duration::from_micros(1));
        assert_eq!(pace.next(1000), MOST_STEPS);
        pace.ran(64, Duration::ZERO);
        assert_eq!(pace.next(1000), MOST_STEPS);
        // `run` submits the next batch and times it for the one after.
        let mut pace = StepPace::default();
        let mut submitted = Vec::new();
        let ran = pace.run(1000, |batch| {
            submitted.push(batch);
            std::thread::sleep(Duration::from_millis(50));
            Ok::<(), ()>(())
        });
        assert_eq!((ran, submitted), (Ok(1), vec![1]));
        // A step took at least 50 ms: at most 5 fit in 250 ms.
        assert!(pace.next(1000) <= 5, "{}", pace.next(1000));
        assert_eq!(pace.run(10, |_| Err("refused")), Err("refused"));
    }
}
