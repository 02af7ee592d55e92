//! State in caller memory: each C state type (`hyst_operator`, …) is an opaque block of 8-byte
//! words that the `_init` function fills with a tag and a plain Rust value (no pointers, so the
//! block may be copied with `memcpy`, kept on the stack, in a static or in retained RAM). Every
//! later call checks the pointer, its alignment and the tag before it touches the value.

use core::mem::{align_of, size_of};
use core::ptr;

use crate::status::{
    HYST_ERR_MISALIGNED, HYST_ERR_NOT_INITIALISED, HYST_ERR_NULL_POINTER, HYST_OK,
};

/// The layout inside a state block: the tag first (so it can be read alone), then the value.
#[repr(C)]
struct Slot<V> {
    tag: u32,
    value: V,
}

/// Whether a value of type `V` fits a state block of type `S` (checked at compile time by the
/// `const` assertions next to each C type).
pub(crate) const fn fits<S, V>() -> bool {
    size_of::<Slot<V>>() <= size_of::<S>() && align_of::<Slot<V>>() <= align_of::<S>()
}

/// NULL and alignment: the block's own alignment (8 bytes, as documented), which is at least
/// the value's (`fits`).
fn check<S, V>(storage: *const S) -> i32 {
    if storage.is_null() {
        HYST_ERR_NULL_POINTER
    } else if !(storage as usize).is_multiple_of(align_of::<S>().max(align_of::<Slot<V>>())) {
        HYST_ERR_MISALIGNED
    } else {
        HYST_OK
    }
}

/// Writes `value` with `tag` into the block at `storage`.
///
/// # Safety
/// `storage` is NULL or points to writable memory of `size_of::<S>()` bytes, and
/// `fits::<S, V>()` holds.
pub(crate) unsafe fn write<S, V>(storage: *mut S, tag: u32, value: V) -> i32 {
    let status = check::<S, V>(storage);
    if status == HYST_OK {
        // SAFETY: non-NULL and aligned (checked), large enough (caller's contract and `fits`).
        unsafe { ptr::write(storage.cast::<Slot<V>>(), Slot { tag, value }) };
    }
    status
}

/// The value in the block at `storage`, if its tag is `tag`.
///
/// # Safety
/// `storage` is NULL or points to readable memory of `size_of::<S>()` bytes that is either a
/// block written by [`write`] with the same `V` (possibly copied) or holds another tag.
pub(crate) unsafe fn value<'a, S, V>(storage: *const S, tag: u32) -> Result<&'a V, i32> {
    let status = check::<S, V>(storage);
    if status != HYST_OK {
        return Err(status);
    }
    // SAFETY: non-NULL, aligned; the tag is a u32 at offset 0 (repr(C)), valid for any bits.
    if unsafe { ptr::read(storage.cast::<u32>()) } != tag {
        return Err(HYST_ERR_NOT_INITIALISED);
    }
    // SAFETY: the tag says `write` put a `Slot<V>` here (caller's contract).
    Ok(unsafe { &(*storage.cast::<Slot<V>>()).value })
}

/// As [`value`], mutable.
///
/// # Safety
/// As [`value`], and the memory is writable and not aliased during the call.
pub(crate) unsafe fn value_mut<'a, S, V>(storage: *mut S, tag: u32) -> Result<&'a mut V, i32> {
    // SAFETY: forwarded contract.
    unsafe { value::<S, V>(storage, tag) }?;
    // SAFETY: as in `value`, and writable and unaliased (caller's contract).
    Ok(unsafe { &mut (*storage.cast::<Slot<V>>()).value })
}
