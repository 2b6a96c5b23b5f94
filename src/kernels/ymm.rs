//! Four f64 lanes in an AVX2 register: the `Lane` the pair's candidates
//! run in side by side (`pair_lanes.rs`), and their masks.

use super::lanes::Lane;
use crate::math::Real;
use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// Four `f64` lanes in one AVX2 register.
#[derive(Copy, Clone)]
pub(super) struct Ymm(pub(super) __m256d);

/// A lane mask: all bits set (true) or clear (false) in each lane.
#[derive(Copy, Clone)]
pub(super) struct YmmMask(pub(super) __m256d);

// SAFETY (every `unsafe` block on `Ymm` and `YmmMask` below): the values
// only exist inside `pair_lanes.rs`'s AVX2 + FMA functions (see the module
// docs), into which these `#[inline(always)]` operations are inlined; the
// intrinsics need no more than AVX2 and FMA.

macro_rules! ymm_binary {
    ($trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for Ymm {
            type Output = Ymm;
            #[inline(always)]
            fn $method(self, other: Ymm) -> Ymm {
                // SAFETY: see above.
                Ymm(unsafe { $intrinsic(self.0, other.0) })
            }
        }
    };
}
ymm_binary!(Add, add, _mm256_add_pd);
ymm_binary!(Sub, sub, _mm256_sub_pd);
ymm_binary!(Mul, mul, _mm256_mul_pd);
ymm_binary!(Div, div, _mm256_div_pd);

impl Neg for Ymm {
    type Output = Ymm;
    /// Flips the sign bit, as `-x` on `f64` does.
    #[inline(always)]
    fn neg(self) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
}

impl BitAnd for YmmMask {
    type Output = YmmMask;
    #[inline(always)]
    fn bitand(self, other: YmmMask) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_and_pd(self.0, other.0) })
    }
}

impl BitOr for YmmMask {
    type Output = YmmMask;
    #[inline(always)]
    fn bitor(self, other: YmmMask) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_or_pd(self.0, other.0) })
    }
}

impl Not for YmmMask {
    type Output = YmmMask;
    #[inline(always)]
    fn not(self) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_xor_pd(self.0, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))) })
    }
}

/// Each operation is the IEEE operation `f64` performs, lane by lane; the
/// comparisons are ordered (`<`, `<=` false on NaN) except `!=` (true on
/// NaN), as in Rust; `min` and `max` are `vminpd`/`vmaxpd`, whose
/// definition (`a < b ? a : b`, `a > b ? a : b`) is the trait's default.
impl Lane for Ymm {
    type Mask = YmmMask;
    #[inline(always)]
    fn splat(x: Real) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_set1_pd(x) })
    }
    #[inline(always)]
    fn mul_add(self, a: Ymm, b: Ymm) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_fmadd_pd(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    fn lt(self, other: Ymm) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn le(self, other: Ymm) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn ne(self, other: Ymm) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_cmp_pd::<_CMP_NEQ_UQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn select(mask: YmmMask, yes: Ymm, no: Ymm) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_blendv_pd(no.0, yes.0, mask.0) })
    }
    #[inline(always)]
    fn min(self, other: Ymm) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_min_pd(self.0, other.0) })
    }
    #[inline(always)]
    fn max(self, other: Ymm) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_max_pd(self.0, other.0) })
    }
}

impl Ymm {
    /// The four lanes.
    #[inline(always)]
    pub(super) fn lanes(self) -> [Real; 4] {
        let mut out = [0.0; 4];
        // SAFETY: see above; `out` holds four f64.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
        out
    }

    /// Lane `K` in every lane (`K` given as the permutation `0x55 · K`).
    #[inline(always)]
    pub(super) fn broadcast<const PERMUTATION: i32>(self) -> Ymm {
        // SAFETY: see above.
        Ymm(unsafe { _mm256_permute4x64_pd::<PERMUTATION>(self.0) })
    }

    /// Bit `k` set where lane `k` equals `value`.
    #[inline(always)]
    pub(super) fn equal_bits(self, value: Real) -> u32 {
        // SAFETY: see above.
        unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, _mm256_set1_pd(value))) as u32 }
    }

    /// The least lane (no lane NaN).
    #[inline(always)]
    pub(super) fn least(self) -> Real {
        // SAFETY: see above.
        unsafe {
            let halves = _mm256_min_pd(self.0, _mm256_permute4x64_pd::<0b01_00_11_10>(self.0));
            let least = _mm256_min_pd(halves, _mm256_permute4x64_pd::<0b10_11_00_01>(halves));
            _mm256_cvtsd_f64(least)
        }
    }

    /// Lanes equal to `other`'s (false on NaN).
    #[inline(always)]
    pub(super) fn equal(self, other: Ymm) -> YmmMask {
        // SAFETY: see above.
        YmmMask(unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, other.0) })
    }

    /// `+∞` in lane `lane`, the lanes of `self` elsewhere.
    #[inline(always)]
    pub(super) fn knock_out(self, lane: usize) -> Ymm {
        let index = constants(0.0, 1.0, 2.0, 3.0);
        Ymm::select(index.equal(Ymm::splat(lane as Real)), Ymm::splat(Real::INFINITY), self)
    }
}

/// Four constants in lanes.
#[inline(always)]
pub(super) fn constants(w: Real, x: Real, y: Real, z: Real) -> Ymm {
    // SAFETY: see above.
    Ymm(unsafe { _mm256_setr_pd(w, x, y, z) })
}
