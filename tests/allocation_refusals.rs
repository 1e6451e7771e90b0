//! Allocations sized by the input are fallible (issue 37): under an
//! allocator that gives at most 192 MiB more than is held, inputs that ask
//! for more get the library's typed error instead of an abort. The cases run
//! one after another in one test, as the limit is the whole binary's. Before, each
//! call below aborted the process ("memory allocation of ... failed"): a
//! 26-byte tree decoded into 4 GiB, a mesh's triangles resolved into a
//! list twice the size of their indices, a record list three times the
//! size of its bytes.

use cap::Cap;
use micromap_index::bake::mesh::{
    bake_meshes, output_bytes_bound, Material, Mesh, MeshBakeError, MeshOptions, MeshTriangles,
};
use micromap_index::bake::Unorm8Texture;
use micromap_index::micromap::{
    read_buffers, BufferBytes, IndexWidth, MicromapError, ReadError, ReadOptions,
};
use micromap_index::succinct::{LevelOrderTree, PaperTree, TreeError};
use std::alloc::System;

/// The system allocator with a limit on the bytes allocated at once: each
/// case allows [`ROOM`] beyond what is allocated when it starts, so a
/// request past that is refused (null), as by an allocator out of memory.
#[global_allocator]
static ALLOCATOR: Cap<System> = Cap::new(System, usize::MAX);

/// The bytes a case may allocate beyond what it holds when it starts.
const ROOM: usize = 192 << 20;

/// Runs `case` with [`ROOM`] bytes to spare, then lifts the limit.
fn with_room<T>(case: impl FnOnce() -> T) -> T {
    ALLOCATOR
        .set_limit(ALLOCATOR.allocated() + ROOM)
        .expect("the limit is above what is allocated");
    let result = case();
    ALLOCATOR.set_limit(usize::MAX).expect("no limit");
    result
}

/// A tree whose root is a leaf (state 3): 26 bytes, of any level.
fn root_leaf(layout: u8, level: u8) -> Vec<u8> {
    let mut bytes = b"SOMT".to_vec();
    bytes.extend_from_slice(&[1, layout, level, 2]);
    bytes.extend_from_slice(&1u64.to_le_bytes());
    bytes.extend_from_slice(&1u64.to_le_bytes());
    bytes.extend_from_slice(&[0, 3]);
    bytes
}

/// One test: the allocator's limit is the whole binary's, so the cases must
/// not run side by side.
#[test]
fn inputs_too_large_for_memory_are_refused_by_type() {
    a_tiny_deep_tree_refuses_its_flat_forms();
    a_mesh_whose_triangle_lists_do_not_fit_is_refused();
    a_record_list_that_does_not_fit_is_refused();
}

fn a_tiny_deep_tree_refuses_its_flat_forms() {
    let paper = PaperTree::from_bytes(&root_leaf(0, 16)).unwrap();
    let fast = LevelOrderTree::from_bytes(&root_leaf(1, 16)).unwrap();
    let flat = Err(TreeError::AllocationFailed { bytes: 1 << 32 });
    assert_eq!(with_room(|| paper.decode()), flat);
    assert_eq!(with_room(|| fast.decode()), flat);
    // The packed 4-state map is 1 GiB.
    let packed = Err(MicromapError::AllocationFailed { bytes: 1 << 30 });
    assert_eq!(with_room(|| paper.to_micromap()), packed);
    assert_eq!(with_room(|| fast.to_micromap()), packed);
    // Level 12 fits: 16 MiB of states, one run.
    let small = PaperTree::from_bytes(&root_leaf(0, 12)).unwrap();
    let states = with_room(|| small.decode()).unwrap();
    assert_eq!(states.len(), 1 << 24);
    assert!(states.iter().all(|&s| s.bits() == 3));
}

fn a_mesh_whose_triangle_lists_do_not_fit_is_refused() {
    // 10 million copies of one triangle: 120 MB of indices, which the
    // allocator gives; resolved to UVs they take 240 MB, which it refuses.
    let count = 10_000_000usize;
    let indices: Vec<u32> = [0, 1, 2].repeat(count);
    let uvs = [0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0];
    let texels = [0u8, 255, 255, 0];
    let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
    let mesh = Mesh {
        triangles: MeshTriangles::Indexed {
            indices: &indices,
            uvs: &uvs,
            stride: 2,
        },
        texture: &texture,
        material: Material::default(),
        vertex_alpha: None,
    };
    let options = MeshOptions::default();
    let refused = MeshBakeError::AllocationFailed {
        bytes: count as u64 * 24,
    };
    assert_eq!(
        with_room(|| output_bytes_bound(&[mesh], &options, IndexWidth::U32)),
        Err(refused.clone())
    );
    let baked = with_room(|| bake_meshes(&[mesh], &options, &mut |_, _| {}));
    assert_eq!(baked.as_ref().err(), Some(&refused));
    assert!(refused.is_allocation_failure());
    // The same mesh with a tenth of the triangles bakes.
    let tenth = Mesh {
        triangles: MeshTriangles::Indexed {
            indices: &indices[..3 * count / 10],
            uvs: &uvs,
            stride: 2,
        },
        ..mesh
    };
    let baked = with_room(|| bake_meshes(&[tenth], &options, &mut |_, _| {})).unwrap();
    assert_eq!(baked.report.distinct_triangles, 1);
}

fn a_record_list_that_does_not_fit_is_refused() {
    // 12 million 8-byte records (96 MB) make a list of 12 million blocks,
    // 24 bytes or more each: refused before any record is read.
    let records = vec![0u8; 8 * 12_000_000];
    let input = BufferBytes {
        records: &records,
        ..Default::default()
    };
    match with_room(|| read_buffers(&input, &ReadOptions::default())) {
        Err(ReadError::Micromap {
            record: 0,
            error: MicromapError::AllocationFailed { bytes },
        }) => assert!(bytes >= 24 * 12_000_000, "{bytes}"),
        other => panic!("{:?}", other.map(|_| ())),
    }
}
