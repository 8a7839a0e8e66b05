//! 64-bit FNV-1a: a hash that is the same across Rust versions, platforms and processes (std's
//! hashers are not guaranteed to be), for keys that outlive a process (the generated meshes'
//! cache names) and for comparing a collective call's arguments across ranks.

/// An FNV-1a hash being built; [`Fnv::finish`] gives its value.
pub(crate) struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv::new()
    }
}

impl Fnv {
    /// The empty hash (FNV's offset basis).
    pub(crate) fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    /// Hashes in `b`, byte by byte.
    pub(crate) fn bytes(&mut self, b: &[u8]) -> &mut Self {
        for &x in b {
            self.0 ^= u64::from(x);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        self
    }

    /// Hashes in `v` (little-endian bytes).
    pub(crate) fn u64(&mut self, v: u64) -> &mut Self {
        self.bytes(&v.to_le_bytes())
    }

    /// Hashes in `b` after its length, so that the boundaries of consecutive fields cannot be
    /// confused.
    pub(crate) fn field(&mut self, b: &[u8]) -> &mut Self {
        self.u64(b.len() as u64).bytes(b)
    }

    /// The hash value.
    pub(crate) fn finish(&self) -> u64 {
        self.0
    }

    /// The hash value as 16 hex digits (names of cached meshes and stored cases).
    pub(crate) fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::Fnv;

    #[test]
    fn fnv1a_reference_values() {
        // The published FNV-1a 64 test vectors.
        assert_eq!(Fnv::new().finish(), 0xcbf2_9ce4_8422_2325);
        assert_eq!(Fnv::new().bytes(b"a").finish(), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(Fnv::new().bytes(b"foobar").finish(), 0x8594_4171_f739_67e8);
        // A field is its length, then its bytes.
        assert_eq!(Fnv::new().field(b"ab").finish(), Fnv::new().u64(2).bytes(b"ab").finish());
        assert_ne!(Fnv::new().field(b"ab").field(b"").finish(), Fnv::new().field(b"a").field(b"b").finish());
    }
}
