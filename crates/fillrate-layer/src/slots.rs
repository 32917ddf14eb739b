//! Query slots of one command buffer: pools of one query type grown in chunks, and a cursor.
//! Slots are reset with vkCmdResetQueryPool only outside a render pass, so each measured render
//! pass reserves (resets) enough fresh slots before it begins, and takes from them inside.

use ash::vk;

/// Queries per pool chunk.
pub const CHUNK: u32 = 64;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QueryKind {
    Occlusion,
    Statistics,
    Timestamp,
    /// Pipeline statistics of compute-shader invocations only (work.rs).
    Compute,
}

/// One query: its pool and index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Slot {
    pub pool: vk::QueryPool,
    pub query: u32,
}

/// A command the layer records into the application's command buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QueryCmd {
    Reset { pool: vk::QueryPool, first: u32, count: u32 },
    Begin { slot: Slot, precise: bool },
    End { slot: Slot },
    Timestamp { slot: Slot, stage: vk::PipelineStageFlags },
}

#[derive(Debug)]
pub struct SlotPool {
    pub kind: QueryKind,
    pub pools: Vec<vk::QueryPool>,
    next: u32,
    reset_until: u32,
}

impl SlotPool {
    pub fn new(kind: QueryKind) -> Self {
        SlotPool { kind, pools: Vec::new(), next: 0, reset_until: 0 }
    }

    /// A new recording: every slot is free again (and must be reset again before use).
    pub fn restart(&mut self) {
        self.next = 0;
        self.reset_until = 0;
    }

    /// Makes `count` more slots from the cursor usable, appending their resets to `out` and
    /// creating pools with `create`; false when a pool could not be created.
    pub fn reserve(
        &mut self,
        count: u32,
        create: &mut dyn FnMut(QueryKind) -> Option<vk::QueryPool>,
        out: &mut Vec<QueryCmd>,
    ) -> bool {
        let target = self.next + count;
        while self.reset_until < target {
            let chunk = (self.reset_until / CHUNK) as usize;
            while self.pools.len() <= chunk {
                match create(self.kind) {
                    Some(pool) => self.pools.push(pool),
                    None => return false,
                }
            }
            let first = self.reset_until % CHUNK;
            let count = (CHUNK - first).min(target - self.reset_until);
            out.push(QueryCmd::Reset { pool: self.pools[chunk], first, count });
            self.reset_until += count;
        }
        true
    }

    /// `n` consecutive reset slots in one pool, the first returned (a multiview pass's query
    /// takes one index per view): slots up to the next pool are skipped when the run would
    /// cross into it.
    pub fn take_run(&mut self, n: u32) -> Option<Slot> {
        let n = n.max(1);
        if n > CHUNK {
            return None;
        }
        if self.next % CHUNK + n > CHUNK {
            self.next = (self.next / CHUNK + 1) * CHUNK;
        }
        if self.next + n > self.reset_until {
            return None;
        }
        let first = self.take();
        self.next += n - 1;
        first
    }

    /// The next reset slot, if any is left.
    pub fn take(&mut self) -> Option<Slot> {
        if self.next >= self.reset_until {
            return None;
        }
        let slot = Slot { pool: self.pools[(self.next / CHUNK) as usize], query: self.next % CHUNK };
        self.next += 1;
        Some(slot)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    /// Pools 1, 2, 3... as they are created.
    fn numbered_pools() -> impl FnMut(QueryKind) -> Option<vk::QueryPool> {
        let mut created = 0u64;
        move |_| {
            created += 1;
            Some(vk::QueryPool::from_raw(created))
        }
    }

    #[test]
    fn reserve_resets_fresh_slots_across_chunks_and_take_stops_at_the_reserve() {
        let mut create = numbered_pools();
        let mut slots = SlotPool::new(QueryKind::Occlusion);
        let mut cmds = Vec::new();
        assert!(slots.reserve(CHUNK - 2, &mut create, &mut cmds));
        for _ in 0..CHUNK - 2 {
            assert!(slots.take().is_some());
        }
        assert_eq!(slots.take(), None);
        assert!(slots.reserve(4, &mut create, &mut cmds));
        let pool = |n| vk::QueryPool::from_raw(n);
        assert_eq!(
            cmds,
            vec![
                QueryCmd::Reset { pool: pool(1), first: 0, count: CHUNK - 2 },
                QueryCmd::Reset { pool: pool(1), first: CHUNK - 2, count: 2 },
                QueryCmd::Reset { pool: pool(2), first: 0, count: 2 },
            ]
        );
        assert_eq!(slots.take(), Some(Slot { pool: pool(1), query: CHUNK - 2 }));
        slots.take();
        assert_eq!(slots.take(), Some(Slot { pool: pool(2), query: 0 }));
        // A new recording reuses the pools and resets from the start again.
        slots.restart();
        cmds.clear();
        assert!(slots.reserve(1, &mut create, &mut cmds));
        assert_eq!(cmds, vec![QueryCmd::Reset { pool: pool(1), first: 0, count: 1 }]);
        assert_eq!(slots.pools.len(), 2);
    }

    #[test]
    fn a_run_of_slots_stays_in_one_pool_and_within_the_reserve() {
        let mut create = numbered_pools();
        let mut slots = SlotPool::new(QueryKind::Occlusion);
        let mut cmds = Vec::new();
        assert!(slots.reserve(CHUNK + 4, &mut create, &mut cmds));
        for _ in 0..CHUNK - 2 {
            slots.take();
        }
        // Two slots are left in the first pool: a run of three starts in the second.
        let run = slots.take_run(3).expect("a run");
        assert_eq!(run, Slot { pool: vk::QueryPool::from_raw(2), query: 0 });
        assert_eq!(slots.take(), Some(Slot { pool: vk::QueryPool::from_raw(2), query: 3 }));
        assert_eq!(slots.take_run(2), None, "past the reserve");
    }
}
