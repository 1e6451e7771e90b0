//! The loader and the instance. The loader library is opened at run time
//! (`ash`'s `loaded` feature); the instance asks for Vulkan 1.2 and is
//! destroyed when the last device made from it goes.

use super::conv::failed;
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// An instance and the loader it came from.
pub(crate) struct Instance {
    // Kept alive: the instance's functions were loaded through it.
    _entry: ash::Entry,
    pub(crate) raw: ash::Instance,
}

impl Instance {
    /// Opens the loader and creates an instance (Vulkan 1.2).
    pub(crate) fn new() -> Result<Rc<Instance>, RenderError> {
        // SAFETY: loading the system's Vulkan loader library; its
        // initialisation has no preconditions on this program.
        let entry =
            unsafe { ash::Entry::load() }.map_err(|e| RenderError::NoLoader(e.to_string()))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"micromap-index")
            .api_version(vk::make_api_version(0, 1, 2, 0));
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: `info` and `app` outlive the call.
        let raw = unsafe { entry.create_instance(&info, None) }.map_err(RenderError::NoInstance)?;
        Ok(Rc::new(Instance { _entry: entry, raw }))
    }

    /// The physical devices, in the loader's order.
    pub(crate) fn physical_devices(&self) -> Result<Vec<vk::PhysicalDevice>, RenderError> {
        // SAFETY: a valid instance.
        unsafe { self.raw.enumerate_physical_devices() }
            .map_err(failed("vkEnumeratePhysicalDevices"))
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: every device made from the instance holds an `Rc` of it,
        // so none is left when this runs.
        unsafe { self.raw.destroy_instance(None) };
    }
}
