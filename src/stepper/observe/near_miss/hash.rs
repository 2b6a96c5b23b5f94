//! The hasher of the observer's maps, keyed by pairs of body indices.

/// The observer's maps hash their pairs of body indices by one multiply
/// and rotate per index: the standard library's SipHash is made to resist
/// crafted keys, which costs time on every lookup, and these keys are the
/// run's own.
pub(super) type PairHash = std::hash::BuildHasherDefault<PairHasher>;

/// See [`PairHash`].
#[derive(Default)]
pub(super) struct PairHasher(u64);

impl std::hash::Hasher for PairHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(5) ^ value).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    fn write_usize(&mut self, value: usize) {
        self.write_u64(value as u64);
    }
}
