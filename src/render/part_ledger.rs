//! What each of a frame's independent parts touched, to hold them to the contract of
//! [`GiMethod::parts`](crate::gi::GiMethod::parts): parts may run at once, each on its own
//! compute queue, where no barrier orders one queue's accesses against another's, so no
//! resource one part writes may be read or written by another. Checked on every frame and every
//! device (one queue included), so a method that breaks it fails where its tests run.

use std::collections::HashMap;

use crate::gpu::{GpuError, GpuResult, ResourceKey, ResourceUse};

/// The first part that touched a resource, and whether any part so far wrote it.
struct Touch {
    part: usize,
    written: bool,
}

/// The resources a frame's parts touched so far.
#[derive(Default)]
pub struct PartLedger {
    touched: HashMap<ResourceKey, Touch>,
}

impl PartLedger {
    /// Part `part`'s accesses (`uses`); an error naming the resource and both parts (by
    /// `labels`) where it and another part touch one resource that either writes.
    pub fn add(&mut self, labels: &[&str], part: usize, uses: &[ResourceUse]) -> GpuResult<()> {
        for used in uses {
            let touch = self.touched.entry(used.key).or_insert(Touch {
                part,
                written: false,
            });
            if touch.part != part && (touch.written || used.writes) {
                let label = |p: usize| labels.get(p).copied().unwrap_or("?");
                return Err(GpuError::Setup(format!(
                    "the method's parts {} and {} both use {} and one of them writes it or \
                     changes its layout: parts may run at once on different queues, so they must \
                     not share what either writes (a shared image's layout is best set before \
                     the parts, in the method's light work)",
                    label(touch.part),
                    label(part),
                    used.name
                )));
            }
            touch.written |= used.writes;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn used(handle: u64, writes: bool) -> ResourceUse {
        ResourceUse {
            key: ResourceKey {
                handle,
                image: false,
            },
            name: format!("buffer {handle}"),
            writes,
        }
    }

    const LABELS: [&str; 3] = ["R", "G", "B"];

    #[test]
    fn parts_may_share_what_they_only_read() {
        let mut ledger = PartLedger::default();
        for part in 0..3 {
            let own = 10 + part as u64;
            let uses = [used(1, false), used(own, false), used(own, true)];
            ledger.add(&LABELS, part, &uses).unwrap();
        }
    }

    #[test]
    fn a_part_may_not_read_what_another_writes() {
        let mut ledger = PartLedger::default();
        ledger.add(&LABELS, 0, &[used(7, true)]).unwrap();
        let error = ledger.add(&LABELS, 1, &[used(7, false)]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the method's parts R and G both use buffer 7 and one of them writes it or changes \
             its layout: parts may run at once on different queues, so they must not share what \
             either writes (a shared image's layout is best set before the parts, in the \
             method's light work)"
        );
    }

    #[test]
    fn a_part_may_not_write_what_another_reads() {
        let mut ledger = PartLedger::default();
        ledger.add(&LABELS, 0, &[used(7, false)]).unwrap();
        ledger.add(&LABELS, 1, &[used(7, false)]).unwrap();
        let error = ledger.add(&LABELS, 2, &[used(7, true)]).unwrap_err();
        assert!(
            error
                .to_string()
                .contains("parts R and B both use buffer 7"),
            "{error}"
        );
    }
}
