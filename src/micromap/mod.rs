//! Opacity micromaps as data: states, formats, special indices; with an
//! allocator (feature `alloc`, part of `std`) also the [`Micromap`]
//! container and the API buffers built from many micromaps
//! ([`MicromapBuffers`]) and read back from untrusted bytes
//! ([`read_buffers`]). `docs/micromaps.md` cites the Vulkan, DXR and glTF
//! text behind each layout rule.
//!
//! # Guarantees
//!
//! - [`Micromap::as_bytes`] is exactly what Vulkan (`VK_EXT_opacity_micromap`,
//!   `VK_KHR_opacity_micromap`), DXR 1.2 and the glTF
//!   `EXT_mesh_opacity_micromap` draft read: states least-significant bit
//!   first, `max(1, 4^level * bits / 8)` bytes, unused bits zero.
//! - [`Micromap::state_at`] reads the micro-triangle the Vulkan reference
//!   index picks in binary32, bit-exact with the GPU's mapping.
//! - The children of micro-triangle `i` at level `n` are `4i..4i+3` at
//!   level `n + 1` (tested for every micro-triangle of levels 0..=10), so
//!   [`Micromap::merge_one_level`] and [`Micromap::upsample_one_level`] are
//!   index arithmetic.
//! - [`TriangleRecord`] and [`UsageCount`] are `#[repr(C)]` with the APIs'
//!   sizes and offsets (checked at compile time); serialisation is
//!   little-endian whatever the host.
//! - [`MicromapBuffersBuilder`] deduplicates by content (hash to bucket,
//!   bytes to decide) and packs blocks naturally aligned without gaps.
//! - [`read_buffers`] never panics: every inconsistency in the bytes is a
//!   [`ReadError`]; what it accepts and [`MicromapBuffersBuilder`] writes
//!   round-trip (property-tested and fuzzed, `fuzz/fuzz_targets/micromap_buffers.rs`).
//!
//! ```
//! # #[cfg(feature = "alloc")] {
//! use micromap_index::micromap::{
//!     read_buffers, BufferBytes, Format, IndexWidth, Micromap, MicromapBuffers, State,
//!     TriangleOpacity,
//! };
//! use micromap_index::Level;
//!
//! // A level-3 4-state map: every third micro-triangle opaque, the rest unknown.
//! let level = Level::new(3).unwrap();
//! let map = Micromap::from_index_fn(level, Format::FourState, |i| {
//!     if i % 3 == 0 { State::Opaque } else { State::UnknownTransparent }
//! }).unwrap();
//! let buffers = MicromapBuffers::build(
//!     [TriangleOpacity::Micromap(&map), TriangleOpacity::Special(State::Opaque)],
//!     Default::default(),
//! ).unwrap();
//! let records = buffers.records_le_bytes();
//! let indices = buffers.index_bytes(0, IndexWidth::U16).unwrap();
//! assert_eq!(indices, [0, 0, 0xfe, 0xff]);
//!
//! let read = read_buffers(
//!     &BufferBytes {
//!         records: &records,
//!         data: buffers.data(),
//!         usage_counts: None,
//!         indices: Some((&indices, IndexWidth::U16)),
//!     },
//!     &Default::default(),
//! ).unwrap();
//! assert_eq!(read.micromaps, [map]);
//! # }
//! ```
// Without `alloc` the containers below do not exist; their links in the
// module docs above stay, for the docs built with it.
#![cfg_attr(not(feature = "alloc"), allow(rustdoc::broken_intra_doc_links))]

#[cfg(feature = "alloc")]
mod buffers;
#[cfg(feature = "alloc")]
mod builder;
#[cfg(feature = "alloc")]
mod index;
#[cfg(feature = "alloc")]
mod khr_lossy;
#[cfg(feature = "alloc")]
mod map;
#[cfg(feature = "alloc")]
mod map_error;
#[cfg(feature = "alloc")]
mod map_rules;
#[cfg(feature = "alloc")]
mod opacity;
#[cfg(feature = "alloc")]
mod read;
#[cfg(feature = "alloc")]
mod records;
mod state;

#[cfg(feature = "alloc")]
pub use buffers::MicromapBuffers;
#[cfg(feature = "alloc")]
pub use builder::{BuildOptions, MicromapBuffersBuilder, TriangleEntry};
#[cfg(feature = "alloc")]
pub use index::{Api, BufferError, IndexWidth, MicromapIndex};
#[cfg(feature = "alloc")]
pub use map::Micromap;
#[cfg(feature = "alloc")]
pub use map_error::MicromapError;
#[cfg(feature = "alloc")]
pub use map_rules::{MergeRule, UnknownPolicy};
#[cfg(feature = "alloc")]
pub use opacity::{BakedOpacity, TriangleOpacity};
#[cfg(feature = "alloc")]
pub use read::{read_buffers, BufferBytes, Overlap, ReadBuffers, ReadError, ReadOptions};
#[cfg(feature = "alloc")]
pub use records::{records_to_le_bytes, usage_counts_to_le_bytes, TriangleRecord, UsageCount};
pub use state::{Format, State};
