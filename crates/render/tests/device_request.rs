//! The device request's parts without a device: selectors, feature sets
//! and the messages that name what a device lacks.

use micromap_index_render::vulkan::{DeviceSelector, Features};
use micromap_index_render::{ErrorClass, RenderError};

#[test]
fn a_selector_is_a_number_or_a_part_of_a_name() {
    assert_eq!("0".parse(), Ok(DeviceSelector::Index(0)));
    assert_eq!("12".parse(), Ok(DeviceSelector::Index(12)));
    assert_eq!(
        "NVIDIA".parse(),
        Ok(DeviceSelector::Name("NVIDIA".to_string()))
    );
    assert!("".parse::<DeviceSelector>().is_err());
    assert!("99999999999999999999999".parse::<DeviceSelector>().is_err());
    let nvidia = DeviceSelector::Name("h100".to_string());
    assert!(nvidia.matches(3, "NVIDIA H100 80GB HBM3"));
    assert!(!nvidia.matches(0, "llvmpipe (LLVM 15.0.6, 256 bits)"));
    assert!(DeviceSelector::Index(1).matches(1, "any"));
    assert!(!DeviceSelector::Index(1).matches(0, "any"));
}

#[test]
fn features_name_their_extensions() {
    let all = Features {
        acceleration_structure: true,
        ray_query: true,
        ray_tracing_pipeline: true,
        opacity_micromap: true,
    };
    let pipeline = Features {
        acceleration_structure: true,
        ray_tracing_pipeline: true,
        ..Features::default()
    };
    assert_eq!(
        all.minus(pipeline).names(),
        ["VK_KHR_ray_query", "VK_EXT_opacity_micromap"]
    );
    assert!(pipeline.minus(all).is_empty());
    assert_eq!(all.and(pipeline), pipeline);
}

#[test]
fn a_device_without_micromaps_is_named_with_what_it_lacks() {
    let e = RenderError::NoSuitableDevice {
        needed: vec![
            "VK_KHR_acceleration_structure",
            "VK_KHR_ray_tracing_pipeline",
            "VK_EXT_opacity_micromap",
        ],
        found: vec![("llvmpipe".to_string(), vec!["VK_EXT_opacity_micromap"])],
    };
    assert_eq!(e.class(), ErrorClass::NoDevice);
    assert_eq!(
        e.to_string(),
        "no Vulkan device with VK_KHR_acceleration_structure, VK_KHR_ray_tracing_pipeline and VK_EXT_opacity_micromap (found: llvmpipe without VK_EXT_opacity_micromap); no CPU Vulkan driver has VK_EXT_opacity_micromap (Mesa's lavapipe neither)"
    );
}
