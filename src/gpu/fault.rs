//! Injected faults: the failure paths no healthy device takes, made to
//! happen on purpose so the reliability tests can walk them. The N-th
//! device-memory allocation fails as VK_ERROR_OUT_OF_DEVICE_MEMORY, or the
//! N-th queue submission finds the device lost (and so does every one after
//! it: a lost device stays lost). The errors say they were injected.
//!
//! Set through `GpuOptions::faults`; the binary reads MEADOW_INJECT_FAULT,
//! e.g. `out-of-device-memory@3` or `device-lost@5` (comma-separated).
//! Its item `list` prints each allocation and submission to stderr as it
//! is counted, `meadow: fault hook: allocation N: WHAT`, so that a test
//! can choose which to fail from one run.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// Which operations fail, counted from 1 over the GPU's whole life.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FaultPlan {
    pub out_of_device_memory_at: Option<u64>,
    pub device_lost_at: Option<u64>,
    /// Print every operation counted (the item `list`).
    pub list: bool,
}

const OOM: &str = "out-of-device-memory";
const LOST: &str = "device-lost";
const LIST: &str = "list";

impl FaultPlan {
    /// Parses `KIND@N[,KIND@N]` and `list`; the empty string plans no
    /// fault.
    pub fn parse(text: &str) -> Result<Self> {
        let mut plan = Self::default();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let bad = || {
                Error::InvalidInput(format!(
                    "MEADOW_INJECT_FAULT item {item:?} is not KIND@N with KIND {OOM} or {LOST} and N >= 1, nor {LIST}"
                ))
            };
            if item == LIST {
                plan.list = true;
                continue;
            }
            let (kind, n) = item.split_once('@').ok_or_else(bad)?;
            let n: u64 = n.parse().ok().filter(|&n| n >= 1).ok_or_else(bad)?;
            match kind {
                OOM => plan.out_of_device_memory_at = Some(n),
                LOST => plan.device_lost_at = Some(n),
                _ => return Err(bad()),
            }
        }
        Ok(plan)
    }
}

/// The plan and the counts of allocations and submissions so far.
#[derive(Debug, Default)]
pub struct Faults {
    plan: FaultPlan,
    allocations: AtomicU64,
    submissions: AtomicU64,
}

impl Faults {
    pub fn new(plan: FaultPlan) -> Self {
        Self {
            plan,
            ..Default::default()
        }
    }

    /// Counts one allocation of `what`; the planned one fails.
    pub fn allocation(&self, what: &str) -> Result<()> {
        let n = self.allocations.fetch_add(1, Ordering::Relaxed) + 1;
        if self.plan.list {
            eprintln!("meadow: fault hook: allocation {n}: {what}");
        }
        if self.plan.out_of_device_memory_at == Some(n) {
            return Err(Error::OutOfDeviceMemory {
                what: format!("{what} (injected: allocation {n})"),
            });
        }
        Ok(())
    }

    /// Counts one queue submission for `what`; from the planned one on,
    /// the device is lost.
    pub fn submission(&self, what: &str) -> Result<()> {
        let n = self.submissions.fetch_add(1, Ordering::Relaxed) + 1;
        if self.plan.list {
            eprintln!("meadow: fault hook: submission {n}: {what}");
        }
        match self.plan.device_lost_at {
            Some(at) if n >= at => Err(Error::DeviceLost {
                during: format!("{what} (injected: submission {n})"),
            }),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_plans_and_refuses_nonsense() {
        assert_eq!(FaultPlan::parse("").unwrap(), FaultPlan::default());
        let plan = FaultPlan::parse("out-of-device-memory@3, device-lost@7").unwrap();
        assert_eq!(plan.out_of_device_memory_at, Some(3));
        assert_eq!(plan.device_lost_at, Some(7));
        assert!(!plan.list);
        assert!(FaultPlan::parse("list").unwrap().list);
        for bad in ["device-lost", "device-lost@0", "lost@2", "device-lost@x"] {
            let e = FaultPlan::parse(bad).unwrap_err().to_string();
            assert!(e.contains("MEADOW_INJECT_FAULT") && e.contains(bad), "{e}");
        }
    }

    #[test]
    fn the_planned_allocation_fails_and_a_lost_device_stays_lost() {
        let faults = Faults::new(FaultPlan::parse("out-of-device-memory@2,device-lost@2").unwrap());
        assert!(faults.allocation("a").is_ok());
        let e = faults.allocation("b").unwrap_err();
        assert!(matches!(e, Error::OutOfDeviceMemory { .. }), "{e}");
        assert!(faults.allocation("c").is_ok());
        assert!(faults.submission("x").is_ok());
        for _ in 0..3 {
            let e = faults.submission("y").unwrap_err();
            assert!(matches!(e, Error::DeviceLost { .. }), "{e}");
        }
    }
}
