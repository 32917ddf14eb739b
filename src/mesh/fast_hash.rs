//! A hash map for `u64` keys that are already well spread (packed vertex pairs, grid cells).
//!
//! std's SipHash is built to resist hostile keys; ours come from our own meshes, and SipHash
//! costs more than the rest of the edge extraction. One multiply and a fold is enough, and it
//! spares a dependency.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A `HashMap` keyed by `u64` with [`U64Hasher`].
pub(crate) type U64Map<V> = HashMap<u64, V, BuildHasherDefault<U64Hasher>>;

/// Creates an empty [`U64Map`] with room for `capacity` keys.
pub(crate) fn u64_map_with_capacity<V>(capacity: usize) -> U64Map<V> {
    HashMap::with_capacity_and_hasher(capacity, BuildHasherDefault::default())
}

/// Multiplicative hash (Fibonacci constant, as FxHash) with the high half folded down, because
/// the table picks buckets from the low bits and a bare product's low bits only see the key's
/// low bits: all edges sharing their larger vertex would land in one bucket chain.
#[derive(Default, Clone, Copy)]
pub(crate) struct U64Hasher {
    state: u64,
}

const FIBONACCI: u64 = 0x9E37_79B9_7F4A_7C15;

impl Hasher for U64Hasher {
    fn finish(&self) -> u64 {
        let product = self.state.wrapping_mul(FIBONACCI);
        product ^ (product >> 32)
    }

    fn write_u64(&mut self, value: u64) {
        self.state = (self.state.rotate_left(5) ^ value).wrapping_mul(FIBONACCI);
    }

    // Only reached if someone keys the map with something other than u64; still correct.
    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn edges_sharing_a_vertex_spread_over_low_bits() {
        // 64 edges with the same larger vertex must not all share their low 6 bits of hash.
        let buckets: HashSet<u64> = (0..64u64)
            .map(|low| {
                let mut hasher = U64Hasher::default();
                hasher.write_u64((low << 32) | 1000);
                hasher.finish() & 63
            })
            .collect();
        assert!(
            buckets.len() > 32,
            "only {} distinct buckets",
            buckets.len()
        );
    }
}
