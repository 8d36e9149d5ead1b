//! Big buffers on huge pages. A log of millions of transitions is read
//! and decoded into buffers of tens of MB; touched 4 KB at a time, their
//! page faults were a third of `btx log`'s time (perf, #42). Where the
//! kernel gives transparent huge pages on request (`madvise`, the usual
//! default), asking for them makes a fault of each 2 MB instead.

/// Buffers below this are left to the allocator as they are.
const HUGE_MIN: usize = 4 << 20;

/// An empty vector with room for `n`, on huge pages where it is big.
pub fn with_capacity<T>(n: usize) -> Vec<T> {
    let v = Vec::with_capacity(n);
    advise(&v);
    v
}

#[cfg(target_os = "linux")]
fn advise<T>(v: &Vec<T>) {
    let bytes = v.capacity().saturating_mul(std::mem::size_of::<T>());
    if bytes < HUGE_MIN {
        return;
    }
    // madvise takes whole pages: the part of the buffer they cover.
    const PAGE: usize = 4096;
    let from = v.as_ptr() as usize;
    let start = from.next_multiple_of(PAGE);
    let end = (from + bytes) / PAGE * PAGE;
    if end > start {
        // SAFETY: the range lies inside the vector's own allocation, and
        // MADV_HUGEPAGE changes how its pages are backed, not their
        // contents; a kernel without it returns an error, ignored.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise<T>(_: &Vec<T>) {}

#[cfg(test)]
mod tests {
    #[test]
    fn a_big_buffer_holds_what_is_put_in_it() {
        let mut v: Vec<u64> = super::with_capacity(1 << 20);
        assert!(v.capacity() >= 1 << 20);
        v.extend(0..1 << 20);
        assert_eq!(v.iter().sum::<u64>(), (1u64 << 20) * ((1 << 20) - 1) / 2);
        let small: Vec<u8> = super::with_capacity(10);
        assert!(small.capacity() >= 10);
    }
}
