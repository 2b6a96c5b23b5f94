//! Runtime CPU-feature dispatch: one kernel body, compiled for several
//! instruction sets, the best chosen when called.
//!
//! The kernels use `mul_add` (fused multiply-add) for their compensated
//! products. Without a target feature that is a call into the C library;
//! with FMA enabled it is one instruction. The binary is built for the
//! x86-64 baseline, so every kernel is compiled three times (baseline,
//! AVX2 + FMA, AVX-512 + FMA) and [`SimdLevel::detect`] picks one at run
//! time. Results are bit-identical at every level: no floating-point
//! contraction is allowed by Rust, and `mul_add` is correctly rounded either
//! way.

use std::sync::atomic::{AtomicU8, Ordering};

/// An instruction-set level the kernels are compiled for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SimdLevel {
    /// The x86-64 baseline (SSE2), or the target's baseline elsewhere.
    Baseline = 1,
    /// AVX2 with FMA.
    Avx2 = 2,
    /// AVX-512 (F, DQ, VL) with FMA.
    Avx512 = 3,
}

static DETECTED: AtomicU8 = AtomicU8::new(0);

impl SimdLevel {
    /// The best level this CPU supports (detected once, then cached).
    #[inline]
    pub fn detect() -> SimdLevel {
        match DETECTED.load(Ordering::Relaxed) {
            1 => SimdLevel::Baseline,
            2 => SimdLevel::Avx2,
            3 => SimdLevel::Avx512,
            _ => {
                let level = Self::probe();
                DETECTED.store(level as u8, Ordering::Relaxed);
                level
            }
        }
    }

    fn probe() -> SimdLevel {
        #[cfg(target_arch = "x86_64")]
        {
            let avx2 = std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
            let avx512 = avx2
                && std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512dq")
                && std::is_x86_feature_detected!("avx512vl");
            if avx512 {
                return SimdLevel::Avx512;
            }
            if avx2 {
                return SimdLevel::Avx2;
            }
        }
        SimdLevel::Baseline
    }

    /// All levels up to and including the detected one.
    pub fn available() -> Vec<SimdLevel> {
        let best = SimdLevel::detect();
        [SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512].into_iter().filter(|l| *l <= best).collect()
    }

    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Baseline => "baseline",
            SimdLevel::Avx2 => "avx2+fma",
            SimdLevel::Avx512 => "avx512+fma",
        }
    }
}

/// Defines `$name(args)` (at the detected level) and `$name_with(level,
/// args)` (at the requested level, lowered to what the CPU supports) around
/// one body compiled once per level.
macro_rules! multiversioned {
    (
        $(#[$doc:meta])*
        $vis:vis fn $name:ident / $name_with:ident ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? $body:block
    ) => {
        $(#[$doc])*
        #[inline]
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            $name_with($crate::kernels::SimdLevel::detect(), $($arg),*)
        }

        #[doc = concat!("[`", stringify!($name), "`] at the given [`SimdLevel`](crate::kernels::SimdLevel) ")]
        /// (lowered to the best the CPU supports): for tests and benchmarks.
        /// Results are bit-identical at every level.
        #[allow(dead_code)]
        $vis fn $name_with(level: $crate::kernels::SimdLevel, $($arg: $ty),*) $(-> $ret)? {
            #[inline(always)]
            fn generic($($arg: $ty),*) $(-> $ret)? $body
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
                unsafe fn avx512($($arg: $ty),*) $(-> $ret)? { generic($($arg),*) }
                #[target_feature(enable = "avx2,fma")]
                unsafe fn avx2($($arg: $ty),*) $(-> $ret)? { generic($($arg),*) }
                match level.min($crate::kernels::SimdLevel::detect()) {
                    // SAFETY: the level is lowered to what this CPU supports.
                    $crate::kernels::SimdLevel::Avx512 => return unsafe { avx512($($arg),*) },
                    // SAFETY: as above.
                    $crate::kernels::SimdLevel::Avx2 => return unsafe { avx2($($arg),*) },
                    $crate::kernels::SimdLevel::Baseline => {}
                }
            }
            let _ = level;
            generic($($arg),*)
        }
    };
}
pub(crate) use multiversioned;
