//! Run-time dispatch of vectorised code to the widest vector unit of the processor.
//!
//! A [`BlockKernel`] (a loop over [`crate::Lanes`], for example a lane kernel over many groups
//! of points) runs through [`run_block_on`] compiled for one [`VectorPath`]: the target's
//! baseline (SSE2 on x86-64, two `f64` per register) or, where the processor has it, AVX2 (four
//! `f64` per register). The kernel's body is inlined into a copy of the caller compiled with
//! `#[target_feature(enable = "avx2")]`, so the same source becomes 256-bit instructions there.
//!
//! Every path gives the same bits. The kernels use only IEEE-754 basic operations (add,
//! subtract, multiply, divide, square root), comparisons and selects, which are correctly
//! rounded whatever the register width, and no path enables FMA (Rust never contracts
//! `a * b + c` by itself, and the kernels call no `mul_add`): a fused multiply-add would round
//! once where the baseline rounds twice. The one exception is which NaN comes out of an
//! operation on two NaNs, which IEEE-754 leaves open and the compiler may change by swapping
//! the operands of a sum or a product: a NaN may differ in sign between paths, only in lanes
//! that hold no result (a batch Jacobian's unreachable lanes). AVX-512 is not compiled: on the
//! one AVX-512 machine measured (an AMD EPYC, 2026-12-03) an `avx512f` copy of the kernels ran
//! 18–26 % slower than the AVX2 one (`docs/performance-log.md`).

use std::sync::OnceLock;

/// The environment variable that forces the baseline path when set to `baseline` (to compare
/// paths, or to rule the wide path out when chasing a difference).
pub const VECTOR_PATH_VARIABLE: &str = "PKM_VECTOR_PATH";

/// An instruction set that a lane kernel is compiled for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VectorPath {
    /// The compilation target's baseline (SSE2 on x86-64).
    Baseline,
    /// AVX2 on x86-64 (256-bit registers), without FMA.
    Avx2,
}

impl VectorPath {
    /// Whether this processor can run the path.
    pub fn is_available(self) -> bool {
        match self {
            Self::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            Self::Avx2 => false,
        }
    }

    /// Every path this processor can run, baseline first.
    pub fn available() -> Vec<Self> {
        [Self::Baseline, Self::Avx2]
            .into_iter()
            .filter(|path| path.is_available())
            .collect()
    }

    /// The path [`run_block`] takes: the widest available, or [`VectorPath::Baseline`] when
    /// the environment variable [`VECTOR_PATH_VARIABLE`] is `baseline`. Decided once per
    /// process.
    pub fn selected() -> Self {
        static SELECTED: OnceLock<VectorPath> = OnceLock::new();
        *SELECTED.get_or_init(|| {
            let forced = std::env::var(VECTOR_PATH_VARIABLE).is_ok_and(|v| v == "baseline");
            let widest = Self::available().into_iter().last();
            match widest {
                Some(path) if !forced => path,
                _ => Self::Baseline,
            }
        })
    }
}

/// A computation over a whole block of work (a loop over many groups of lanes), compiled for
/// one [`VectorPath`] by [`run_block_on`], so that the loop runs inside the wide copy with one
/// dispatch per block (`pkm_workspace_indices::LaneKernel` is one group of points run this
/// way). `run` must be `#[inline(always)]` and call only `#[inline(always)]` kernels to be
/// compiled for the path; a call that is not inlined runs on the baseline, with the same
/// result, only slower.
pub trait BlockKernel {
    /// What the kernel returns.
    type Output;
    /// The kernel.
    fn run(&self) -> Self::Output;
}

/// `kernel` compiled for `path`, or for the baseline when this processor cannot run `path`.
/// The result is the same on every path, bit for bit (module documentation).
#[inline]
pub fn run_block_on<K: BlockKernel>(path: VectorPath, kernel: &K) -> K::Output {
    match path {
        #[cfg(target_arch = "x86_64")]
        VectorPath::Avx2 if path.is_available() => {
            // SAFETY: the processor has AVX2 (checked just above), the only requirement of a
            // function compiled with `#[target_feature(enable = "avx2")]`.
            unsafe { run_avx2(kernel) }
        }
        _ => kernel.run(),
    }
}

/// `kernel` on [`VectorPath::selected`].
#[inline]
pub fn run_block<K: BlockKernel>(kernel: &K) -> K::Output {
    run_block_on(VectorPath::selected(), kernel)
}

/// The kernel inlined into a function compiled for AVX2 (no FMA: see the module
/// documentation).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2<K: BlockKernel>(kernel: &K) -> K::Output {
    kernel.run()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_baseline_is_always_available_and_first() {
        let paths = VectorPath::available();
        assert_eq!(paths.first(), Some(&VectorPath::Baseline));
        assert!(paths.contains(&VectorPath::selected()));
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_is_offered_exactly_where_the_processor_has_it() {
        let has = std::arch::is_x86_feature_detected!("avx2");
        assert_eq!(VectorPath::available().contains(&VectorPath::Avx2), has);
    }
}
