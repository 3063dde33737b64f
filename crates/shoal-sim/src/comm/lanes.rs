//! What the medium's lane kernels share: four lanes of a quantity ([`Lane`]), up to four
//! poses as structure of arrays ([`PoseLanes`]), and one way to run a kernel with the widest
//! vectors this CPU has: [`avx_dispatch!`] defines a function that calls the kernel compiled
//! for AVX when the running CPU has it, and as compiled for the baseline otherwise. The
//! kernels do the same IEEE operations in every width (no fused multiply-adds, which Rust never
//! contracts implicitly), so the bits do not depend on which copy ran.

/// Lanes per chunk.
pub(super) const W: usize = 4;

/// Four lanes of one quantity.
pub(super) type Lane = [f64; W];

/// Up to [`W`] poses (an LED's or a photodiode's): positions \[m\] and unit axes.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PoseLanes {
    pub(super) px: Lane,
    pub(super) py: Lane,
    pub(super) pz: Lane,
    pub(super) ax: Lane,
    pub(super) ay: Lane,
    pub(super) az: Lane,
}

/// `avx_dispatch!(/// doc
/// pub(super) fn name(a: A, b: B) -> R => kernel);` defines `name` (with that visibility),
/// which calls the `#[inline(always)]` function `kernel` with the same arguments — through a
/// copy compiled with AVX enabled when the CPU has it (detected at run time), else directly.
macro_rules! avx_dispatch {
    ($(#[$doc:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty => $kernel:ident) => {
        $(#[$doc])*
        $vis fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            {
                /// The kernel compiled for AVX.
                #[target_feature(enable = "avx")]
                fn with_avx($($arg: $ty),*) -> $ret {
                    $kernel($($arg),*)
                }
                if std::arch::is_x86_feature_detected!("avx") {
                    #[expect(
                        unsafe_code,
                        reason = "a target-feature function is called only after the CPU feature is detected"
                    )]
                    // SAFETY: `with_avx` requires AVX, which the running CPU has (detected
                    // just above).
                    return unsafe { with_avx($($arg),*) };
                }
            }
            $kernel($($arg),*)
        }
    };
}

pub(super) use avx_dispatch;
