//! A large factor's storage on the system's huge pages, where it offers
//! them (Linux's transparent huge pages, 2 MiB on x86-64, given on
//! request when set to `madvise`). A substitution streams the whole
//! factor: on 4 KiB pages it crosses a page every thousand
//! single-precision entries, and each page costs a translation the
//! processor's tables cannot hold for tens of megabytes, and stops its
//! prefetch. On the 10,051-block deformable wall, solves on a copy on
//! huge pages alternating with solves on one on small pages (medians):
//! 4.74 against 5.00 ms at dt 1 ms, 5.49 against 6.01 as it settles.

use std::mem::MaybeUninit;

use rayon::prelude::*;

/// The size of a huge page the storage is aligned to, in bytes.
const HUGE_PAGE: usize = 1 << 21;

/// Storage of fewer bytes than this many huge pages is left on small
/// pages: it would waste up to one huge page of slack for little gain.
const LEAST_HUGE_PAGES: usize = 4;

/// `len` copies of `value`, in storage the system is asked to back with
/// huge pages before any of it is touched (where it is large enough).
///
/// Large storage is first written on every core, a huge page a task: each
/// page's first write is a fault the system serves by finding and clearing
/// a fresh page, which on a virtual machine can cost ten times as much as
/// on small pages (the host backs the page anew). Written on one core, the
/// 10,051-block deformable walls' factors took 0.41–0.65 s (2D, 93 MB) and
/// 0.89–2.2 s (3D, 364 MB) to fill, their single-precision copies 0.45–0.49
/// and 1.7–2.1 s; on both, 0.02–0.10, 0.43–0.56, 0.13–0.19 and 1.07–1.09 s.
pub(crate) fn filled<T: Copy + Send + Sync>(len: usize, value: T) -> Vec<T> {
    let size = std::mem::size_of::<T>().max(1);
    if len * size < LEAST_HUGE_PAGES * HUGE_PAGE {
        return vec![value; len];
    }
    // A huge page's slack, so the aligned part holds all `len` entries.
    let mut v = Vec::with_capacity(len + HUGE_PAGE / size);
    advise(v.as_mut_ptr() as usize, v.capacity() * size);
    (v.spare_capacity_mut()[..len].par_chunks_mut(HUGE_PAGE / size))
        .for_each(|c| c.fill(MaybeUninit::new(value)));
    // SAFETY: the first `len` entries were written just above.
    unsafe { v.set_len(len) };
    v
}

/// Asks for huge pages over the whole huge pages within `bytes` from
/// `start`.
#[cfg(target_os = "linux")]
fn advise(start: usize, bytes: usize) {
    let first = start.next_multiple_of(HUGE_PAGE);
    let end = (start + bytes) / HUGE_PAGE * HUGE_PAGE;
    if end > first {
        // SAFETY: the range lies within an allocation the caller owns and
        // has not yet touched; the advice changes how its memory is
        // backed, never what it holds. A refusal (huge pages off) leaves
        // it on small pages, as without the call.
        unsafe {
            libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_: usize, _: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small storage is a plain vector; large storage holds what was
    /// asked, and where the system gives huge pages on request, lies on
    /// them once touched.
    #[test]
    fn a_large_factors_storage_lies_on_huge_pages_where_the_system_offers_them() {
        let small = filled(1000, 1.5_f32);
        assert_eq!(small, vec![1.5_f32; 1000]);
        let len = 12 * HUGE_PAGE / 4;
        let large = filled(len, 2.5_f32);
        assert_eq!(large.len(), len);
        assert!(large.iter().all(|&x| x == 2.5));
        let setting = std::fs::read_to_string("/sys/kernel/mm/transparent_hugepage/enabled");
        let offered = setting.is_ok_and(|s| s.contains("[madvise]") || s.contains("[always]"));
        if !cfg!(target_os = "linux") || !offered {
            println!("huge pages are not offered here: only the contents checked");
            return;
        }
        // The advice splits the mapping at the first whole huge page: the
        // middle lies past it.
        let middle = large[len / 2..].as_ptr() as usize;
        let huge = huge_kib_at(middle).expect("the storage's mapping");
        println!("{huge} KiB of the storage's mapping on huge pages");
        assert!(huge >= 2048, "{huge} KiB on huge pages");
    }

    /// The huge pages (KiB) of the mapping holding `address`, read off
    /// /proc/self/smaps.
    fn huge_kib_at(address: usize) -> Option<usize> {
        let smaps = std::fs::read_to_string("/proc/self/smaps").ok()?;
        let mut inside = false;
        for line in smaps.lines() {
            let first = line.split_whitespace().next().unwrap_or("");
            if let Some((from, to)) = first.split_once('-') {
                if let (Ok(from), Ok(to)) = (
                    usize::from_str_radix(from, 16),
                    usize::from_str_radix(to, 16),
                ) {
                    inside = (from..to).contains(&address);
                    continue;
                }
            }
            if inside {
                if let Some(kib) = line.strip_prefix("AnonHugePages:") {
                    return kib.trim().trim_end_matches("kB").trim().parse().ok();
                }
            }
        }
        None
    }
}
