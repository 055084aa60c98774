//! FNV-1a, the 64-bit digest vkgi uses to tell data apart where equal bits are what matters (the
//! reference cache's keys, the lattices a CAVE's nodes compare): fast, stable across runs,
//! builds and machines, and not meant to resist tampering.

pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// `hash` extended by `bytes` (start from [`FNV_OFFSET`]).
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>, mut hash: u64) -> u64 {
    for b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_published_fnv1a_64_vectors() {
        assert_eq!(fnv1a([], FNV_OFFSET), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(*b"a", FNV_OFFSET), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(*b"foobar", FNV_OFFSET), 0x8594_4171_f739_67e8);
    }
}
