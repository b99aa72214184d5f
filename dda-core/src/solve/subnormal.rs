//! Single-precision substitutions with subnormal numbers taken as zero.
//!
//! A correction's right-hand side is scaled to its largest entry, and a
//! settled wall's residual spans many decades, so its small entries, and
//! their products with a factor's decaying fill, fall below f32's
//! smallest normal number (1.2e-38). On x86 every operation that reads or
//! makes such a number takes a microcode assist of some hundred cycles:
//! the 3D 10,051-block deformable wall's top supernodes were substituted
//! at 2–4 GB/s where memory gives 15, and the widest (1,944 columns) took
//! 3.6 ms a sweep against 0.75 with subnormals flushed. Relative to the
//! scaled right-hand side they are below 1e-38, far under the copy's own
//! round-off (6e-8), so flushing them changes no move that matters.
//!
//! The mode is a thread's own (x86 MXCSR's DAZ and FTZ bits): each piece
//! of a substitution sets it on the thread it runs on, so an answer does
//! not depend on which thread or how many run it. Double-precision solves
//! keep the default mode. Elsewhere than x86-64 nothing changes.

/// While alive, subnormal single-precision numbers are read and made as
/// zero on this thread (where `flush`); the mode before is put back on
/// drop.
pub(crate) struct FlushSubnormals {
    #[cfg(target_arch = "x86_64")]
    before: Option<u32>,
}

/// MXCSR's denormals-are-zero (bit 6) and flush-to-zero (bit 15) bits.
#[cfg(target_arch = "x86_64")]
const DAZ_FTZ: u32 = 0x8040;

impl FlushSubnormals {
    pub(crate) fn on(flush: bool) -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if !flush {
                return Self { before: None };
            }
            let before = read_mxcsr();
            write_mxcsr(before | DAZ_FTZ);
            Self {
                before: Some(before),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = flush;
            Self {}
        }
    }
}

impl Drop for FlushSubnormals {
    fn drop(&mut self) {
        #[cfg(target_arch = "x86_64")]
        if let Some(before) = self.before {
            write_mxcsr(before);
        }
    }
}

#[cfg(target_arch = "x86_64")]
fn read_mxcsr() -> u32 {
    let mut csr = 0_u32;
    // SAFETY: `stmxcsr` stores the 32-bit control register at the address
    // given, a live local, and touches nothing else.
    unsafe {
        std::arch::asm!("stmxcsr [{}]", in(reg) &mut csr, options(nostack, preserves_flags));
    }
    csr
}

#[cfg(target_arch = "x86_64")]
fn write_mxcsr(csr: u32) {
    // SAFETY: `ldmxcsr` loads a value read by `stmxcsr` with only the DAZ
    // and FTZ bits changed: no reserved bit is set, so it cannot fault.
    unsafe {
        std::arch::asm!("ldmxcsr [{}]", in(reg) &csr, options(nostack, readonly, preserves_flags));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn halve(x: f32) -> f32 {
        std::hint::black_box(x) / 2.0
    }

    /// Within the guard a product below f32's smallest normal is zero, and
    /// a subnormal read is zero; outside it, and after it, both are kept.
    #[test]
    fn subnormals_are_zero_only_within_the_guard() {
        let small = f32::MIN_POSITIVE;
        let subnormal = halve(small);
        assert!(subnormal > 0.0, "subnormals kept by default");
        {
            let _flush = FlushSubnormals::on(true);
            #[cfg(target_arch = "x86_64")]
            {
                assert_eq!(halve(small), 0.0);
                assert_eq!(std::hint::black_box(subnormal) * 1.0, 0.0);
            }
            let _nested = FlushSubnormals::on(true);
        }
        assert_eq!(halve(small), subnormal, "the mode is put back");
        {
            let _off = FlushSubnormals::on(false);
            assert_eq!(halve(small), subnormal);
        }
        // Double precision's own subnormals are untouched where f32 is
        // not flushed.
        assert!(std::hint::black_box(f64::MIN_POSITIVE) / 2.0 > 0.0);
    }
}
