//! Device choice: each physical device's names, versions and ray tracing
//! extensions, and the first that has what a [`DeviceRequest`] requires.
//! Nothing is created here.

use super::conv::text;
use super::instance::Instance;
use super::{DeviceInfo, DeviceRequest, Features};
use crate::error::RenderError;
use ash::vk;
use std::ffi::CStr;

/// A physical device and what it has.
pub(crate) struct Adapter {
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) info: DeviceInfo,
    /// The features of [`Features`] it has.
    pub(crate) has: Features,
}

/// The extension names of `features`, in the order messages list them.
pub(crate) fn extension_names(features: Features) -> Vec<&'static CStr> {
    let mut names = Vec::new();
    if features.acceleration_structure {
        names.push(vk::KHR_ACCELERATION_STRUCTURE_NAME);
    }
    if features.ray_query {
        names.push(vk::KHR_RAY_QUERY_NAME);
    }
    if features.ray_tracing_pipeline {
        names.push(vk::KHR_RAY_TRACING_PIPELINE_NAME);
    }
    names
}

impl Adapter {
    /// What `physical` is and has.
    fn new(instance: &Instance, physical: vk::PhysicalDevice) -> Adapter {
        let raw = &instance.raw;
        // SAFETY: a physical device of this instance.
        let (props, extensions) = unsafe {
            (
                raw.get_physical_device_properties(physical),
                raw.enumerate_device_extension_properties(physical)
                    .unwrap_or_default(),
            )
        };
        let mut info = DeviceInfo {
            name: text(props.device_name_as_c_str()),
            driver_version: props.driver_version,
            api_version: props.api_version,
            vendor_id: props.vendor_id,
            device_id: props.device_id,
            ..DeviceInfo::default()
        };
        let v12 = props.api_version >= vk::API_VERSION_1_2;
        if v12 {
            let mut about = vk::PhysicalDeviceDriverProperties::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut about);
            // SAFETY: a physical device of a Vulkan 1.2 instance that
            // supports 1.2, a valid chain.
            unsafe { raw.get_physical_device_properties2(physical, &mut props2) };
            info.driver_name = text(about.driver_name_as_c_str());
            info.driver_info = text(about.driver_info_as_c_str());
        }
        let ext = |wanted: &CStr| {
            extensions
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(wanted))
        };
        let has = Features {
            acceleration_structure: v12
                && ext(vk::KHR_ACCELERATION_STRUCTURE_NAME)
                && ext(vk::KHR_DEFERRED_HOST_OPERATIONS_NAME),
            ray_query: v12 && ext(vk::KHR_RAY_QUERY_NAME),
            ray_tracing_pipeline: v12 && ext(vk::KHR_RAY_TRACING_PIPELINE_NAME),
        };
        Adapter {
            physical,
            info,
            has,
        }
    }

    /// The first physical device with everything `request` requires, or
    /// why there is none.
    pub(crate) fn choose(
        instance: &Instance,
        request: &DeviceRequest,
    ) -> Result<Adapter, RenderError> {
        let physicals = instance.physical_devices()?;
        if physicals.is_empty() {
            return Err(RenderError::NoPhysicalDevice);
        }
        let mut found = Vec::new();
        for physical in physicals {
            let adapter = Adapter::new(instance, physical);
            if request.required.within(adapter.has) {
                return Ok(adapter);
            }
            found.push(adapter.info.name);
        }
        Err(RenderError::NoSuitableDevice {
            needed: extension_names(request.required)
                .into_iter()
                .map(|n| n.to_str().unwrap_or("?"))
                .collect(),
            found,
        })
    }
}
