//! Large zeroed buffers on transparent huge pages where the OS gives them on
//! request (Linux with THP in `madvise` mode, as Debian ships it).
//!
//! A build of 4M objects touches about 550 MB. In 4 KiB pages that is about
//! 135,000 page faults, each a trap into the kernel to clear one page: a
//! fifth of the build's time on a 2-core machine. In 2 MiB pages it is a few
//! hundred. The advice changes how pages are backed, never what they hold,
//! and where it is refused (THP off, another OS) nothing changes.

/// Huge pages are 2 MiB on x86-64 and on 4 KiB-page aarch64; only whole,
/// aligned ones inside a buffer are advised.
#[cfg(target_os = "linux")]
const HUGE_PAGE: usize = 2 << 20;

/// `len` zeroed elements, advised onto huge pages before anything touches
/// them (the allocator's zeroed memory of this size comes straight from
/// `mmap`, so its pages are still unmapped).
pub(super) fn zeroed_vec<T: bytemuck::Zeroable>(len: usize) -> Vec<T> {
    let mut v = bytemuck::zeroed_vec(len);
    advise(&mut v);
    v
}

#[cfg(target_os = "linux")]
fn advise<T>(v: &mut [T]) {
    let start = v.as_mut_ptr() as usize;
    let lo = start.next_multiple_of(HUGE_PAGE);
    let hi = (start + std::mem::size_of_val(v)) / HUGE_PAGE * HUGE_PAGE;
    if hi > lo {
        // SAFETY: [lo, hi) lies inside `v`, borrowed mutably here, and is
        // page aligned. MADV_HUGEPAGE changes only how those pages are
        // backed, never their contents; a refusal is an error code, ignored.
        unsafe { libc::madvise(lo as *mut libc::c_void, hi - lo, libc::MADV_HUGEPAGE) };
    }
}

#[cfg(not(target_os = "linux"))]
fn advise<T>(_: &mut [T]) {}
