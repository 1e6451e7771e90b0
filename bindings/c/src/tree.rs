//! The succinct tree (`succinct::PaperTree`, `succinct::LevelOrderTree`).

use crate::constants::{MMI_TREE_LEVEL_ORDER, MMI_TREE_PAPER};
use crate::ffi::{
    copy_out, guard, mmi_result, null, slice, slice_mut, write, Error, Result,
    MMI_ERROR_BUFFER_TOO_SMALL, MMI_ERROR_INVALID_ARGUMENT, MMI_ERROR_INVALID_ENUM,
    MMI_ERROR_INVALID_LEVEL, MMI_ERROR_MALFORMED,
};
use crate::mesh::format;
use micromap_index::micromap::State;
use micromap_index::succinct::{LevelOrderTree, PaperTree, TreeError};
use micromap_index::Level;

/// A succinct tree in one of the two layouts. Opaque to C; freed by
/// `mmi_tree_free`.
pub enum mmi_tree {
    /// The paper's depth-first layout.
    Paper(PaperTree),
    /// The level-order layout with a rank directory.
    LevelOrder(LevelOrderTree),
}

/// What `mmi_tree_info` reports.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct mmi_tree_info {
    /// `MMI_TREE_PAPER` or `MMI_TREE_LEVEL_ORDER`.
    pub layout: u32,
    /// The subdivision level.
    pub level: u32,
    /// `MMI_FORMAT_2_STATE` or `MMI_FORMAT_4_STATE`.
    pub format: u32,
    /// Padding, 0.
    pub reserved: u32,
    /// The tree's size in bits (tree bits, leaf states and, for the level
    /// order, its rank directory).
    pub total_bits: u64,
    /// Leaf states stored.
    pub leaf_count: u64,
}

fn tree_error(e: &TreeError, code: mmi_result) -> Error {
    let code = match e {
        TreeError::LevelTooHigh { .. } => MMI_ERROR_INVALID_LEVEL,
        TreeError::AllocationFailed { .. } => crate::ffi::MMI_ERROR_OUT_OF_MEMORY,
        _ => code,
    };
    Error::new(code, e.to_string())
}

/// # Safety
/// `tree` must be NULL or a live handle.
unsafe fn handle<'a>(tree: *const mmi_tree) -> Result<&'a mmi_tree> {
    if tree.is_null() {
        return Err(null("tree"));
    }
    // SAFETY: a live handle (the caller's promise).
    Ok(unsafe { &*tree })
}

/// Hands `tree` to C through `out`.
///
/// # Safety
/// `out` must be NULL or writable.
unsafe fn give(tree: mmi_tree, out: *mut *mut mmi_tree) -> Result<()> {
    let raw = Box::into_raw(Box::new(tree));
    // SAFETY: the caller's promise about `out`.
    unsafe { write(out, raw, "tree") }
}

// `as_states` rests on this.
const _: () = assert!(size_of::<State>() == 1 && align_of::<State>() == 1);

/// The caller's state bytes as states, in place: a copy would double the
/// memory of a level-16 map (4 GiB). A byte above 3 is
/// `MMI_ERROR_INVALID_ENUM`.
fn as_states(bytes: &[u8]) -> Result<&[State]> {
    if let Some(i) = bytes.iter().position(|&b| State::from_bits(b).is_none()) {
        return Err(Error::new(
            MMI_ERROR_INVALID_ENUM,
            format!("states[{i}] = {}: expected a state 0..=3", bytes[i]),
        ));
    }
    // SAFETY: `State` is `#[repr(u8)]` with the values 0..=3, and every
    // byte is one of them (checked above); same size and alignment, and
    // the borrow keeps the bytes' lifetime.
    Ok(unsafe { core::slice::from_raw_parts(bytes.as_ptr().cast::<State>(), bytes.len()) })
}

/// Encodes a flat micromap of `level` (0..=16) given as `state_count ==
/// 4^level` states (`MMI_STATE_*`, one byte each) into a tree of `layout`
/// (`MMI_TREE_PAPER` or `MMI_TREE_LEVEL_ORDER`) and `format`; a 2-state
/// format refuses unknown states (`MMI_ERROR_INVALID_ARGUMENT`), a wrong
/// count is `MMI_ERROR_LENGTH`. `*tree` receives the handle (NULL on an
/// error).
///
/// # Safety
/// `states` must be NULL or point to `state_count` bytes; `tree` writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_encode(
    layout: u32,
    level: u32,
    format: u32,
    states: *const u8,
    state_count: usize,
    tree: *mut *mut mmi_tree,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        unsafe { write(tree, core::ptr::null_mut(), "tree") }?;
        if layout != MMI_TREE_PAPER && layout != MMI_TREE_LEVEL_ORDER {
            return Err(Error::new(
                MMI_ERROR_INVALID_ENUM,
                format!("layout {layout}: expected MMI_TREE_PAPER or MMI_TREE_LEVEL_ORDER"),
            ));
        }
        let level =
            Level::new(level).map_err(|e| Error::new(MMI_ERROR_INVALID_LEVEL, e.to_string()))?;
        let format = self::format(format)?;
        // SAFETY: the caller's promise about `states`.
        let bytes = unsafe { slice(states, state_count, "states") }?;
        let states = as_states(bytes)?;
        let encoded = if layout == MMI_TREE_PAPER {
            PaperTree::encode(level, format, states).map(mmi_tree::Paper)
        } else {
            LevelOrderTree::encode(level, format, states).map(mmi_tree::LevelOrder)
        };
        let encoded = encoded.map_err(|e| {
            let code = if matches!(e, TreeError::StateCount { .. }) {
                crate::ffi::MMI_ERROR_LENGTH
            } else {
                MMI_ERROR_INVALID_ARGUMENT
            };
            tree_error(&e, code)
        })?;
        // SAFETY: the caller's promise about `tree`.
        unsafe { give(encoded, tree) }
    })
}

/// Reads a tree from the bytes `mmi_tree_to_bytes` writes (either layout,
/// named by the header's layout byte): any other input is
/// `MMI_ERROR_MALFORMED`, never a crash. `*tree` receives the handle (NULL
/// on an error).
///
/// # Safety
/// `bytes` must be NULL or point to `len` bytes; `tree` writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_from_bytes(
    bytes: *const u8,
    len: usize,
    tree: *mut *mut mmi_tree,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        unsafe { write(tree, core::ptr::null_mut(), "tree") }?;
        // SAFETY: the caller's promise about `bytes`.
        let bytes = unsafe { slice(bytes, len, "bytes") }?;
        // Byte 5 names the layout (the format table in `succinct`); each
        // reader checks everything, that byte included.
        let read = if bytes.get(5) == Some(&0) {
            PaperTree::from_bytes(bytes).map(mmi_tree::Paper)
        } else {
            LevelOrderTree::from_bytes(bytes).map(mmi_tree::LevelOrder)
        };
        let read = read.map_err(|e| Error::new(MMI_ERROR_MALFORMED, e.to_string()))?;
        // SAFETY: the caller's promise about `tree`.
        unsafe { give(read, tree) }
    })
}

/// The state of micro-triangle `index` (`MMI_STATE_*`), or
/// `MMI_ERROR_INVALID_ARGUMENT` for an index `>= 4^level`.
///
/// # Safety
/// `tree` must be NULL or a live handle; `state` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_get(
    tree: *const mmi_tree,
    index: u64,
    state: *mut u8,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        let found = match unsafe { handle(tree) }? {
            mmi_tree::Paper(t) => t.get(index),
            mmi_tree::LevelOrder(t) => t.get(index),
        };
        let found = found.ok_or_else(|| {
            Error::new(
                MMI_ERROR_INVALID_ARGUMENT,
                format!("micro-triangle {index} is past the tree's last"),
            )
        })?;
        // SAFETY: the caller's promise about `state`.
        unsafe { write(state, found.bits(), "state") }
    })
}

/// The state a ray hit at barycentrics `(u, v)` reads: the Vulkan
/// reference index in binary32, then the lookup (every float pair).
///
/// # Safety
/// As `mmi_tree_get`.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_get_f32(
    tree: *const mmi_tree,
    u: f32,
    v: f32,
    state: *mut u8,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        let found = match unsafe { handle(tree) }? {
            mmi_tree::Paper(t) => t.get_f32(u, v),
            mmi_tree::LevelOrder(t) => t.get_f32(u, v),
        };
        let found = found.ok_or_else(|| Error::new(MMI_ERROR_INVALID_ARGUMENT, "no state"))?;
        // SAFETY: the caller's promise about `state`.
        unsafe { write(state, found.bits(), "state") }
    })
}

/// The tree's bytes (version 1 of the format in `docs/` and
/// `succinct`): `*len` receives the size; with `out == NULL` that is all;
/// a smaller `capacity` is `MMI_ERROR_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `tree` must be NULL or a live handle; `out` NULL or `capacity` writable
/// bytes; `len` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_to_bytes(
    tree: *const mmi_tree,
    out: *mut u8,
    capacity: usize,
    len: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        let bytes = match unsafe { handle(tree) }? {
            mmi_tree::Paper(t) => t.to_bytes(),
            mmi_tree::LevelOrder(t) => t.to_bytes(),
        };
        // SAFETY: the caller's promises about `out` and `len`.
        unsafe { copy_out(&bytes, out, capacity, len, "the tree's bytes") }
    })
}

/// Every micro-triangle's state (`4^level` bytes, `MMI_STATE_*`), in the
/// size-query style of `mmi_tree_to_bytes` (`*len` in states).
///
/// # Safety
/// As `mmi_tree_to_bytes`.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_decode(
    tree: *const mmi_tree,
    states: *mut u8,
    capacity: usize,
    len: *mut usize,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        let t = unsafe { handle(tree) }?;
        let level = match t {
            mmi_tree::Paper(t) => t.level(),
            mmi_tree::LevelOrder(t) => t.level(),
        };
        let count = 1usize
            .checked_shl(2 * level.get())
            .filter(|&c| c != 0)
            .ok_or_else(|| {
                Error::new(
                    crate::ffi::MMI_ERROR_LENGTH,
                    "the states do not fit in memory",
                )
            })?;
        if states.is_null() || capacity < count {
            // SAFETY: the caller's promise about `len`.
            unsafe { write(len, count, "len") }?;
            if states.is_null() {
                return Ok(());
            }
            return Err(Error::new(
                MMI_ERROR_BUFFER_TOO_SMALL,
                format!("the states need {count} bytes, the buffer holds {capacity}"),
            ));
        }
        // Written run by run into the caller's buffer: no copy of 4^level
        // states is made here (a level-16 tree of 24 bytes decodes to 4 GiB).
        // SAFETY: the caller's promise about `states` (`capacity >= count`
        // bytes, checked above).
        let target = unsafe { slice_mut(states, count, "states") }?;
        let mut fill = |first: u64, n: u64, state: State| {
            // The runs tile 0..4^level = 0..count.
            target[first as usize..(first + n) as usize].fill(state.bits());
        };
        match t {
            mmi_tree::Paper(t) => t.for_each_run(&mut fill),
            mmi_tree::LevelOrder(t) => t.for_each_run(&mut fill),
        }
        // SAFETY: the caller's promise about `len`.
        unsafe { write(len, count, "len") }
    })
}

/// The tree's layout, level, format and sizes.
///
/// # Safety
/// `tree` must be NULL or a live handle; `info` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_info_get(
    tree: *const mmi_tree,
    info: *mut mmi_tree_info,
) -> mmi_result {
    guard(|| {
        // SAFETY: the caller's promise about `tree`.
        let value = match unsafe { handle(tree) }? {
            mmi_tree::Paper(t) => mmi_tree_info {
                layout: MMI_TREE_PAPER,
                level: t.level().get(),
                format: u32::from(t.format().raw()),
                reserved: 0,
                total_bits: t.total_bits(),
                leaf_count: t.leaf_count(),
            },
            mmi_tree::LevelOrder(t) => mmi_tree_info {
                layout: MMI_TREE_LEVEL_ORDER,
                level: t.level().get(),
                format: u32::from(t.format().raw()),
                reserved: 0,
                total_bits: t.total_bits(),
                leaf_count: t.leaf_count(),
            },
        };
        // SAFETY: the caller's promise about `info`.
        unsafe { write(info, value, "info") }
    })
}

/// Frees a tree; NULL is ignored.
///
/// # Safety
/// `tree` must be NULL or a live handle from `mmi_tree_encode` or
/// `mmi_tree_from_bytes`, not used again.
#[no_mangle]
pub unsafe extern "C" fn mmi_tree_free(tree: *mut mmi_tree) {
    if tree.is_null() {
        return;
    }
    let _ = std::panic::catch_unwind(|| {
        // SAFETY: a live handle from `Box::into_raw` in `give`, freed once.
        drop(unsafe { Box::from_raw(tree) });
    });
}
