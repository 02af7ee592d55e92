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

/// A C state type and the Rust value its block holds, marked by the tag `TAG` (one per C type,
/// so that a block of another type is refused).
pub(crate) trait Block {
    /// The value inside.
    type Value;
    /// The tag written before the value.
    const TAG: u32;
}

/// Whether a value of type `V` fits a state block of type `S` (checked at compile time for each
/// C type by [`put`]).
const fn fits<S, V>() -> bool {
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

/// Writes `value` with its type's tag into the block at `storage` (an `_init` function).
///
/// # Safety
/// `storage` is NULL or points to writable memory of `size_of::<B>()` bytes.
pub(crate) unsafe fn put<B: Block>(storage: *mut B, value: B::Value) -> i32 {
    const { assert!(fits::<B, B::Value>()) };
    let status = check::<B, B::Value>(storage);
    if status == HYST_OK {
        let slot = Slot { tag: B::TAG, value };
        // SAFETY: non-NULL and aligned (checked), large enough (caller's contract and `fits`).
        unsafe { ptr::write(storage.cast::<Slot<B::Value>>(), slot) };
    }
    status
}

/// The initialised value behind `storage`, or the status of the failed check.
pub(crate) fn get<'a, B: Block>(storage: *const B) -> Result<&'a B::Value, i32> {
    // SAFETY: the caller of the C function passes NULL, an initialised block, or any other
    // readable block of the type's size (whose tag then does not match).
    unsafe { value::<B, B::Value>(storage, B::TAG) }
}

/// As [`get`], mutable.
pub(crate) fn get_mut<'a, B: Block>(storage: *mut B) -> Result<&'a mut B::Value, i32> {
    // SAFETY: as in `get`, and the C function's caller does not alias the block during the call.
    unsafe { value_mut::<B, B::Value>(storage, B::TAG) }
}

/// The value in the block at `storage`, if its tag is `tag`.
///
/// # Safety
/// `storage` is NULL or points to readable memory of `size_of::<S>()` bytes that is either a
/// block written by [`put`] with the same `V` (possibly copied) or holds another tag.
unsafe fn value<'a, S, V>(storage: *const S, tag: u32) -> Result<&'a V, i32> {
    let status = check::<S, V>(storage);
    if status != HYST_OK {
        return Err(status);
    }
    // SAFETY: non-NULL, aligned; the tag is a u32 at offset 0 (repr(C)), valid for any bits.
    if unsafe { ptr::read(storage.cast::<u32>()) } != tag {
        return Err(HYST_ERR_NOT_INITIALISED);
    }
    // SAFETY: the tag says `put` wrote a `Slot<V>` here (caller's contract).
    Ok(unsafe { &(*storage.cast::<Slot<V>>()).value })
}

/// As [`value`], mutable.
///
/// # Safety
/// As [`value`], and the memory is writable and not aliased during the call.
unsafe fn value_mut<'a, S, V>(storage: *mut S, tag: u32) -> Result<&'a mut V, i32> {
    // SAFETY: forwarded contract.
    unsafe { value::<S, V>(storage, tag) }?;
    // SAFETY: as in `value`, and writable and unaliased (caller's contract).
    Ok(unsafe { &mut (*storage.cast::<Slot<V>>()).value })
}
