//! The API rules of the newest specs the buffers are checked against
//! (`../shared/micromap-landscape.md`, update of 2026-12-01): glTF's levels
//! stop at 12 like DXR's; Vulkan KHR, DXR and glTF accept 8-bit indices,
//! Vulkan EXT does not.

use micromap_index::micromap::{
    Api, BufferError, BuildOptions, Format, IndexWidth, Micromap, MicromapBuffers, State,
    TriangleOpacity,
};
use micromap_index::Level;

fn one_map(level: u32) -> MicromapBuffers {
    let mut map = Micromap::new(Level::new(level).unwrap(), Format::TwoState).unwrap();
    map.set(0, State::Opaque).unwrap();
    MicromapBuffers::build([TriangleOpacity::Micromap(&map)], BuildOptions::default()).unwrap()
}

#[test]
fn gltf_and_dxr_levels_stop_at_12_vulkan_leaves_it_to_the_device() {
    let twelve = one_map(12);
    let thirteen = one_map(13);
    for api in [Api::Gltf, Api::Dxr] {
        assert_eq!(api.max_level(), Some(12));
        assert_eq!(twelve.check_for(api, IndexWidth::U16), Ok(()), "{api}");
        assert_eq!(
            thirteen.check_for(api, IndexWidth::U16),
            Err(BufferError::LevelNotAllowed {
                level: 13,
                max: 12,
                api
            }),
            "{api}"
        );
    }
    for api in [Api::VulkanExt, Api::VulkanKhr] {
        assert_eq!(api.max_level(), None);
        assert_eq!(thirteen.check_for(api, IndexWidth::U16), Ok(()), "{api}");
    }
}

#[test]
fn eight_bit_indices_everywhere_but_vulkan_ext() {
    let buffers = one_map(1);
    for api in [Api::VulkanKhr, Api::Dxr, Api::Gltf] {
        assert_eq!(buffers.check_for(api, IndexWidth::U8), Ok(()), "{api}");
        assert_eq!(IndexWidth::narrowest(Some(0), api), IndexWidth::U8);
    }
    assert_eq!(
        buffers.check_for(Api::VulkanExt, IndexWidth::U8),
        Err(BufferError::IndexWidthNotAllowed {
            width: IndexWidth::U8,
            api: Api::VulkanExt
        })
    );
    assert_eq!(
        IndexWidth::narrowest(Some(0), Api::VulkanExt),
        IndexWidth::U16
    );
}

#[test]
fn khr_lossy_builds_take_4_state_records_up_to_the_lossy_cap() {
    let four = |k: usize| {
        Micromap::from_states(
            Level::new(3).unwrap(),
            Format::FourState,
            State::ALL.into_iter().cycle().skip(k).take(64),
        )
        .unwrap()
    };
    let (a, b) = (four(0), four(1));
    let mut two = Micromap::new(Level::new(2).unwrap(), Format::TwoState).unwrap();
    two.set(3, State::Opaque).unwrap();
    let fine = MicromapBuffers::build(
        [TriangleOpacity::Micromap(&a), TriangleOpacity::Micromap(&b)],
        BuildOptions::default(),
    )
    .unwrap();
    assert_eq!(fine.check_for_khr_lossy(IndexWidth::U8, 3), Ok(()));
    assert_eq!(
        fine.check_for_khr_lossy(IndexWidth::U8, 2),
        Err(BufferError::LevelNotAllowed {
            level: 3,
            max: 2,
            api: Api::VulkanKhr
        })
    );
    let mixed = MicromapBuffers::build(
        [
            TriangleOpacity::Micromap(&a),
            TriangleOpacity::Micromap(&two),
        ],
        BuildOptions::default(),
    )
    .unwrap();
    assert_eq!(mixed.check_for(Api::VulkanKhr, IndexWidth::U8), Ok(()));
    assert_eq!(
        mixed.check_for_khr_lossy(IndexWidth::U8, 12),
        Err(BufferError::FormatNotAllowed {
            record: 1,
            format: 1
        })
    );
}
