//! Arrays the application hands the layer as a pointer and a count.

/// The `count` elements at `pointer`, or none when the pointer is null or the count 0 (a null
/// pointer must not reach `slice::from_raw_parts`, even with a length of 0).
///
/// # Safety
/// `pointer` is null or points at `count` valid `T`s that outlive `'a`.
pub unsafe fn app_array<'a, T>(pointer: *const T, count: u32) -> &'a [T] {
    if pointer.is_null() || count == 0 {
        &[]
    } else {
        // SAFETY: the caller's contract.
        unsafe { std::slice::from_raw_parts(pointer, count as usize) }
    }
}
