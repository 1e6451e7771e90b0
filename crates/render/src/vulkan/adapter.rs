//! Device choice: each physical device's names, versions and ray tracing
//! extensions ([`DeviceInfo`]), and the device a [`DeviceRequest`] picks:
//! the one it selects, or the first with what it requires. Nothing is
//! created here.

use super::conv::text;
use super::instance::Instance;
use super::{DeviceInfo, DeviceRequest, Features};
use crate::error::RenderError;
use ash::vk;
use std::ffi::CStr;

/// The name of `VK_KHR_opacity_micromap` (`ash` 0.38 has no constant).
const KHR_OPACITY_MICROMAP_NAME: &CStr = c"VK_KHR_opacity_micromap";

/// A physical device and what it is.
pub(crate) struct Adapter {
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) info: DeviceInfo,
}

/// The device extensions that `features` enable, each feature's own first.
pub(crate) fn extension_names(features: Features) -> Vec<&'static CStr> {
    let mut names = Vec::new();
    if features.acceleration_structure {
        names.extend([
            vk::KHR_ACCELERATION_STRUCTURE_NAME,
            vk::KHR_DEFERRED_HOST_OPERATIONS_NAME,
        ]);
    }
    if features.ray_query {
        names.push(vk::KHR_RAY_QUERY_NAME);
    }
    if features.ray_tracing_pipeline {
        names.push(vk::KHR_RAY_TRACING_PIPELINE_NAME);
    }
    if features.opacity_micromap {
        names.extend([vk::EXT_OPACITY_MICROMAP_NAME, vk::KHR_SYNCHRONIZATION2_NAME]);
    }
    names
}

impl Adapter {
    /// What the `index`-th device, `physical`, is and has.
    fn new(instance: &Instance, index: usize, physical: vk::PhysicalDevice) -> Adapter {
        let raw = &instance.raw;
        // SAFETY: a physical device of this instance.
        let (props, extensions) = unsafe {
            (
                raw.get_physical_device_properties(physical),
                raw.enumerate_device_extension_properties(physical)
                    .unwrap_or_default(),
            )
        };
        let ext = |wanted: &CStr| {
            extensions
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(wanted))
        };
        let mut info = DeviceInfo {
            index,
            name: text(props.device_name_as_c_str()),
            driver_version: props.driver_version,
            api_version: props.api_version,
            vendor_id: props.vendor_id,
            device_id: props.device_id,
            khr_opacity_micromap: ext(KHR_OPACITY_MICROMAP_NAME),
            ..DeviceInfo::default()
        };
        if props.api_version < vk::API_VERSION_1_2 {
            return Adapter { physical, info };
        }
        let omm_listed = ext(vk::EXT_OPACITY_MICROMAP_NAME) && ext(vk::KHR_SYNCHRONIZATION2_NAME);
        let mut about = vk::PhysicalDeviceDriverProperties::default();
        let mut omm_props = vk::PhysicalDeviceOpacityMicromapPropertiesEXT::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut about);
        if omm_listed {
            props2 = props2.push_next(&mut omm_props);
        }
        // SAFETY: a physical device of a Vulkan 1.2 instance that supports
        // 1.2; a valid chain (the micromap struct only where the device
        // lists its extension).
        unsafe { raw.get_physical_device_properties2(physical, &mut props2) };
        info.driver_name = text(about.driver_name_as_c_str());
        info.driver_info = text(about.driver_info_as_c_str());
        let mut omm_features = vk::PhysicalDeviceOpacityMicromapFeaturesEXT::default();
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
        {
            let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut v12);
            if omm_listed {
                features2 = features2.push_next(&mut omm_features);
            }
            // SAFETY: as above.
            unsafe { raw.get_physical_device_features2(physical, &mut features2) };
        }
        info.sampler_lookup = v12.runtime_descriptor_array == vk::TRUE
            && v12.shader_sampled_image_array_non_uniform_indexing == vk::TRUE;
        info.mirror_clamp_to_edge = v12.sampler_mirror_clamp_to_edge == vk::TRUE;
        let omm = omm_listed && omm_features.micromap == vk::TRUE;
        if omm {
            info.max_micromap_levels = Some([
                omm_props.max_opacity2_state_subdivision_level,
                omm_props.max_opacity4_state_subdivision_level,
            ]);
        }
        let accel =
            ext(vk::KHR_ACCELERATION_STRUCTURE_NAME) && ext(vk::KHR_DEFERRED_HOST_OPERATIONS_NAME);
        info.has = Features {
            acceleration_structure: accel,
            ray_query: ext(vk::KHR_RAY_QUERY_NAME),
            ray_tracing_pipeline: ext(vk::KHR_RAY_TRACING_PIPELINE_NAME),
            opacity_micromap: accel && omm,
        };
        Adapter { physical, info }
    }

    /// What of `required` this device lacks: "Vulkan 1.2" before 1.2,
    /// else the missing extensions' names.
    fn lacks(&self, required: Features) -> Vec<&'static str> {
        if !required.is_empty() && self.info.api_version < vk::API_VERSION_1_2 {
            return vec!["Vulkan 1.2"];
        }
        required.minus(self.info.has).names()
    }

    /// The device `request` selects, or the first with everything it
    /// requires, or why there is none.
    pub(crate) fn choose(
        instance: &Instance,
        request: &DeviceRequest,
    ) -> Result<Adapter, RenderError> {
        let physicals = instance.physical_devices()?;
        if physicals.is_empty() {
            return Err(RenderError::NoPhysicalDevice);
        }
        let mut found = Vec::new();
        let mut names = Vec::new();
        for (index, physical) in physicals.into_iter().enumerate() {
            let adapter = Adapter::new(instance, index, physical);
            names.push(format!("{index}: {}", adapter.info.name));
            if let Some(select) = &request.select {
                if !select.matches(index, &adapter.info.name) {
                    continue;
                }
            }
            let lacks = adapter.lacks(request.required);
            if lacks.is_empty() {
                return Ok(adapter);
            }
            found.push((adapter.info.name, lacks));
            if request.select.is_some() {
                break;
            }
        }
        match &request.select {
            Some(select) if found.is_empty() => Err(RenderError::DeviceNotFound {
                selector: select.to_string(),
                found: names,
            }),
            _ => Err(RenderError::NoSuitableDevice {
                needed: request.required.names(),
                found,
            }),
        }
    }
}
